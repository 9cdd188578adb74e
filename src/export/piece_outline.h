// Outline geometry of a flat pattern piece for the print and cut files: the cut line (the sew
// line offset outward by the seam allowance), where a notch meets it, and where the label goes.
// Polygons are closed, counter-clockwise, the last point not repeating the first, any unit.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace s2p {

using Polygon2 = std::vector<Eigen::Vector2d>;

// Mitred corners of a seam allowance reach at most this many allowances from the sew line; a
// sharper corner is bevelled to a point there (Boost's limited miter: right at the tip the cut
// line then passes up to 3 % closer than the allowance).
constexpr double kSeamMiterLimit = 4;

// True when the polygon has ≥ 3 finite points, a positive (counter-clockwise) area and no edge
// touching a non-adjacent one.
bool isSimplePolygon(const Polygon2& polygon);

// The polygon offset outward by `distance` ≥ 0 (Boost.Geometry's buffer): straight edges stay
// straight, convex corners are mitred up to miterLimit·distance, concave corners and concave
// curves tighter than the distance lose the loops a naive offset would make, a slot narrower
// than 2·distance is bridged. The result is a simple counter-clockwise polygon; new vertices
// (intersections) are exact to about 1e-8 of the polygon's size (Boost's robust rounding).
// Distance 0 returns the polygon unchanged. InputError when the polygon is not simple.
Polygon2 offsetOutline(const Polygon2& polygon, double distance,
                       double miterLimit = kSeamMiterLimit);

// The first point where the ray from `origin` along `direction` meets the polygon's boundary,
// or origin + reach·direction when it meets none within `reach`: where a notch on the sew line
// crosses the cut line.
Eigen::Vector2d rayToOutline(const Polygon2& polygon, const Eigen::Vector2d& origin,
                             const Eigen::Vector2d& direction, double reach);

// A point inside the polygon far from its boundary and from the given segments (e.g. the
// grainline), found on a grid: where a piece's label reads best.
struct LabelSpot {
  Eigen::Vector2d at = Eigen::Vector2d::Zero();
  double clearance = 0;  // distance to the nearest boundary edge or segment
};
LabelSpot labelSpot(const Polygon2& polygon,
                    const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& avoid = {});

}  // namespace s2p
