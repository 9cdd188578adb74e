#include "segment/hem_plane.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace s2p {

std::optional<FittedPlane> trimmedCurvePlane(const Isoline& curve, double outliers) {
  if (!(outliers >= 0 && outliers < 1))
    throw InputError("hem plane: the outlier fraction must lie in [0, 1)");
  std::vector<Eigen::Vector3d> points;
  for (const IsolineCurve& c : curve.curves)
    for (const IsolinePoint& p : c.points) points.push_back(p.position);
  if (points.size() < 8) return std::nullopt;
  // Least trimmed squares by concentration steps: fit, keep the closest (1 − outliers) of the
  // points to that plane, refit, until the kept set stops changing. A bay's walls can hold a
  // third of the points; one trimming from the plain fit (tilted toward the bay) keeps them.
  const auto keep = std::max<size_t>(
      3, static_cast<size_t>(std::ceil((1 - outliers) * static_cast<double>(points.size()))));
  FittedPlane plane = fitPlane(points);
  std::vector<size_t> kept;
  for (int step = 0; step < 20 && keep < points.size(); ++step) {
    std::vector<std::pair<double, size_t>> d;
    for (size_t i = 0; i < points.size(); ++i)
      d.emplace_back(std::abs((points[i] - plane.centre).dot(plane.normal())), i);
    std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(keep - 1), d.end());
    std::vector<size_t> next;
    for (size_t i = 0; i < keep; ++i) next.push_back(d[i].second);
    std::sort(next.begin(), next.end());
    if (next == kept) break;
    kept = std::move(next);
    std::vector<Eigen::Vector3d> inliers;
    for (const size_t i : kept) inliers.push_back(points[i]);
    plane = fitPlane(inliers);
  }
  return plane;
}

Eigen::VectorXd planeDisplacement(const TriMesh& mesh, const FittedPlane& plane,
                                  const Eigen::Vector3d& positiveSide, double band) {
  if (!(band > 0) || !std::isfinite(band))
    throw InputError("hem plane: the band must be a positive number of metres");
  const Eigen::Vector3d n = plane.normal();
  const double side = (positiveSide - plane.centre).dot(n) >= 0 ? 1.0 : -1.0;
  Eigen::VectorXd out(mesh.numVertices());
  for (int v = 0; v < mesh.numVertices(); ++v)
    out[v] = std::clamp(side * (mesh.V.row(v).transpose() - plane.centre).dot(n) / band, -1.0, 1.0);
  return out;
}

}  // namespace s2p
