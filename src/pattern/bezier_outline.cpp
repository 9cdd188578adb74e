#include "pattern/bezier_outline.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "core/error.h"

namespace s2p {
namespace {

// 8-point Gauss–Legendre nodes on [−1, 1] (positive half) and weights.
constexpr double kGaussX[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                               0.9602898564975363};
constexpr double kGaussW[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                               0.1012285362903763};

double gaussLength(const CubicBezier& b, double t0, double t1) {
  const double mid = 0.5 * (t0 + t1), half = 0.5 * (t1 - t0);
  double sum = 0.0;
  for (int i = 0; i < 4; ++i)
    sum += kGaussW[i] * (b.derivative(mid - half * kGaussX[i]).norm() +
                         b.derivative(mid + half * kGaussX[i]).norm());
  return sum * half;
}

double distanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                         const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double l2 = ab.squaredNorm();
  const double t = l2 > 0.0 ? std::clamp((p - a).dot(ab) / l2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Distance from p to the polyline pts[first..last].
double distanceToPolyline(const std::vector<Eigen::Vector2d>& pts, int first, int last,
                          const Eigen::Vector2d& p) {
  double best = (pts[first] - p).norm();
  for (int i = first; i < last; ++i)
    best = std::min(best, distanceToSegment(p, pts[i], pts[i + 1]));
  return best;
}

// Closest parameter of segment b to p: the best of a coarse sampling, refined by Newton on
// (B(t) − p)·B'(t) = 0.
double closestParameter(const CubicBezier& b, const Eigen::Vector2d& p) {
  constexpr int kSamples = 16;
  double bestT = 0.0, bestD = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= kSamples; ++i) {
    const double t = static_cast<double>(i) / kSamples;
    const double d = (b.point(t) - p).squaredNorm();
    if (d < bestD) bestD = d, bestT = t;
  }
  double t = bestT;
  for (int iter = 0; iter < 8; ++iter) {
    const Eigen::Vector2d q = b.point(t) - p, d1 = b.derivative(t), d2 = b.secondDerivative(t);
    const double num = q.dot(d1), den = d1.squaredNorm() + q.dot(d2);
    if (!(std::abs(den) > 0.0)) break;
    const double next = std::clamp(t - num / den, 0.0, 1.0);
    if (std::abs(next - t) < 1e-14) {
      t = next;
      break;
    }
    t = next;
  }
  return (b.point(t) - p).squaredNorm() <= bestD ? t : bestT;
}

// === Schneider's fit

class ChainFitter {
 public:
  ChainFitter(std::vector<Eigen::Vector2d> pts, const BezierFitOptions& options)
      : pts_(std::move(pts)), options_(options) {}

  BezierChain fit() {
    const int last = static_cast<int>(pts_.size()) - 1;
    fitRange(0, last, endTangent(0, +1), endTangent(last, -1));
    return std::move(chain_);
  }

 private:
  // Unit tangent at an end point, pointing into the polyline (direction +1 from the start,
  // −1 from the end): the one-sided second-order difference on chord-length parameters,
  // the first chord when that differs from it by more than 45° (noise) or with two points.
  Eigen::Vector2d endTangent(int i, int direction) const {
    const Eigen::Vector2d p0 = pts_[i], p1 = pts_[i + direction];
    Eigen::Vector2d chord = (p1 - p0).normalized();
    const int n = static_cast<int>(pts_.size());
    if (n < 3) return chord;
    const Eigen::Vector2d p2 = pts_[i + 2 * direction];
    const double h1 = (p1 - p0).norm(), h2 = (p2 - p1).norm();
    // Derivative at s = 0 of the quadratic through (0, p0), (h1, p1), (h1 + h2, p2).
    const Eigen::Vector2d d = -(2.0 * h1 + h2) / (h1 * (h1 + h2)) * p0 +
                              (h1 + h2) / (h1 * h2) * p1 - h1 / (h2 * (h1 + h2)) * p2;
    if (!(d.norm() > 0.0) || !d.allFinite()) return chord;
    const Eigen::Vector2d t = d.normalized();
    return t.dot(chord) > std::cos(0.25 * std::numbers::pi) ? t : chord;
  }

