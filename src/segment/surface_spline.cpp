#include "segment/surface_spline.h"

#include <cmath>

#include "core/error.h"

namespace s2p {
namespace {

using Vec3 = Eigen::Vector3d;

// Centripetal Catmull-Rom segment from p1 to p2 (Barry–Goldman pyramidal form), u in [0, 1].
Vec3 catmullRom(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& p3, double u) {
  auto knot = [](double t, const Vec3& a, const Vec3& b) {
    return t + std::max(std::sqrt((b - a).norm()), 1e-12);
  };
  const double t0 = 0, t1 = knot(t0, p0, p1), t2 = knot(t1, p1, p2), t3 = knot(t2, p2, p3);
  const double t = t1 + u * (t2 - t1);
  auto lerp = [t](const Vec3& a, const Vec3& b, double ta, double tb) {
    return ((tb - t) * a + (t - ta) * b) / (tb - ta);
  };
  const Vec3 a1 = lerp(p0, p1, t0, t1), a2 = lerp(p1, p2, t1, t2), a3 = lerp(p2, p3, t2, t3);
  const Vec3 b1 = lerp(a1, a2, t0, t2), b2 = lerp(a2, a3, t1, t3);
  return lerp(b1, b2, t1, t2);
}

std::vector<Vec3> distinctAnchors(const Eigen::MatrixX3d& anchors, bool closed) {
  if (!anchors.allFinite()) throw InputError("surface spline: an anchor is not finite");
  std::vector<Vec3> a;
  for (Eigen::Index i = 0; i < anchors.rows(); ++i) {
    const Vec3 p = anchors.row(i).transpose();
    if (a.empty() || (p - a.back()).norm() > 1e-9) a.push_back(p);
  }
  if (closed && a.size() > 1 && (a.front() - a.back()).norm() <= 1e-9) a.pop_back();
  const size_t need = closed ? 3 : 2;
  if (a.size() < need)
    throw InputError("surface spline: " + std::to_string(a.size()) + " distinct anchor(s) left; a " +
                     (closed ? "closed" : "open") + " curve needs at least " +
                     std::to_string(need));
  return a;
}

}  // namespace

Eigen::MatrixX3d catmullRomSamples(const Eigen::MatrixX3d& anchors, bool closed, double spacing) {
  if (!(spacing > 0)) throw InputError("surface spline: the sample spacing must be positive");
  const std::vector<Vec3> a = distinctAnchors(anchors, closed);
  const int n = static_cast<int>(a.size());
  auto at = [&](int i) -> const Vec3& {
    if (closed) return a[((i % n) + n) % n];
    return a[std::clamp(i, 0, n - 1)];
  };
  // Open ends: phantom points mirrored through the end anchors.
  auto point = [&](int i) -> Vec3 {
    if (closed || (i >= 0 && i < n)) return at(i);
    return i < 0 ? Vec3(2 * a[0] - a[1]) : Vec3(2 * a[n - 1] - a[n - 2]);
  };
  std::vector<Vec3> out;
  const int segments = closed ? n : n - 1;
  for (int s = 0; s < segments; ++s) {
    const Vec3 p0 = point(s - 1), p1 = point(s), p2 = point(s + 1), p3 = point(s + 2);
    const int steps = std::max(1, static_cast<int>(std::ceil((p2 - p1).norm() / spacing)));
    for (int k = 0; k < steps; ++k) out.push_back(catmullRom(p0, p1, p2, p3, double(k) / steps));
  }
  if (!closed) out.push_back(a.back());
  Eigen::MatrixX3d P(static_cast<int>(out.size()), 3);
  for (size_t i = 0; i < out.size(); ++i) P.row(static_cast<int>(i)) = out[i].transpose();
  return P;
}

std::vector<SurfacePoint> surfaceSpline(const MeshQuery& query, const Eigen::MatrixX3d& anchors,
                                        bool closed, double spacing) {
  const Eigen::MatrixX3d samples = catmullRomSamples(anchors, closed, spacing);
  const std::vector<ClosestHit> hits = query.closestPoints(samples);
  std::vector<SurfacePoint> curve;
  curve.reserve(hits.size());
  for (const ClosestHit& h : hits) curve.push_back({h.face, h.bary});
  return curve;
}

}  // namespace s2p
