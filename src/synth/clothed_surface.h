// The geometry of a synthetic scan: body, garments, shoes, hair and bag fused into ONE closed
// surface through level sets (OpenVDB), as a scanner's reconstruction does, with the true label
// of every vertex and face and the true boundary curves between labels.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "body/body_model.h"
#include "core/progress.h"
#include "core/tri_mesh.h"
#include "synth/outfit.h"
#include "synth/truth.h"

namespace s2p {

struct GeometryOptions {
  double voxelSize = 0.004;    // metres, level-set resolution (hem steps need ≤ ease / 2)
  int targetVertices = 50000;  // decimate to about this many vertices (0: keep the level-set
                               // mesh); meshoptimizer, vertices stay on the surface
  double noise = 0;            // metres, σ of positional noise along the normal
  int holes = 0;               // holes cut where scanners miss (armpits, crotch, soles, crown)
  double holeRadius = 0.03;    // metres
  std::uint64_t seed = 1;
};

// What the generator did (for reports and benchmarks).
struct GeometryStats {
  long activeVoxels = 0;        // voxels of the union level set
  int levelSetVertices = 0;     // vertices of the level-set mesh before decimation
  int removedComponents = 0;    // floating level-set pieces dropped (normally 0)
  int holes = 0;                // holes actually cut
  double secondsBody = 0, secondsUnion = 0, secondsLabels = 0, secondsDecimate = 0,
         secondsBoundaries = 0, secondsCorrupt = 0;  // wall time per stage
};

struct ClothedSurface {
  TriMesh mesh;                  // closed, manifold, one component (unless holes were asked)
  Eigen::VectorXi vertexLabel;   // #V Label codes
  Eigen::VectorXi faceLabel;     // #F Label codes (at the face centroid)
  Eigen::VectorXi faceLayer;     // #F index into outfit.garments of the layer that shows, −1 = skin
  Eigen::VectorXi vertexLayer;   // #V likewise
  Eigen::MatrixX3d restPosition; // #V the rest-pose body point under each vertex (solid-texture
                                 // coordinates that follow the body through any pose)
  std::vector<TrueGarment> garments;     // one per outfit garment: label, one-piece, occlusion,
                                         // visible area
  std::vector<TrueBoundary> boundaries;  // curves between every pair of adjacent labels; under
                                         // a free-hanging hem the rim is reported as the
                                         // garment|skin boundary and Gap|skin where the cap
                                         // meets the legs
  GeometryStats stats;
};

// Builds the clothed surface of `model` posed by `params`. Deterministic for a given seed.
// Throws InputError on an outfit it cannot build (two garments with one name, say).
ClothedSurface makeClothedSurface(const BodyModel& model, const BodyParams& params,
                                  const Outfit& outfit, const GeometryOptions& options,
                                  Progress& progress = Progress::silent());

}  // namespace s2p