  // Unit tangent at an inner split point, pointing backwards (towards pts_[i − 1]).
  Eigen::Vector2d centreTangent(int i) const {
    Eigen::Vector2d t = pts_[i - 1] - pts_[i + 1];
    if (!(t.norm() > 0.0)) t = pts_[i - 1] - pts_[i];
    return t.normalized();
  }

  std::vector<double> chordParameters(int first, int last) const {
    std::vector<double> u(last - first + 1, 0.0);
    for (int i = first + 1; i <= last; ++i)
      u[i - first] = u[i - first - 1] + (pts_[i] - pts_[i - 1]).norm();
    for (double& x : u) x /= u.back();
    return u;
  }

  // Least-squares inner control points along the tangents t1 (at first, pointing forward) and
  // t2 (at last, pointing backward); the Wu–Barsky third-of-the-chord fallback when the
  // system is singular, an arm would not be positive or would reach past the chord's end.
  CubicBezier generate(int first, int last, const std::vector<double>& u, const Eigen::Vector2d& t1,
                       const Eigen::Vector2d& t2) const {
    const Eigen::Vector2d p0 = pts_[first], p3 = pts_[last];
    double c00 = 0, c01 = 0, c11 = 0, x0 = 0, x1 = 0;
    for (int i = first; i <= last; ++i) {
      const double t = u[i - first], s = 1.0 - t;
      const double b0 = s * s * s, b1 = 3 * t * s * s, b2 = 3 * t * t * s, b3 = t * t * t;
      const Eigen::Vector2d a0 = t1 * b1, a1 = t2 * b2;
      c00 += a0.dot(a0);
      c01 += a0.dot(a1);
      c11 += a1.dot(a1);
      const Eigen::Vector2d rest = pts_[i] - (p0 * (b0 + b1) + p3 * (b2 + b3));
      x0 += a0.dot(rest);
      x1 += a1.dot(rest);
    }
    const double det = c00 * c11 - c01 * c01;
    const double chord = (p3 - p0).norm();
    double alpha1 = 0.0, alpha2 = 0.0;
    if (std::abs(det) > 1e-12 * std::max(c00 * c11, 1e-300)) {
      alpha1 = (x0 * c11 - x1 * c01) / det;
      alpha2 = (c00 * x1 - c01 * x0) / det;
    }
    // An arm that reaches past the chord's far end (its control point projects outside [0,
    // chord]) makes the segment run past its end point and turn back onto it: a hook narrower
    // than the tolerance, which the fit's error test cannot see, and which makes the outline
    // cross itself at the corner (a neckline's last segment: an arm of 21 mm on a 10 mm chord,
    // the sew line then crossed itself 0.5 mm from the corner). With both projections inside,
    // the segment advances monotonically along its chord: no hook, no loop.
    const Eigen::Vector2d along = chord > 0 ? ((p3 - p0) / chord).eval() : Eigen::Vector2d::Zero();
    const double along1 = alpha1 * t1.dot(along), along2 = chord + alpha2 * t2.dot(along);
    const bool withinChord = along1 >= 0 && along1 <= chord && along2 >= 0 && along2 <= chord;
    if (!(alpha1 > 1e-6 * chord) || !(alpha2 > 1e-6 * chord) || !std::isfinite(alpha1) ||
        !std::isfinite(alpha2) || !withinChord)
      alpha1 = alpha2 = chord / 3.0;
    return CubicBezier{{p0, p0 + alpha1 * t1, p3 + alpha2 * t2, p3}};
  }

  // Largest sample distance |B(u_i) − P_i| (an upper bound of the polyline's distance to B).
  double pointError(const CubicBezier& b, int first, int last, const std::vector<double>& u) const {
    double worst = 0.0;
    for (int i = first + 1; i < last; ++i)
      worst = std::max(worst, (b.point(u[i - first]) - pts_[i]).norm());
    return worst;
  }

