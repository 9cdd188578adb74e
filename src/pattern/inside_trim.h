// A garment's inside seen through one of its openings. A scanner's low cameras look up under a
// skirt's hem (or into a wide sleeve) and see the cloth's inner face; the scan joins it to the
// outer face at the rim, so the cut garment is the outer surface with a band of its own inside
// folded in below the hem (f2, ../shared/testscans: 0.13 m² of its skirt, up to 15 cm deep).
// Flattened with the rest, that band unfolds below the hem as flaps. It is the same cloth seen
// twice: the pattern keeps the outer face and the rim where the two meet is the hem.
#pragma once

#include <Eigen/Core>
#include <optional>

#include "core/tri_mesh.h"

namespace s2p {

struct InsideTrimOptions {
  // A face is turned to the body when its normal and the body's normal at the nearest body point
  // meet at more than acos(−facingCos) (90°): the inner face of a skirt over the thigh (180°),
  // and between the legs, where the nearest body point is an inner thigh (about 90°; at 120°
  // f2 kept a tongue of 7 cm there).
  double facingCos = 0.0;
  // m²: less than this, taken together, is noise of the rim (a few folded triangles), kept.
  double minArea = 0.002;
};

struct InsideTrim {
  TriMesh mesh;                // the garment without its inside
  Eigen::VectorXi faceOrigin;  // #F of mesh: the input's faceOrigin of each kept face
  int removedFaces = 0;
  double removedArea = 0;  // m², the inside and any piece it alone held on
};

// The faces of `garment` turned to `body` (options.facingCos) that reach the garment's border
// through faces turned to the body, removed with the pieces only they joined to the rest (the
// largest piece is kept). nullopt when they are less than options.minArea, or when the garment
// without them is not a manifold (then it is left whole). faceOrigin: #F of garment. Throws
// InputError for an empty body or sizes that differ.
std::optional<InsideTrim> trimInsideSeenThroughOpenings(const TriMesh& garment,
                                                        const Eigen::VectorXi& faceOrigin,
                                                        const TriMesh& body,
                                                        const InsideTrimOptions& options = {});

}  // namespace s2p
