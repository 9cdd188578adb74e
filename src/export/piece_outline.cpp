#include "export/piece_outline.h"

#include <algorithm>
#include <boost/geometry.hpp>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace s2p {
namespace {

namespace bg = boost::geometry;
using BPoint = bg::model::d2::point_xy<double>;
using BPolygon = bg::model::polygon<BPoint, /*ClockWise=*/false, /*Closed=*/true>;
using BMultiPolygon = bg::model::multi_polygon<BPolygon>;

BPolygon toBoost(const Polygon2& polygon) {
  BPolygon out;
  for (const Eigen::Vector2d& p : polygon) out.outer().emplace_back(p.x(), p.y());
  if (!polygon.empty()) out.outer().emplace_back(polygon.front().x(), polygon.front().y());
  return out;
}

double distanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Even-odd crossing test.
bool inside(const Polygon2& polygon, const Eigen::Vector2d& p) {
  bool in = false;
  for (size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      in = !in;
  }
  return in;
}

// Without the vertices that lie on the straight line through their neighbours (the buffer keeps
// the offset of every input vertex, also beside a mitred corner).
Polygon2 withoutCollinear(const Polygon2& polygon) {
  Polygon2 out;
  const size_t n = polygon.size();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d a = polygon[(i + n - 1) % n] - polygon[i];
    const Eigen::Vector2d b = polygon[(i + 1) % n] - polygon[i];
    const double cross = a.x() * b.y() - a.y() * b.x();
    if (std::abs(cross) > 1e-12 * a.norm() * b.norm() || a.dot(b) > 0) out.push_back(polygon[i]);
  }
  return out;
}

}  // namespace

bool isSimplePolygon(const Polygon2& polygon) {
  if (polygon.size() < 3) return false;
  for (const Eigen::Vector2d& p : polygon)
    if (!p.allFinite()) return false;
  const BPolygon b = toBoost(polygon);
  return bg::is_valid(b) && bg::area(b) > 0;
}

Polygon2 offsetOutline(const Polygon2& polygon, double distance, double miterLimit) {
  if (!(distance >= 0) || !std::isfinite(distance))
    throw InputError("offsetOutline: the offset distance must be finite and ≥ 0, got " +
                     std::to_string(distance));
  if (!isSimplePolygon(polygon))
    throw InputError("offsetOutline: the outline (" + std::to_string(polygon.size()) +
                     " points) is not a simple counter-clockwise polygon");
  if (distance == 0) return polygon;

  namespace strategy = bg::strategy::buffer;
  BMultiPolygon out;
  bg::buffer(toBoost(polygon), out, strategy::distance_symmetric<double>(distance),
             strategy::side_straight(), strategy::join_miter(miterLimit), strategy::end_flat(),
             strategy::point_square());
  // An outward offset of one simple polygon is one polygon; its holes (slots bridged over) are
  // not cut.
  const auto largest = std::max_element(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return bg::area(a) < bg::area(b);
  });
  if (largest == out.end())
    throw InputError("offsetOutline: the offset of the outline by " + std::to_string(distance) +
                     " is empty");
  Polygon2 result;
  for (const BPoint& p : largest->outer()) result.emplace_back(p.x(), p.y());
  result.pop_back();  // the closing point
  return withoutCollinear(result);
}

Eigen::Vector2d rayToOutline(const Polygon2& polygon, const Eigen::Vector2d& origin,
                             const Eigen::Vector2d& direction, double reach) {
  // A hit this little behind the origin still counts: an origin on the boundary hits itself.
  const double slack = 1e-9 * std::max(reach, 1e-9);
  double best = reach;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d a = polygon[i];
    const Eigen::Vector2d e = polygon[(i + 1) % polygon.size()] - a;
    // origin + t·direction = a + s·e
    const double det = e.x() * direction.y() - e.y() * direction.x();
    if (std::abs(det) < 1e-300) continue;
    const Eigen::Vector2d r = a - origin;
    const double t = (e.x() * r.y() - e.y() * r.x()) / det;
    const double s = (direction.x() * r.y() - direction.y() * r.x()) / det;
    if (t >= -slack && t < best && s >= 0 && s <= 1) best = t;
  }
  return origin + best * direction;
}

LabelSpot labelSpot(const Polygon2& polygon,
                    const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& avoid) {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector2d hi = -lo;
  for (const Eigen::Vector2d& p : polygon) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const auto clearance = [&](const Eigen::Vector2d& p) {
    double d = std::numeric_limits<double>::max();
    for (size_t i = 0; i < polygon.size(); ++i)
      d = std::min(d, distanceToSegment(p, polygon[i], polygon[(i + 1) % polygon.size()]));
    for (const auto& [a, b] : avoid) d = std::min(d, distanceToSegment(p, a, b));
    return d;
  };
  // A coarse grid over the bounding box, then a finer one around the best coarse cell.
  constexpr int kSteps = 32;
  LabelSpot best{0.5 * (lo + hi), -1};
  Eigen::Vector2d from = lo, cell = (hi - lo) / kSteps;
  for (int pass = 0; pass < 2; ++pass) {
    for (int i = 0; i <= kSteps; ++i)
      for (int j = 0; j <= kSteps; ++j) {
        const Eigen::Vector2d p = from + Eigen::Vector2d(i * cell.x(), j * cell.y());
        if (!inside(polygon, p)) continue;
        const double d = clearance(p);
        if (d > best.clearance) best = {p, d};
      }
    from = best.at - cell;
    cell *= 2.0 / kSteps;
  }
  if (best.clearance < 0) best.clearance = 0;  // no grid point inside: a sliver of a piece
  return best;
}

}  // namespace s2p