  // Largest distance of curve samples to the polyline pts_[first..last].
  double curveError(const CubicBezier& b, int first, int last) const {
    constexpr int kCurveSamples = 64;  // as many as maxDeviation checks
    double worst = 0.0;
    for (int k = 1; k < kCurveSamples; ++k)
      worst = std::max(worst, distanceToPolyline(pts_, first, last,
                                                 b.point(static_cast<double>(k) / kCurveSamples)));
    return worst;
  }

  void reparametrise(const CubicBezier& b, int first, int last, std::vector<double>& u) const {
    for (int i = first; i <= last; ++i) {
      double& t = u[i - first];
      const Eigen::Vector2d q = b.point(t) - pts_[i], d1 = b.derivative(t),
                            d2 = b.secondDerivative(t);
      const double den = d1.squaredNorm() + q.dot(d2);
      if (std::abs(den) > 0.0) t = std::clamp(t - q.dot(d1) / den, 0.0, 1.0);
    }
  }

  // One segment on pts_[first..last] with end tangents t1, t2 (Schneider's fit with Newton
  // reparametrisation); true when it is within the tolerance both ways.
  bool fitSegment(int first, int last, const Eigen::Vector2d& t1, const Eigen::Vector2d& t2,
                  CubicBezier& out) const {
    const double tol = options_.tolerance;
    if (last - first == 1) {  // two points: arms of a third of the chord
      const double d = (pts_[last] - pts_[first]).norm() / 3.0;
      out = CubicBezier{{pts_[first], pts_[first] + d * t1, pts_[last] + d * t2, pts_[last]}};
      return true;
    }
    std::vector<double> u = chordParameters(first, last);
    out = generate(first, last, u, t1, t2);
    double error = pointError(out, first, last, u);
    if (error <= tol && curveError(out, first, last) <= tol) return true;
    if (error > options_.reparametriseFactor * tol) return false;
    for (int pass = 0; pass < options_.maxReparametrisations; ++pass) {
      reparametrise(out, first, last, u);
      // Keep the parameters increasing (Newton can swap neighbours on tight bends).
      for (size_t i = 1; i < u.size(); ++i) u[i] = std::max(u[i], u[i - 1]);
      const CubicBezier candidate = generate(first, last, u, t1, t2);
      const double candidateError = pointError(candidate, first, last, u);
      if (candidateError < error) out = candidate, error = candidateError;
      if (error <= tol && curveError(out, first, last) <= tol) return true;
    }
    return false;
  }

  // The chain on pts_[first..last]: one segment if it fits, otherwise greedily the longest
  // prefix that fits (binary search on its end), ending at a split point whose data tangent
  // both neighbouring segments share (G1), then the rest the same way.
  void fitRange(int first, int last, const Eigen::Vector2d& t1, const Eigen::Vector2d& t2) {
    int start = first;
    Eigen::Vector2d tangent = t1;
    CubicBezier segment;
    while (!fitSegment(start, last, tangent, t2, segment)) {
      int lo = start + 1, hi = last;  // a two-point segment always "fits"; the whole does not
      while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        CubicBezier probe;
        if (fitSegment(start, mid, tangent, centreTangent(mid), probe))
          lo = mid;
        else
          hi = mid;
      }
      const Eigen::Vector2d centre = centreTangent(lo);
      fitSegment(start, lo, tangent, centre, segment);
      chain_.segments.push_back(segment);
      start = lo;
      tangent = -centre;
    }
    chain_.segments.push_back(segment);
  }

  std::vector<Eigen::Vector2d> pts_;
  BezierFitOptions options_;
  BezierChain chain_;
};

// Cumulative arc lengths of a segment at kTable + 1 equally spaced parameters.
constexpr int kTable = 16;
std::array<double, kTable + 1> lengthTable(const CubicBezier& b) {
  std::array<double, kTable + 1> s{};
  for (int k = 0; k < kTable; ++k)
    s[k + 1] =
        s[k] + gaussLength(b, static_cast<double>(k) / kTable, static_cast<double>(k + 1) / kTable);
  return s;
}

}  // namespace

