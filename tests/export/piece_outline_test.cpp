#include "export/piece_outline.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "pattern_fixtures.h"

namespace s2p {
namespace {

using test::Points;

Eigen::Vector2d lowCorner(const Points& p) {
  Eigen::Vector2d lo = p.front();
  for (const auto& q : p) lo = lo.cwiseMin(q);
  return lo;
}
Eigen::Vector2d highCorner(const Points& p) {
  Eigen::Vector2d hi = p.front();
  for (const auto& q : p) hi = hi.cwiseMax(q);
  return hi;
}

// The cut line simple and counter-clockwise, each of its vertices at least the allowance away
// from the sew line, and each sew vertex at least `tip`·allowance inside it (up to rounding).
void expectCleanOffset(const Points& sew, const Points& cut, double d, double tip = 1) {
  EXPECT_TRUE(test::noSelfIntersection(cut));
  EXPECT_GT(test::signedArea(cut), test::signedArea(sew));
  for (const auto& p : cut) EXPECT_GE(test::distanceToOutline(sew, p), d - 1e-8);
  for (const auto& p : sew) EXPECT_GE(test::distanceToOutline(cut, p), tip * d - 1e-8);
}

TEST(PieceOutline, ZeroAllowanceIsTheSewLine) {
  const Points sew = test::lShape();
  EXPECT_EQ(offsetOutline(sew, 0), sew);
}

TEST(PieceOutline, RectangleOf20By30cmWith1cmIs22By32cm) {
  const Points cut = offsetOutline(test::rectangle(0.2, 0.3), 0.01);
  const Eigen::Vector2d size = highCorner(cut) - lowCorner(cut);
  EXPECT_NEAR(size.x(), 0.22, 1e-12);
  EXPECT_NEAR(size.y(), 0.32, 1e-12);
  EXPECT_NEAR(lowCorner(cut).x(), -0.01, 1e-12);
  // Mitred corners: the cut line is the full 22 × 32 cm rectangle, not rounded, 4 corners.
  EXPECT_NEAR(test::signedArea(cut), 0.22 * 0.32, 1e-12);
  EXPECT_EQ(cut.size(), 4u);
}

TEST(PieceOutline, ConcaveLShapeGivesASimpleMitredOutline) {
  const Points sew = test::lShape();
  const double d = 0.01;
  const Points cut = offsetOutline(sew, d);
  expectCleanOffset(sew, cut, d);
  // Every edge shifted out by d: the (0.3 + 2d)² square minus the 0.2 m notch square.
  EXPECT_NEAR(test::signedArea(cut), std::pow(0.3 + 2 * d, 2) - 0.2 * 0.2, 1e-9);
  bool concaveCorner = false;  // the inner corner moves diagonally to (0.1 + d, 0.1 + d)
  for (const auto& p : cut) concaveCorner |= (p - Eigen::Vector2d(0.1 + d, 0.1 + d)).norm() < 1e-8;
  EXPECT_TRUE(concaveCorner);
}

TEST(PieceOutline, SlotNarrowerThanTwoAllowancesIsBridged) {
  // A U: a 1 cm wide, 10 cm deep slot from the top; a 1 cm allowance closes it.
  const Points sew{{0, 0},       {0.2, 0},     {0.2, 0.2},   {0.105, 0.2},
                   {0.105, 0.1}, {0.095, 0.1}, {0.095, 0.2}, {0, 0.2}};
  const Points cut = offsetOutline(sew, 0.01);
  expectCleanOffset(sew, cut, 0.01);
  // Nothing of the cut line dips into the slot.
  for (const auto& p : cut) {
    if (std::abs(p.x() - 0.1) < 0.02) {
      EXPECT_TRUE(p.y() > 0.21 - 1e-9 || p.y() < -0.01 + 1e-9);
    }
  }
}

TEST(PieceOutline, ConcaveCurveTighterThanTheAllowanceMakesNoLoop) {
  // A 10 × 10 cm square with a semicircular bite of radius 5 mm in its top edge, 1 mm chords.
  Points sew{{0, 0}, {0.1, 0}, {0.1, 0.1}};
  const double r = 0.005;
  for (int k = 0; k <= 16; ++k) {
    const double a = std::numbers::pi * k / 16;  // from the right end of the bite, under it
    sew.emplace_back(0.05 + r * std::cos(a), 0.1 - r * std::sin(a));
  }
  sew.emplace_back(0, 0.1);
  const Points cut = offsetOutline(sew, 0.01);
  expectCleanOffset(sew, cut, 0.01);
}

TEST(PieceOutline, SharpCornerIsCutAtTheMiterLimit) {
  // A 10° spike: its plain miter would reach d / sin(5°) ≈ 11.5 d.
  const double half = 5 * std::numbers::pi / 180;
  const Points sew{{0, 0}, {0.3, -0.3 * std::tan(half)}, {0.3, 0.3 * std::tan(half)}};
  const double d = 0.01;
  const Points cut = offsetOutline(sew, d);
  expectCleanOffset(sew, cut, d, 0.97);
  for (const auto& p : cut) EXPECT_LE(test::distanceToOutline(sew, p), kSeamMiterLimit * d + 1e-9);
}

TEST(PieceOutline, BadOutlinesAreInputErrors) {
  EXPECT_FALSE(isSimplePolygon({{0, 0}, {1, 0}}));
  const Points bowTie{{0, 0}, {1, 1}, {1, 0}, {0, 1}};
  EXPECT_FALSE(isSimplePolygon(bowTie));
  Points clockwise = test::rectangle(1, 1);
  std::reverse(clockwise.begin(), clockwise.end());
  EXPECT_FALSE(isSimplePolygon(clockwise));
  EXPECT_FALSE(isSimplePolygon({{0, 0}, {1, 0}, {NAN, 1}}));
  EXPECT_TRUE(isSimplePolygon(test::lShape()));
  EXPECT_THROW(offsetOutline(bowTie, 0.01), InputError);
  EXPECT_THROW(offsetOutline(test::lShape(), -0.01), InputError);
}

TEST(PieceOutline, RayFromTheSewLineMeetsTheCutLine) {
  const Points cut = offsetOutline(test::rectangle(0.2, 0.3), 0.01);
  const Eigen::Vector2d hit = rayToOutline(cut, {0.1, 0.3}, {0, 1}, 0.04);
  EXPECT_NEAR(hit.x(), 0.1, 1e-12);
  EXPECT_NEAR(hit.y(), 0.31, 1e-12);
  // On the outline itself (no allowance) the ray stops where it starts.
  const Eigen::Vector2d self = rayToOutline(test::rectangle(0.2, 0.3), {0.2, 0.15}, {1, 0}, 0);
  EXPECT_NEAR((self - Eigen::Vector2d(0.2, 0.15)).norm(), 0, 1e-12);
}

TEST(PieceOutline, LabelSpotIsInsideAndClearOfTheGrainline) {
  const Points l = test::lShape();
  const LabelSpot spot = labelSpot(l);
  // The largest circle in the L touches its outer edges x = 0, y = 0 and the concave corner:
  // radius c with c = √2 (0.1 − c).
  const double c = 0.1 * std::sqrt(2.0) / (1 + std::sqrt(2.0));
  EXPECT_LE(spot.clearance, c + 1e-12);
  EXPECT_GT(spot.clearance, c - 0.001);
  EXPECT_NEAR(test::distanceToOutline(l, spot.at), spot.clearance, 1e-12);
  const Points square = test::rectangle(0.2, 0.2);
  const LabelSpot clear = labelSpot(square, {{{0.1, 0.02}, {0.1, 0.18}}});
  EXPECT_GT(std::abs(clear.at.x() - 0.1), 0.03);
}

}  // namespace
}  // namespace s2p
