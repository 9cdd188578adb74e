// Where colour cannot push a boundary either way, the plane its curve runs round the body in.
// A garment's hem (the waist boundary B(U|L), §5.3) runs round the body in about one plane.
// Where both garments hold a colour (a jersey's white stripes over white shorts) the colour
// displacement is zero and the front moves by its regulariser alone; it can stall in a band of
// that colour and leave a bay of one garment in the other (glb_footballer: 9 cm high at one hip).
// The plane of the rest of the curve tells those vertices which side they are on.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/tri_mesh.h"
#include "segment/isoline.h"

namespace s2p {

// The least-squares plane of the curve's points without the `outliers` fraction farthest from it
// (a bay's points): least trimmed squares by concentration steps from the plain fit. nullopt for
// fewer than 8 points. 0.4 by default: a bay's two walls and its top can hold a third of the
// points (a 10 cm bay over a sixth of a 94 cm waist); 60 % of a loop still spans it.
std::optional<FittedPlane> trimmedCurvePlane(const Isoline& curve, double outliers = 0.4);

// +1 on the side of `plane` that holds `positiveSide` (a point of the boundary's positive
// garment, e.g. the mean of its region points) and −1 on the other, from `band` metres off the
// plane, linear between. #V of `mesh`.
Eigen::VectorXd planeDisplacement(const TriMesh& mesh, const FittedPlane& plane,
                                  const Eigen::Vector3d& positiveSide, double band = 0.02);

}  // namespace s2p