// === CubicBezier, BezierChain

Eigen::Vector2d CubicBezier::point(double t) const {
  const double s = 1.0 - t;
  return s * s * s * p[0] + 3 * s * s * t * p[1] + 3 * s * t * t * p[2] + t * t * t * p[3];
}

Eigen::Vector2d CubicBezier::derivative(double t) const {
  const double s = 1.0 - t;
  return 3 * s * s * (p[1] - p[0]) + 6 * s * t * (p[2] - p[1]) + 3 * t * t * (p[3] - p[2]);
}

Eigen::Vector2d CubicBezier::secondDerivative(double t) const {
  return 6 * (1.0 - t) * (p[2] - 2 * p[1] + p[0]) + 6 * t * (p[3] - 2 * p[2] + p[1]);
}

double CubicBezier::length(double t0, double t1) const {
  // Subdivide into pieces of at most 1/8 of the parameter range for accuracy on bends.
  const int pieces = std::max(1, static_cast<int>(std::ceil(std::abs(t1 - t0) * 8.0)));
  double sum = 0.0;
  for (int i = 0; i < pieces; ++i)
    sum += gaussLength(*this, t0 + (t1 - t0) * i / pieces, t0 + (t1 - t0) * (i + 1) / pieces);
  return sum;
}

double BezierChain::length() const {
  double sum = 0.0;
  for (const CubicBezier& b : segments) sum += b.length();
  return sum;
}

Eigen::Vector2d BezierChain::point(double tau) const {
  if (segments.empty()) return Eigen::Vector2d::Constant(std::nan(""));
  const int i = std::clamp(static_cast<int>(std::floor(tau)), 0, size() - 1);
  return segments[i].point(std::clamp(tau - i, 0.0, 1.0));
}

// === Fitting

BezierChain fitBezierChain(const Eigen::MatrixX2d& polyline, const BezierFitOptions& options) {
  if (!(options.tolerance > 0.0) || !std::isfinite(options.tolerance))
    throw InputError(
        fmt::format("fitBezierChain: the tolerance must be positive (got {})", options.tolerance));
  if (!polyline.allFinite())
    throw InputError("fitBezierChain: the polyline has non-finite coordinates");
  std::vector<Eigen::Vector2d> pts;
  pts.reserve(polyline.rows());
  for (int i = 0; i < polyline.rows(); ++i) {
    const Eigen::Vector2d p = polyline.row(i).transpose();
    if (pts.empty() || (p - pts.back()).norm() > 0.0) pts.push_back(p);
  }
  if (pts.size() < 2)
    throw InputError(fmt::format(
        "fitBezierChain: the polyline has {} distinct points; an edge needs at least two",
        pts.size()));
  return ChainFitter(std::move(pts), options).fit();
}

std::vector<BezierChain> fitOutline(const Eigen::MatrixX2d& points, const std::vector<int>& corners,
                                    const BezierFitOptions& options) {
  const int n = static_cast<int>(points.rows());
  if (corners.empty())
    throw InputError("fitOutline: at least one corner is needed to cut the outline into edges");
  for (size_t k = 0; k < corners.size(); ++k)
    if (corners[k] < 0 || corners[k] >= n || (k > 0 && corners[k] <= corners[k - 1]))
      throw InputError(
          fmt::format("fitOutline: corner {} (index {}) is out of range or out of "
                      "order; corners must increase within [0, {})",
                      k, corners[k], n));
  std::vector<BezierChain> chains;
  const int m = static_cast<int>(corners.size());
  for (int k = 0; k < m; ++k) {
    const int a = corners[k];
    const int b = k + 1 < m ? corners[k + 1] : corners[0] + n;  // wrap
    Eigen::MatrixX2d edge(b - a + 1, 2);
    for (int i = a; i <= b; ++i) edge.row(i - a) = points.row(i % n);
    chains.push_back(fitBezierChain(edge, options));
  }
  return chains;
}

