// Small sewing patterns built in code for the print and cut file tests, and a simple-polygon
// check that does not share code with the writers.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "export/sewing_pattern.h"

namespace s2p::test {

using Points = std::vector<Eigen::Vector2d>;

// Counter-clockwise w × h rectangle (m) with its lower-left corner at the origin.
inline Points rectangle(double w, double h) {
  return {{0, 0}, {w, 0}, {w, h}, {0, h}};
}

// An L: the 0.3 m square minus its upper-right 0.2 m square, so one concave corner at (0.1, 0.1).
inline Points lShape() {
  return {{0, 0}, {0.3, 0}, {0.3, 0.1}, {0.1, 0.1}, {0.1, 0.3}, {0, 0.3}};
}

// A rectangle piece with a notch at the middle of every edge, a vertical grainline and one
// internal line (a dart leg).
inline SewingPiece rectanglePiece(const std::string& name, double w, double h) {
  SewingPiece piece;
  piece.name = name;
  piece.garment = "tshirt";
  piece.sewLine = rectangle(w, h);
  piece.corners = {0, 1, 2, 3};
  piece.notches = {
      {{w / 2, 0}, {0, -1}}, {{w, h / 2}, {1, 0}}, {{w / 2, h}, {0, 1}}, {{0, h / 2}, {-1, 0}}};
  piece.grainFrom = {w / 2, 0.2 * h};
  piece.grainTo = {w / 2, 0.8 * h};
  piece.internalLines = {{{0.3 * w, h}, {0.4 * w, 0.7 * h}, {0.5 * w, h}}};
  return piece;
}

// A 20 × 30 cm front (cut 1) and an L-shaped sleeve (cut 2, mirrored).
inline SewingPattern twoPiecePattern() {
  SewingPattern pattern;
  pattern.styleName = "test style";
  pattern.creationDate = "2026-12-01";
  pattern.sampleSize = "M";
  pattern.pieces.push_back(rectanglePiece("front", 0.2, 0.3));
  SewingPiece sleeve;
  sleeve.name = "left_sleeve";
  sleeve.garment = "tshirt";
  sleeve.quantity = 2;
  sleeve.mirrored = true;
  sleeve.sewLine = lShape();
  sleeve.notches = {{{0.2, 0}, {0, -1}}, {{0.05, 0.3}, {0, 1}}};
  sleeve.grainFrom = {0.05, 0.05};
  sleeve.grainTo = {0.05, 0.25};
  pattern.pieces.push_back(sleeve);
  return pattern;
}

// Whether segments ab and cd share a point (collinear overlaps included).
inline bool segmentsMeet(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                         const Eigen::Vector2d& c, const Eigen::Vector2d& d) {
  const auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& p,
                        const Eigen::Vector2d& q) {
    const double v = (p - o).x() * (q - o).y() - (p - o).y() * (q - o).x();
    return std::abs(v) < 1e-15 ? 0 : (v > 0 ? 1 : -1);
  };
  const auto within = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q,
                         const Eigen::Vector2d& r) {  // r on the box of pq
    return r.x() >= std::min(p.x(), q.x()) - 1e-15 && r.x() <= std::max(p.x(), q.x()) + 1e-15 &&
           r.y() >= std::min(p.y(), q.y()) - 1e-15 && r.y() <= std::max(p.y(), q.y()) + 1e-15;
  };
  const int d1 = cross(c, d, a), d2 = cross(c, d, b), d3 = cross(a, b, c), d4 = cross(a, b, d);
  if (d1 * d2 < 0 && d3 * d4 < 0) return true;
  return (d1 == 0 && within(c, d, a)) || (d2 == 0 && within(c, d, b)) ||
         (d3 == 0 && within(a, b, c)) || (d4 == 0 && within(a, b, d));
}

// No two non-adjacent edges of the closed polygon meet, and no edge has zero length.
inline bool noSelfIntersection(const Points& polygon) {
  const size_t n = polygon.size();
  for (size_t i = 0; i < n; ++i) {
    if ((polygon[(i + 1) % n] - polygon[i]).norm() < 1e-12) return false;
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the closing edge
      if (segmentsMeet(polygon[i], polygon[(i + 1) % n], polygon[j], polygon[(j + 1) % n]))
        return false;
    }
  }
  return true;
}

inline double signedArea(const Points& polygon) {
  double a = 0;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& p = polygon[i];
    const Eigen::Vector2d& q = polygon[(i + 1) % polygon.size()];
    a += p.x() * q.y() - p.y() * q.x();
  }
  return 0.5 * a;
}

// Distance from p to the closed polygon's boundary.
inline double distanceToOutline(const Points& polygon, const Eigen::Vector2d& p) {
  double best = 1e300;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d a = polygon[i], ab = polygon[(i + 1) % polygon.size()] - a;
    const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (a + t * ab - p).norm());
  }
  return best;
}

}  // namespace s2p::test
