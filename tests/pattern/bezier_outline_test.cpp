#include "pattern/bezier_outline.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>

#include "core/error.h"

namespace s2p {
namespace {

constexpr double kPi = std::numbers::pi;

// n samples of a circular arc of the given radius and angle, centred at the origin.
Eigen::MatrixX2d arc(int n, double radius, double angle, double start = 0.0) {
  Eigen::MatrixX2d p(n, 2);
  for (int i = 0; i < n; ++i) {
    const double a = start + angle * i / (n - 1);
    p.row(i) << radius * std::cos(a), radius * std::sin(a);
  }
  return p;
}

// Largest distance of dense chain samples from the exact circle.
double circleError(const BezierChain& chain, double radius) {
  double worst = 0.0;
  for (const CubicBezier& b : chain.segments)
    for (int k = 0; k <= 200; ++k)
      worst = std::max(worst, std::abs(b.point(k / 200.0).norm() - radius));
  return worst;
}

void expectG1(const BezierChain& chain) {
  for (int i = 0; i + 1 < chain.size(); ++i) {
    const Eigen::Vector2d in = (chain.segments[i].p[3] - chain.segments[i].p[2]).normalized();
    const Eigen::Vector2d out =
        (chain.segments[i + 1].p[1] - chain.segments[i + 1].p[0]).normalized();
    EXPECT_EQ(chain.segments[i].p[3], chain.segments[i + 1].p[0]);  // C0, exactly
    EXPECT_LT(std::abs(in.x() * out.y() - in.y() * out.x()), 1e-6) << "joint " << i;
    EXPECT_GT(in.dot(out), 0.0) << "joint " << i;
  }
}

TEST(BezierOutline, CircularArcWithinATenthOfAMillimetre) {
  // Radius 0.3 m, 120°, 200 samples; a tight tolerance of 0.05 mm.
  const Eigen::MatrixX2d p = arc(200, 0.3, 2.0 * kPi / 3.0);
  const BezierChain chain = fitBezierChain(p, {.tolerance = 5e-5});
  const double dev = maxDeviation(chain, p), circ = circleError(chain, 0.3);
  std::cout << "arc 120° r 0.3 m, tolerance 0.05 mm: " << chain.size()
            << " segments, deviation from the polyline " << dev * 1e3 << " mm, from the circle "
            << circ * 1e3 << " mm\n";
  EXPECT_LT(dev, 1e-4);
  EXPECT_LT(circ, 1e-4);
  EXPECT_LE(chain.size(), 2);  // a cubic holds 60° of a circle to ~2.4e-5·r = 7 µm
  expectG1(chain);
  // End points exact.
  EXPECT_EQ(chain.segments.front().p[0], Eigen::Vector2d(p.row(0)));
  EXPECT_EQ(chain.segments.back().p[3], Eigen::Vector2d(p.row(p.rows() - 1)));
  // Arc length ≈ the circle's 0.2π (within the fit's error).
  EXPECT_NEAR(chain.length(), 0.3 * 2.0 * kPi / 3.0, 1e-4);
}

TEST(BezierOutline, DefaultToleranceUsesFewSegments) {
  // At 1 mm a 120° arc of 0.3 m needs one segment (a cubic's error there is ~0.3 mm), a whole
  // circle of 0.3 m a few.
  const Eigen::MatrixX2d p = arc(100, 0.3, 2.0 * kPi / 3.0);
  const BezierChain chain = fitBezierChain(p);
  EXPECT_EQ(chain.size(), 1);
  EXPECT_LT(maxDeviation(chain, p), 1e-3);
  const Eigen::MatrixX2d circle = arc(400, 0.3, 2.0 * kPi * 399.0 / 400.0);
  const BezierChain full = fitBezierChain(circle);
  std::cout << "circle r 0.3 m at 1 mm: " << full.size() << " segments\n";
  EXPECT_LE(full.size(), 3);  // 120° each: ~0.45 mm
  EXPECT_LT(maxDeviation(full, circle), 1e-3);
  expectG1(full);
}

TEST(BezierOutline, StraightLineIsOneSegment) {
  Eigen::MatrixX2d p(50, 2);
  for (int i = 0; i < 50; ++i) p.row(i) << 0.1 + 0.01 * i, 0.2 - 0.004 * i;
  const BezierChain chain = fitBezierChain(p, {.tolerance = 1e-6});
  EXPECT_EQ(chain.size(), 1);
  EXPECT_LT(maxDeviation(chain, p), 1e-12);
  // Two points are one straight segment too.
  const BezierChain two = fitBezierChain(p.topRows(2).eval());
  EXPECT_EQ(two.size(), 1);
  EXPECT_NEAR(two.length(), (p.row(1) - p.row(0)).norm(), 1e-15);
}

TEST(BezierOutline, NoisyWigglyEdgeIsWithinToleranceAndG1) {
  // A sine edge with ±0.3 mm jitter (a flattened mesh boundary), tolerance 1 mm.
  const int n = 300;
  Eigen::MatrixX2d p(n, 2);
  for (int i = 0; i < n; ++i) {
    const double x = 0.6 * i / (n - 1);
    const double jitter = 3e-4 * std::sin(12345.678 * i * i);
    p.row(i) << x, 0.05 * std::sin(2.0 * kPi * x / 0.3) + jitter;
  }
  const BezierChain chain = fitBezierChain(p);
  const double dev = maxDeviation(chain, p);
  std::cout << "sine edge with 0.3 mm jitter at 1 mm: " << chain.size() << " segments, deviation "
            << dev * 1e3 << " mm\n";
  EXPECT_LT(dev, 1e-3);
  EXPECT_LE(chain.size(), 8);
  expectG1(chain);
}

// Arc length along the chain of a point on it: a dense polyline of the chain (20000 samples a
// segment; chord error ~1e-12 m) and the projection onto its nearest piece.
class ChainArcLength {
 public:
  explicit ChainArcLength(const BezierChain& chain) {
    for (const CubicBezier& b : chain.segments)
      for (int k = pts_.empty() ? 0 : 1; k <= 20000; ++k) {
        const Eigen::Vector2d p = b.point(k / 20000.0);
        cum_.push_back(pts_.empty() ? 0.0 : cum_.back() + (p - pts_.back()).norm());
        pts_.push_back(p);
      }
  }
  double operator()(const Eigen::Vector2d& q) const {
    double bestD = 1e300, bestS = 0.0;
    for (size_t i = 0; i + 1 < pts_.size(); ++i) {
      const Eigen::Vector2d ab = pts_[i + 1] - pts_[i];
      const double t = std::clamp((q - pts_[i]).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      const double d = (pts_[i] + t * ab - q).squaredNorm();
      if (d < bestD) bestD = d, bestS = cum_[i] + t * ab.norm();
    }
    return bestS;
  }
  double total() const { return cum_.back(); }

 private:
  std::vector<Eigen::Vector2d> pts_;
  std::vector<double> cum_;
};

// A segment whose arm reaches past its chord's far end runs past its end point and turns back
// onto it: a hook narrower than the tolerance, invisible to the error test, that made a
// neckline's sew line cross itself at its corner (sleeveless_knee_skirt at 9,000 vertices). On
// jittered arcs that end in a short turn (a corner's last boundary vertices), every segment whose
// end tangents face along its chord has its inner control points within the chord: it advances
// monotonically along it (without the bound, two of the 563 reach past it).
TEST(BezierOutline, NoSegmentRunsPastTheEndOfItsChord) {
  int segments = 0;
  for (int c = 0; c < 200; ++c) {
    const int n = 20 + c % 40;
    const double radius = 0.05 + 0.002 * c, angle = 0.3 + 0.01 * c;
    Eigen::MatrixX2d p = arc(n, radius, angle);
    for (int i = 1; i + 1 < n; ++i)
      p.row(i) += 4e-4 * Eigen::RowVector2d(std::sin(97.1 * c + 12345.678 * i * i),
                                            std::cos(31.7 * c + 5432.1 * i));
    // The last vertex turned off the arc by up to ±60°, 1–4 mm from the one before.
    const Eigen::RowVector2d d = p.row(n - 2) - p.row(n - 3);
    const double turn = std::sin(7.3 * c) * kPi / 3, step = 1e-3 * (1 + 3 * (c % 4) / 3.0);
    const Eigen::RowVector2d u = d.normalized();
    p.row(n - 1) =
        p.row(n - 2) + step * Eigen::RowVector2d(std::cos(turn) * u.x() - std::sin(turn) * u.y(),
                                                 std::sin(turn) * u.x() + std::cos(turn) * u.y());
    const BezierChain chain = fitBezierChain(p);
    for (const CubicBezier& b : chain.segments) {
      const Eigen::Vector2d chord = b.p[3] - b.p[0];
      const double length = chord.norm();
      // Where an end tangent of the data itself turns back from the chord (the 60° turn at the
      // last vertex), no segment along it can advance monotonically; those are not asked.
      if ((b.p[1] - b.p[0]).dot(chord) < 0 || (b.p[2] - b.p[3]).dot(chord) > 0) continue;
      for (int k : {1, 2}) {
        const double x = (b.p[k] - b.p[0]).dot(chord) / length;
        EXPECT_GE(x, -1e-12 * length) << "case " << c << ", control point " << k;
        EXPECT_LE(x, length * (1 + 1e-12)) << "case " << c << ", control point " << k;
      }
      ++segments;
    }
  }
  std::cout << segments << " segments\n";
}

TEST(BezierOutline, ResampleHasExactCountEndsAndEqualSpacing) {
  const Eigen::MatrixX2d circle = arc(400, 0.3, 2.0 * kPi * 0.9);
  const BezierChain chain = fitBezierChain(circle, {.tolerance = 1e-5});
  ASSERT_GT(chain.size(), 1);
  const ChainArcLength arcLength(chain);
  EXPECT_NEAR(chain.length(), arcLength.total(), 1e-9);
  for (int count : {2, 3, 17, 101}) {
    const Eigen::MatrixX2d q = resampleChain(chain, count);
    ASSERT_EQ(q.rows(), count);
    EXPECT_EQ(Eigen::Vector2d(q.row(0)), chain.segments.front().p[0]);
    EXPECT_EQ(Eigen::Vector2d(q.row(count - 1)), chain.segments.back().p[3]);
    for (int i = 1; i + 1 < count; ++i)
      EXPECT_NEAR(arcLength(q.row(i).transpose()), chain.length() * i / (count - 1), 1e-9)
          << count << " " << i;
  }
}

TEST(BezierOutline, FitOutlineKeepsCornersSharp) {
  // A square of side 0.2 sampled every 1 cm; corners at 0, 20, 40, 60.
  Eigen::MatrixX2d sq(80, 2);
  for (int i = 0; i < 20; ++i) {
    const double t = 0.01 * i;
    sq.row(i) << t, 0;
    sq.row(20 + i) << 0.2, t;
    sq.row(40 + i) << 0.2 - t, 0.2;
    sq.row(60 + i) << 0, 0.2 - t;
  }
  const std::vector<BezierChain> edges = fitOutline(sq, {0, 20, 40, 60});
  ASSERT_EQ(edges.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(edges[k].size(), 1);
    EXPECT_NEAR(edges[k].length(), 0.2, 1e-12);
    // Each edge ends where the next begins, at the corner.
    EXPECT_EQ(edges[k].segments.back().p[3], edges[(k + 1) % 4].segments.front().p[0]);
  }
  EXPECT_THROW(fitOutline(sq, {}), InputError);
  EXPECT_THROW(fitOutline(sq, {20, 10}), InputError);
  EXPECT_THROW(fitBezierChain(Eigen::MatrixX2d::Zero(3, 2)), InputError);
  EXPECT_THROW(fitBezierChain(sq, {.tolerance = 0.0}), InputError);
  EXPECT_THROW(resampleChain(edges[0], 1), InputError);
}

}  // namespace
}  // namespace s2p

namespace s2p {
namespace {

// Seam walking on an arc of a circle: scaling across the chord by s turns the arc into an
// elliptic arc with the same chord, whose length is known by quadrature; the walked chain reaches
// a target 1 % longer exactly, keeps its ends and its G1 joints, moves by a few mm (the sagitta
// grows by about the factor), and a target below the chord or beyond the limit is refused.
TEST(BezierOutline, WalkingAChainReachesItsTargetLengthAndKeepsItsEnds) {
  const Eigen::MatrixX2d p = arc(200, 0.3, kPi / 2.0);
  const BezierChain chain = fitBezierChain(p, {.tolerance = 5e-5});
  const double length = chain.length();
  const auto walked = walkChainToLength(chain, 1.01 * length, 0.02);
  ASSERT_TRUE(walked.has_value());
  EXPECT_NEAR(walked->length(), 1.01 * length, 1e-9);
  EXPECT_EQ(walked->segments.front().p[0], chain.segments.front().p[0]);
  EXPECT_EQ(walked->segments.back().p[3], chain.segments.back().p[3]);
  expectG1(*walked);
  // The mid point moved outwards along the arc's axis by a few millimetres, no more.
  const Eigen::Vector2d before = chain.point(0.5 * chain.size());
  const Eigen::Vector2d after = walked->point(0.5 * walked->size());
  EXPECT_GT((after - before).norm(), 1e-3);
  EXPECT_LT((after - before).norm(), 2e-2);
  // s = 1 is the identity; a target shorter than the chord, or a 1 mm limit, is refused.
  const BezierChain same = scaledAcrossChord(chain, 1.0);
  EXPECT_NEAR(same.length(), length, 1e-12);
  const double chord = (chain.segments.back().p[3] - chain.segments.front().p[0]).norm();
  EXPECT_FALSE(walkChainToLength(chain, 0.99 * chord, 1.0).has_value());
  EXPECT_FALSE(walkChainToLength(chain, 1.01 * length, 0.001).has_value());
}

}  // namespace
}  // namespace s2p