// === Resampling and deviation

Eigen::MatrixX2d resampleChain(const BezierChain& chain, int count) {
  if (count < 2) throw InputError(fmt::format("resampleChain: count {} < 2", count));
  if (chain.segments.empty()) throw InputError("resampleChain: the chain has no segments");
  const int m = chain.size();
  std::vector<std::array<double, kTable + 1>> tables(m);
  std::vector<double> start(m + 1, 0.0);
  for (int i = 0; i < m; ++i) {
    tables[i] = lengthTable(chain.segments[i]);
    start[i + 1] = start[i] + tables[i][kTable];
  }
  const double total = start[m];
  Eigen::MatrixX2d out(count, 2);
  out.row(0) = chain.segments.front().p[0].transpose();
  out.row(count - 1) = chain.segments.back().p[3].transpose();
  int seg = 0;
  for (int j = 1; j + 1 < count; ++j) {
    const double s = total * j / (count - 1);
    while (seg + 1 < m && start[seg + 1] < s) ++seg;
    const CubicBezier& b = chain.segments[seg];
    const auto& table = tables[seg];
    const double local = s - start[seg];
    int k = 0;
    while (k + 1 < kTable && table[k + 1] < local) ++k;
    // Newton on length(t_k, t) = local − table[k] within the table interval.
    const double lo = static_cast<double>(k) / kTable, hi = static_cast<double>(k + 1) / kTable;
    const double want = local - table[k];
    const double span = table[k + 1] - table[k];
    double t = span > 0.0 ? lo + (hi - lo) * std::clamp(want / span, 0.0, 1.0) : lo;
    for (int iter = 0; iter < 12; ++iter) {
      const double f = gaussLength(b, lo, t) - want;
      const double speed = b.derivative(t).norm();
      if (!(speed > 0.0)) break;
      const double next = std::clamp(t - f / speed, lo, hi);
      const bool done = std::abs(next - t) < 1e-15;
      t = next;
      if (done) break;
    }
    out.row(j) = b.point(t).transpose();
  }
  return out;
}

double distanceToChain(const BezierChain& chain, const Eigen::Vector2d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const CubicBezier& b : chain.segments) {
    // The convex hull of the control points bounds the segment: skip when it is farther.
    double hullLower = std::numeric_limits<double>::infinity();
    Eigen::Vector2d lo = b.p[0], hi = b.p[0];
    for (const Eigen::Vector2d& c : b.p) lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
    hullLower = (p - p.cwiseMax(lo).cwiseMin(hi)).norm();
    if (hullLower >= best) continue;
    best = std::min(best, (b.point(closestParameter(b, p)) - p).norm());
  }
  return best;
}

double maxDeviation(const BezierChain& chain, const Eigen::MatrixX2d& polyline) {
  if (chain.segments.empty() || polyline.rows() == 0)
    throw InputError("maxDeviation: the chain and the polyline must be non-empty");
  std::vector<Eigen::Vector2d> pts(polyline.rows());
  for (int i = 0; i < polyline.rows(); ++i) pts[i] = polyline.row(i).transpose();
  double worst = 0.0;
  for (const Eigen::Vector2d& p : pts) worst = std::max(worst, distanceToChain(chain, p));
  constexpr int kSamples = 64;
  const int last = static_cast<int>(pts.size()) - 1;
  for (const CubicBezier& b : chain.segments)
    for (int k = 0; k <= kSamples; ++k)
      worst = std::max(
          worst, distanceToPolyline(pts, 0, last, b.point(static_cast<double>(k) / kSamples)));
  return worst;
}

std::vector<double> jointFractions(const BezierChain& chain) {
  std::vector<double> out;
  const double total = chain.length();
  if (!(total > 0.0)) return out;
  double run = 0.0;
  for (int k = 0; k + 1 < chain.size(); ++k) {
    run += chain.segments[k].length();
    out.push_back(run / total);
  }
  return out;
}

