// A disk over a closed loop of points in 3D: the cloth a scan did not show inside a hole or a
// contact, as a surface that meets the loop exactly. The loop is projected onto its best-fit
// plane, the polygon is meshed there by remeshPanel (constrained Delaunay, ≥ 20.7°, no point
// added on the loop) and each inner vertex is lifted off the plane by the harmonic interpolation
// of the loop's heights (a membrane: flat where the loop is flat, no bulge of its own).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

namespace s2p {

struct LoopFill {
  // 3D; the first outline.size() rows are the loop's points, exactly and in order, the inner
  // vertices follow.
  Eigen::MatrixX3d V;
  Eigen::MatrixX3i F;    // counter-clockwise seen along `normal`
  Eigen::VectorXd bump;  // #V: 0 on the loop, 1 at the patch's middle (Δb = −1, normalised)
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // of the best-fit plane
};

// outline: at least 3 points, a closed polygon (the last joins the first). spacing: the mesh's
// edge length inside (m). nullopt, with the reason in `why` when given, when the loop does not
// project onto its plane as a simple polygon or repeats a point.
std::optional<LoopFill> fillLoop(const std::vector<Eigen::Vector3d>& outline, double spacing,
                                 std::string* why = nullptr);

}  // namespace s2p