namespace {

// The parameter of `segment` at arc length s from its start (bisection on the monotone length).
double parameterAtLength(const CubicBezier& segment, double s) {
  double lo = 0.0, hi = 1.0;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (segment.length(0.0, mid) < s ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// De Casteljau split of a segment at t: the pieces [0, t] and [t, 1].
std::pair<CubicBezier, CubicBezier> splitSegment(const CubicBezier& b, double t) {
  const Eigen::Vector2d p01 = b.p[0] + t * (b.p[1] - b.p[0]);
  const Eigen::Vector2d p12 = b.p[1] + t * (b.p[2] - b.p[1]);
  const Eigen::Vector2d p23 = b.p[2] + t * (b.p[3] - b.p[2]);
  const Eigen::Vector2d p012 = p01 + t * (p12 - p01), p123 = p12 + t * (p23 - p12);
  const Eigen::Vector2d mid = p012 + t * (p123 - p012);
  return {CubicBezier{{b.p[0], p01, p012, mid}}, CubicBezier{{mid, p123, p23, b.p[3]}}};
}

}  // namespace

BezierChain splitChainAt(const BezierChain& chain, std::vector<double> fractions) {
  constexpr double kMerge = 1e-4;
  const double total = chain.length();
  if (!(total > 0.0) || chain.segments.empty()) return chain;
  std::sort(fractions.begin(), fractions.end());
  const std::vector<double> joints = jointFractions(chain);
  BezierChain out;
  double start = 0.0;  // arc-length fraction where the current segment begins
  size_t next = 0;
  for (int k = 0; k < chain.size(); ++k) {
    const double end = k + 1 < chain.size() ? joints[k] : 1.0;
    CubicBezier rest = chain.segments[k];
    double restStart = start;  // fraction where `rest` begins
    for (; next < fractions.size() && fractions[next] < end - kMerge; ++next) {
      const double f = fractions[next];
      if (f <= restStart + kMerge) continue;
      const double t = parameterAtLength(rest, (f - restStart) * total);
      auto [head, tail] = splitSegment(rest, t);
      out.segments.push_back(head);
      rest = tail;
      restStart = f;
    }
    while (next < fractions.size() && fractions[next] <= end + kMerge) ++next;
    out.segments.push_back(rest);
    start = end;
  }
  return out;
}

BezierChain scaledAcrossChord(const BezierChain& chain, double s) {
  const Eigen::Vector2d a = chain.segments.front().p[0];
  const Eigen::Vector2d u = (chain.segments.back().p[3] - a).normalized();
  BezierChain out = chain;
  for (CubicBezier& b : out.segments)
    for (Eigen::Vector2d& x : b.p) {
      const Eigen::Vector2d along = a + u * u.dot(x - a);
      x = along + s * (x - along);
    }
  // The ends lie on the chord: kept bit for bit (they are corners the next edge starts from).
  out.segments.front().p[0] = chain.segments.front().p[0];
  out.segments.back().p[3] = chain.segments.back().p[3];
  return out;
}

std::optional<BezierChain> walkChainToLength(const BezierChain& chain, double target,
                                             double limit) {
  if (chain.segments.empty()) return std::nullopt;
  const Eigen::Vector2d a = chain.segments.front().p[0], b = chain.segments.back().p[3];
  if ((b - a).norm() < 1e-9) return std::nullopt;
  double lo = 0.0, hi = 4.0;
  if (scaledAcrossChord(chain, lo).length() > target ||
      scaledAcrossChord(chain, hi).length() < target)
    return std::nullopt;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (scaledAcrossChord(chain, mid).length() < target ? lo : hi) = mid;
  }
  BezierChain out = scaledAcrossChord(chain, 0.5 * (lo + hi));
  double moved = 0;
  for (int k = 0; k < chain.size(); ++k)
    for (int i = 0; i < 4; ++i)
      moved = std::max(moved, (out.segments[k].p[i] - chain.segments[k].p[i]).norm());
  if (moved > limit) return std::nullopt;
  return out;
}

}  // namespace s2p
