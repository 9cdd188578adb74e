#include "body/mannequin_implicit.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace s2p {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kFar = 1e9;

// Quadratic polynomial smooth minimum (C1), blend radius k.
double smin(double a, double b, double k) {
  if (k <= 0) return std::min(a, b);
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}

// Fritsch–Carlson slope at an interior knot from the two neighbouring secants.
double pchipSlope(double s0, double s1, double h0, double h1) {
  if (s0 * s1 <= 0) return 0.0;
  const double w1 = 2 * h1 + h0, w2 = h1 + 2 * h0;
  return (w1 + w2) / (w1 / s0 + w2 / s1);
}

double distanceToSegment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - a - t * ab).norm();
}

// Convex hull perimeter of 2D points (Andrew's monotone chain).
double hullPerimeter(std::vector<Eigen::Vector2d> pts) {
  if (pts.size() < 3) return 0.0;
  std::sort(pts.begin(), pts.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
  };
  std::vector<Eigen::Vector2d> hull(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i - 1]) <= 0) --k;
    hull[k++] = pts[i - 1];
  }
  double perimeter = 0;
  for (size_t i = 0; i + 1 < k; ++i) perimeter += (hull[i + 1] - hull[i]).norm();
  return perimeter;
}

// Loft with its frame from an axis direction and a hint for u (made ⟂ axis).
Loft makeLoft(const Eigen::Vector3d& origin, const Eigen::Vector3d& end,
              const Eigen::Vector3d& uHint, double mirror = 1.0) {
  Loft l;
  l.origin = origin;
  const Eigen::Vector3d d = end - origin;
  l.length = d.norm();
  l.axis = l.length > 0 ? Eigen::Vector3d(d / l.length) : Eigen::Vector3d::UnitY();
  l.u = (uHint - uHint.dot(l.axis) * l.axis).normalized();
  l.v = mirror * l.axis.cross(l.u);
  return l;
}

Loft makeEllipsoid(const Eigen::Vector3d& centre, const Eigen::Vector3d& axis,
                   const Eigen::Vector3d& uHint, const Eigen::Vector3d& radii, double mirror,
                   double blend, int joint) {
  Loft l;
  l.origin = centre;
  l.length = 0;
  l.axis = axis.normalized();
  l.u = (uHint - uHint.dot(l.axis) * l.axis).normalized();
  l.v = mirror * l.axis.cross(l.u);
  l.t = {0.0};
  l.sec = {Eigen::Vector4d(radii.x(), radii.y(), 0, 0)};
  l.capStart = l.capEnd = radii.z();
  l.blend = blend;
  l.bones = {{0.0, joint}};
  l.finalize();
  return l;
}

}  // namespace

// === Loft

void Loft::finalize() {
  const size_t n = t.size();
  slope.assign(n, Eigen::Vector4d::Zero());
  for (size_t i = 1; i + 1 < n; ++i) {
    const double h0 = t[i] - t[i - 1], h1 = t[i + 1] - t[i];
    for (int c = 0; c < 4; ++c) {
      const double s0 = (sec[i][c] - sec[i - 1][c]) / h0, s1 = (sec[i + 1][c] - sec[i][c]) / h1;
      slope[i][c] = pchipSlope(s0, s1, h0, h1);
    }
  }
  boundRadius = 0;
  for (const auto& s : sec)
    boundRadius = std::max(boundRadius, std::hypot(s[2], s[3]) + std::max(s[0], s[1]));
}

double Loft::knotSpace(double tt) const {
  if (t.size() < 2) return tt;
  const size_t i =
      std::min<size_t>(std::upper_bound(t.begin(), t.end(), tt) - t.begin(), t.size() - 1) - 1;
  const double x = std::clamp((tt - t[i]) / (t[i + 1] - t[i]), 0.0, 1.0);
  return (static_cast<double>(i) + x) / static_cast<double>(t.size() - 1);
}

double Loft::fromKnotSpace(double w) const {
  if (t.size() < 2) return w;
  const double x = std::clamp(w, 0.0, 1.0) * static_cast<double>(t.size() - 1);
  const size_t i = std::min<size_t>(static_cast<size_t>(x), t.size() - 2);
  return t[i] + (x - static_cast<double>(i)) * (t[i + 1] - t[i]);
}

Eigen::Vector4d Loft::section(double tt) const {
  if (t.size() == 1 || tt <= t.front()) return sec.front();
  if (tt >= t.back()) return sec.back();
  size_t i = std::upper_bound(t.begin(), t.end(), tt) - t.begin() - 1;
  const double h = t[i + 1] - t[i], x = (tt - t[i]) / h;
  const double h00 = (1 + 2 * x) * (1 - x) * (1 - x), h10 = x * (1 - x) * (1 - x);
  const double h01 = x * x * (3 - 2 * x), h11 = x * x * (x - 1);
  return h00 * sec[i] + h10 * h * slope[i] + h01 * sec[i + 1] + h11 * h * slope[i + 1];
}

// === Skeleton tables

const std::array<int, kMjCount>& mannequinParents() {
  static const std::array<int, kMjCount> p = {-1, 0, 1, 2,  3,  2,  2,  5,  6,  7,  8, 9,
                                              10, 0, 0, 13, 14, 15, 16, 17, 18, 11, 12};
  return p;
}

const std::array<const char*, kMjCount>& mannequinJointNames() {
  static const std::array<const char*, kMjCount> n = {
      "pelvis",        "spine",          "chest",         "neck",           "head",
      "left_clavicle", "right_clavicle", "left_shoulder", "right_shoulder", "left_elbow",
      "right_elbow",   "left_wrist",     "right_wrist",   "left_hip",       "right_hip",
      "left_knee",     "right_knee",     "left_ankle",    "right_ankle",    "left_toe",
      "right_toe",     "left_hand",      "right_hand"};
  return n;
}

MannequinLevels mannequinLevels(const MannequinMeasurements& m) {
  const double s = m.height / 1.75;
  return {0.72 * m.height, 0.61 * m.height, m.inseam + 0.10 * s};
}

// === MannequinImplicit

MannequinImplicit::MannequinImplicit(const MannequinMeasurements& m,
                                     const MannequinImplicit* warmStart)
    : m_(m) {
  const double vals[] = {m.height,    m.chest,  m.waist, m.hip,   m.shoulder,
                         m.armLength, m.inseam, m.neck,  m.thigh, m.upperArm};
  for (double v : vals)
    if (!std::isfinite(v) || v <= 0)
      throw InputError("mannequin: every measurement must be a positive finite length in metres");
  if (m.height < 1.0 || m.height > 2.5)
    throw InputError("mannequin: height " + std::to_string(m.height) +
                     " m is outside 1.0–2.5 m; use a realistic adult height");
  const double s = m.height / 1.75;
  const auto ratioOk = [&](double v, double def, double lo, double hi) {
    return v / (def * s) >= lo && v / (def * s) <= hi;
  };
  if (!ratioOk(m.chest, 0.96, 0.6, 1.6) || !ratioOk(m.waist, 0.82, 0.55, 1.8) ||
      !ratioOk(m.hip, 0.98, 0.6, 1.6) || !ratioOk(m.shoulder, 0.36, 0.7, 1.35) ||
      !ratioOk(m.armLength, 0.56, 0.8, 1.2) || !ratioOk(m.inseam, 0.80, 0.85, 1.15) ||
      !ratioOk(m.neck, 0.38, 0.7, 1.4) || !ratioOk(m.thigh, 0.56, 0.65, 1.5) ||
      !ratioOk(m.upperArm, 0.31, 0.65, 1.6))
    throw InputError(
        "mannequin: a measurement is out of proportion with the height (girths 0.6–1.6×, "
        "lengths 0.8–1.2× the defaults scaled by height/1.75 m); request a plausible body");

  // Calibration: adjust internal knobs until a tape on the implicit surface reads m.
  Knobs k = warmStart ? warmStart->knobs_ : Knobs{};
  const MannequinLevels lv = mannequinLevels(m);
  for (int it = 0; it < 12; ++it) {
    build(k);
    Eigen::Vector3d nArm, nNeck;
    const Eigen::Vector3d cArm = upperArmTapeCentre(true, &nArm);
    const Eigen::Vector3d cNeck = neckTapeCentre(&nNeck);
    const double top = headTop(), cr = crotch();
    const double chest = sectionGirth({0, lv.chest, 0}, Eigen::Vector3d::UnitY());
    const double waist = sectionGirth({0, lv.waist, 0}, Eigen::Vector3d::UnitY());
    const double hip = sectionGirth({0, lv.hip, 0}, Eigen::Vector3d::UnitY());
    const double thigh = sectionGirth(thighTapeCentre(true), Eigen::Vector3d::UnitY());
    const double arm = sectionGirth(cArm, nArm);
    const double neck = sectionGirth(cNeck, nNeck);
    const double err =
        std::max({std::abs(top - m.height), std::abs(cr - m.inseam), std::abs(chest - m.chest),
                  std::abs(waist - m.waist), std::abs(hip - m.hip), std::abs(thigh - m.thigh),
                  std::abs(arm - m.upperArm), std::abs(neck - m.neck)});
    if (err < 1e-6) {
      knobs_ = k;
      return;
    }
    if (it == 11 && err > 1e-4)
      throw InputError(
          "mannequin: cannot build a body whose tapes read the requested "
          "measurements (off by " +
          std::to_string(1000 * err) + " mm); the combination is out of proportion");
    k.headShift += m.height - top;
    k.crotchShift += m.inseam - cr;
    k.chest *= m.chest / chest;
    k.waist *= m.waist / waist;
    k.hip *= m.hip / hip;
    k.thigh *= m.thigh / thigh;
    k.upperArm *= m.upperArm / arm;
    k.neck *= m.neck / neck;
  }
  build(k);
  knobs_ = k;
}

void MannequinImplicit::build(const Knobs& kn) {
  const MannequinMeasurements& m = m_;
  const double H = m.height, s = H / 1.75;
  const MannequinLevels lv = mannequinLevels(m);
  const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(),
                        Z = Eigen::Vector3d::UnitZ();
  prims_.clear();
  limbs_.clear();
  limbBlend_.clear();

  const double ySj = 0.805 * H, yNb = 0.845 * H, yAp = 0.765 * H, yUb = 0.68 * H;
  const double yTop = 0.80 * H, yHipJ = m.inseam + 0.085 * s;
  const double yPelvis = lv.hip + 0.36 * (lv.waist - lv.hip);  // fixed fraction between knots
  const double headTop = H + kn.headShift;

  // --- torso: horizontal elliptical sections (half width a, half depth b, centre z)
  const double ac = 0.170 * m.chest / 0.96 * kn.chest, bc = 0.135 * m.chest / 0.96 * kn.chest;
  const double aw = 0.145 * m.waist / 0.82 * kn.waist, bw = 0.115 * m.waist / 0.82 * kn.waist;
  const double ah = 0.180 * m.hip / 0.98 * kn.hip, bh = 0.130 * m.hip / 0.98 * kn.hip;
  const double crotchCap = 0.05 * s;
  const double y0 = m.inseam + kn.crotchShift + crotchCap;
  {
    Loft t = makeLoft({0, y0, 0}, {0, yTop, 0}, X, -1.0);  // v = +Z (front)
    const double L = yTop - y0;
    auto knot = [&](double y, double a, double b, double cz) {
      t.t.push_back((y - y0) / L);
      t.sec.emplace_back(a, b, 0, cz);
    };
    knot(y0, 0.75 * ah, 0.88 * bh, -0.02 * s);
    knot(lv.hip, ah, bh, -0.018 * s);
    knot(lv.waist, aw, bw, 0.0);
    knot(yUb, std::max(0.93 * ac, 1.01 * aw), std::max(0.9 * bc, 1.01 * bw), 0.006 * s);
    knot(lv.chest, ac, bc, 0.012 * s);
    knot(yAp, 0.96 * ac, 0.92 * bc, 0.0);
    knot(yTop, 0.75 * ac, 0.72 * bc, -0.015 * s);
    t.capStart = crotchCap;
    t.capEnd = 0.1 * s;
    t.blend = 0.03 * s;
    t.bones = {{(yPelvis - y0) / L, kMjPelvis},
               {(lv.waist - y0) / L, kMjSpine},
               {(lv.chest - y0) / L, kMjChest}};
    t.finalize();
    crotchZ_ = t.sec.front()[3];
    prims_.push_back(t);
    joints_.row(kMjPelvis) = Eigen::Vector3d(0, yPelvis, t.section((yPelvis - y0) / L)[3]);
    joints_.row(kMjSpine) = Eigen::Vector3d(0, lv.waist, t.section((lv.waist - y0) / L)[3]);
    joints_.row(kMjChest) = Eigen::Vector3d(0, lv.chest, t.section((lv.chest - y0) / L)[3]);
  }
  // --- neck, from inside the shoulders to the skull base
  const Eigen::Vector3d neckBase(0, yNb, -0.025 * s), headBase(0, headTop - 0.155 * s, -0.012 * s);
  {
    const double r = m.neck / (2 * kPi) * kn.neck;
    Loft l = makeLoft(neckBase - 0.03 * s * Y, headBase, X);
    l.t = {0.0, 0.5, 1.0};
    l.sec = {{1.25 * r, 1.12 * r, 0, 0}, {1.02 * r, 0.98 * r, 0, 0}, {1.0 * r, 0.97 * r, 0, 0}};
    l.capStart = l.capEnd = 0.03 * s;
    l.blend = 0.03 * s;
    l.bones = {{0.05, kMjChest}, {0.25, kMjNeck}, {0.85, kMjNeck}, {1.1, kMjHead}};
    l.finalize();
    prims_.push_back(l);
    joints_.row(kMjNeck) = neckBase;
    joints_.row(kMjHead) = headBase;
  }
  // --- head: cranium, jaw, nose, ears
  prims_.push_back(makeEllipsoid({0, headTop - 0.105 * s, -0.010 * s}, Y, X,
                                 Eigen::Vector3d(0.077, 0.097, 0.105) * s, 1, 0.02 * s, kMjHead));
  prims_.push_back(makeEllipsoid({0, headTop - 0.165 * s, 0.020 * s}, Y, X,
                                 Eigen::Vector3d(0.056, 0.068, 0.065) * s, 1, 0.025 * s, kMjHead));
  prims_.push_back(makeEllipsoid({0, headTop - 0.128 * s, 0.083 * s}, Eigen::Vector3d(0, 1, 0.35),
                                 X, Eigen::Vector3d(0.011, 0.017, 0.024) * s, 1, 0.012 * s,
                                 kMjHead));
  for (double side : {1.0, -1.0})
    prims_.push_back(makeEllipsoid({side * 0.076 * s, headTop - 0.115 * s, -0.012 * s}, Y, X,
                                   Eigen::Vector3d(0.010, 0.018, 0.028) * s, side, 0.012 * s,
                                   kMjHead));
  // --- clavicle / trapezius lofts from the neck base to the shoulders
  for (double side : {1.0, -1.0}) {
    const int cj = side > 0 ? kMjLeftClavicle : kMjRightClavicle;
    const int sj = side > 0 ? kMjLeftShoulder : kMjRightShoulder;
    const Eigen::Vector3d a(side * 0.03 * s, yNb - 0.045 * s, -0.03 * s);
    const Eigen::Vector3d b(side * m.shoulder / 2, ySj + 0.022 * s, -0.022 * s);
    Loft l = makeLoft(a, b, Y, side);
    l.t = {0.0, 1.0};
    l.sec = {{0.05 * s, 0.058 * s, 0, 0}, {0.036 * s, 0.05 * s, 0, 0}};
    l.capStart = 0.03 * s;
    l.capEnd = 0.035 * s;
    l.blend = 0.035 * s;
    l.bones = {{-0.2, kMjChest}, {0.35, cj}, {0.9, cj}, {1.3, sj}};
    l.finalize();
    prims_.push_back(l);
    joints_.row(cj) = a;
  }
  coreEnd_ = static_cast<int>(prims_.size());

  // --- arms: deltoid, upper arm, forearm, mitten hand, thumb; 45° below horizontal
  const double c45 = std::sqrt(0.5);
  for (double side : {1.0, -1.0}) {
    const bool left = side > 0;
    const int js = left ? kMjLeftShoulder : kMjRightShoulder;
    const int je = left ? kMjLeftElbow : kMjRightElbow;
    const int jw = left ? kMjLeftWrist : kMjRightWrist;
    const int jh = left ? kMjLeftHand : kMjRightHand;
    const int jc = left ? kMjLeftClavicle : kMjRightClavicle;
    const Eigen::Vector3d dir(side * c45, -c45, 0);
    const Eigen::Vector3d up = side * Z.cross(dir);  // ⟂ arm, pointing up and out
    const Eigen::Vector3d S(side * m.shoulder / 2, ySj, -0.02 * s);
    const Eigen::Vector3d E = S + 0.55 * m.armLength * dir;
    const Eigen::Vector3d W = E + 0.45 * m.armLength * dir;
    joints_.row(js) = S;
    joints_.row(je) = E;
    joints_.row(jw) = W;
    joints_.row(jh) = W + 0.095 * s * dir;
    const int begin = static_cast<int>(prims_.size());
    prims_.push_back(makeEllipsoid(S + 0.012 * s * up, dir, up,
                                   Eigen::Vector3d(0.052, 0.056, 0.062) * s, side, 0.03 * s, js));
    prims_.back().bones = {{-0.5, jc}, {0.5, js}};
    const double r = m.upperArm / (2 * kPi) * kn.upperArm;
    Loft ua = makeLoft(S, E, up, side);
    ua.t = {0.0, 0.5, 1.0};
    ua.sec = {{0.05 * s, 0.053 * s, 0, 0}, {0.98 * r, 1.02 * r, 0, 0}, {0.037 * s, 0.04 * s, 0, 0}};
    ua.capStart = 0.03 * s;
    ua.capEnd = 0.04 * s;
    ua.blend = 0.03 * s;
    ua.bones = {{0.0, js}, {0.85, js}, {1.15, je}};
    ua.finalize();
    prims_.push_back(ua);
    Loft fa = makeLoft(E, W, up, side);
    fa.t = {0.0, 0.3, 1.0};
    fa.sec = {
        {0.036 * s, 0.04 * s, 0, 0}, {0.039 * s, 0.043 * s, 0, 0}, {0.02 * s, 0.029 * s, 0, 0}};
    fa.capStart = 0.035 * s;
    fa.capEnd = 0.02 * s;
    fa.blend = 0.025 * s;
    fa.bones = {{-0.15, js}, {0.15, je}, {0.85, je}, {1.1, jw}};
    fa.finalize();
    prims_.push_back(fa);
    Loft hd = makeLoft(W, W + 0.165 * s * dir, up, side);
    hd.t = {0.0, 0.4, 0.65, 1.0};
    hd.sec = {{0.017 * s, 0.029 * s, 0, 0},
              {0.0145 * s, 0.044 * s, 0, 0},
              {0.0125 * s, 0.042 * s, 0, 0},
              {0.0105 * s, 0.035 * s, 0, 0}};
    hd.capStart = 0.02 * s;
    hd.capEnd = 0.025 * s;
    hd.blend = 0.015 * s;
    hd.bones = {{-0.15, je}, {0.1, jw}, {0.5, jw}, {0.65, jh}};
    hd.finalize();
    prims_.push_back(hd);
    const Eigen::Vector3d tb = W + 0.035 * s * dir + 0.026 * s * Z - 0.004 * s * up;
    Loft th = makeLoft(tb, tb + 0.05 * s * (dir + 0.9 * Z - 0.25 * up).normalized(), up, side);
    th.t = {0.0, 1.0};
    th.sec = {{0.011 * s, 0.013 * s, 0, 0}, {0.0095 * s, 0.0105 * s, 0, 0}};
    th.capStart = 0.012 * s;
    th.capEnd = 0.012 * s;
    th.blend = 0.012 * s;
    th.bones = {{0.0, jw}};
    th.finalize();
    prims_.push_back(th);
    limbs_.emplace_back(begin, static_cast<int>(prims_.size()));
    limbBlend_.push_back(0.03 * s);
  }

  // --- legs: thigh, calf, foot; legs spread 7° each
  const double spread = 7.0 * kPi / 180.0;
  for (double side : {1.0, -1.0}) {
    const bool left = side > 0;
    const int jh = left ? kMjLeftHip : kMjRightHip;
    const int jk = left ? kMjLeftKnee : kMjRightKnee;
    const int ja = left ? kMjLeftAnkle : kMjRightAnkle;
    const int jt = left ? kMjLeftToe : kMjRightToe;
    const Eigen::Vector3d dir(side * std::sin(spread), -std::cos(spread), 0);
    const Eigen::Vector3d Hj(side * 0.09 * s * std::sqrt(m.hip / (0.98 * s)), yHipJ, -0.005 * s);
    const double legLen = (yHipJ - 0.075 * s) / std::cos(spread);
    const Eigen::Vector3d K = Hj + 0.5 * legLen * dir, A = Hj + legLen * dir;
    const Eigen::Vector3d fd =
        Eigen::Vector3d(side * std::sin(8 * kPi / 180), 0, std::cos(8 * kPi / 180));
    const Eigen::Vector3d heel = Eigen::Vector3d(A.x(), 0, A.z()) - 0.045 * s * fd;
    joints_.row(jh) = Hj;
    joints_.row(jk) = K;
    joints_.row(ja) = A;
    joints_.row(jt) = heel + 0.7 * 0.2 * s * fd + 0.02 * s * Y;
    const int begin = static_cast<int>(prims_.size());
    const double r = m.thigh / (2 * kPi) * kn.thigh;
    const double tKey = (0.135 * s / std::cos(spread)) / (0.5 * legLen);
    Loft tl = makeLoft(Hj, K, Z.cross(dir) * side, side);
    tl.t = {0.0, tKey, 0.75, 1.0};
    tl.sec = {{0.95 * r, 0.9 * r, 0, 0},
              {r, r, 0, 0},
              {0.06 * s, 0.063 * s, 0, 0.004 * s},
              {0.05 * s, 0.052 * s, 0, 0}};
    tl.capStart = 0.06 * s;
    tl.capEnd = 0.045 * s;
    tl.blend = 0.03 * s;
    tl.bones = {{-0.1, kMjPelvis}, {0.1, jh}, {0.85, jh}, {1.1, jk}};
    tl.finalize();
    prims_.push_back(tl);
    Loft cl = makeLoft(K, A, Z.cross(dir) * side, side);
    cl.t = {0.0, 0.3, 0.8, 1.0};
    cl.sec = {{0.05 * s, 0.052 * s, 0, 0},
              {0.052 * s, 0.058 * s, 0, -0.012 * s},
              {0.036 * s, 0.038 * s, 0, 0},
              {0.032 * s, 0.035 * s, 0, 0}};
    cl.capStart = 0.04 * s;
    cl.capEnd = 0.03 * s;
    cl.blend = 0.03 * s;
    cl.bones = {{-0.1, jh}, {0.1, jk}, {0.85, jk}, {1.1, ja}};
    cl.finalize();
    prims_.push_back(cl);
    Loft ft = makeLoft(heel, heel + 0.2 * s * fd, Y, side);
    ft.t = {0.0, 0.3, 0.7, 1.0};
    const double fa[4] = {0.032 * s, 0.042 * s, 0.025 * s, 0.015 * s};
    const double fb[4] = {0.03 * s, 0.038 * s, 0.048 * s, 0.04 * s};
    for (int i = 0; i < 4; ++i) ft.sec.emplace_back(fa[i], fb[i], fa[i], 0.0);
    ft.capStart = 0.025 * s;
    ft.capEnd = 0.03 * s;
    ft.blend = 0.02 * s;
    ft.bones = {{0.55, ja}, {0.75, jt}};
    ft.finalize();
    prims_.push_back(ft);
    limbs_.emplace_back(begin, static_cast<int>(prims_.size()));
    limbBlend_.push_back(0.035 * s);
  }
}

double MannequinImplicit::bound(int k, const Eigen::Vector3d& p) const {
  const Loft& l = prims_[k];
  return distanceToSegment(p, l.origin - l.capStart * l.axis,
                           l.origin + (l.length + l.capEnd) * l.axis) -
         l.boundRadius;
}

double MannequinImplicit::lowerBound(const Eigen::Vector3d& p) const {
  double lb = kFar;
  for (int k = 0; k < numPrimitives(); ++k) lb = std::min(lb, bound(k, p));
  return lb;
}

double MannequinImplicit::primitiveValue(int k, const Eigen::Vector3d& p) const {
  const Loft& l = prims_[k];
  const Eigen::Vector3d q = p - l.origin;
  const double s = q.dot(l.axis);
  const double tt = l.length > 0 ? std::clamp(s / l.length, 0.0, 1.0) : 0.0;
  const Eigen::Vector4d sc = l.section(tt);
  const double x = q.dot(l.u) - sc[2], y = q.dot(l.v) - sc[3];
  double z = 0, c = 1;
  if (s < 0) {
    z = -s;
    c = l.capStart;
  } else if (s > l.length) {
    z = s - l.length;
    c = l.capEnd;
  }
  const double a = sc[0], b = sc[1];
  const double k0 = std::sqrt(x * x / (a * a) + y * y / (b * b) + z * z / (c * c));
  const double k1 =
      std::sqrt(x * x / (a * a * a * a) + y * y / (b * b * b * b) + z * z / (c * c * c * c));
  const double d = k1 > 1e-12 ? k0 * (k0 - 1) / k1 : -std::min({a, b, c});
  return std::max(d, bound(k, p));
}

double MannequinImplicit::chainValue(int begin, int end, const Eigen::Vector3d& p, double) const {
  double acc = kFar;
  for (int k = begin; k < end; ++k) {
    const double blend = prims_[k].blend;
    if (acc < kFar && bound(k, p) >= acc + blend) continue;  // cannot change the blend
    const double d = primitiveValue(k, p);
    acc = acc < kFar ? smin(acc, d, blend) : d;
  }
  return acc;
}

double MannequinImplicit::value(const Eigen::Vector3d& p) const {
  const double core = chainValue(0, coreEnd_, p, kFar);
  double f = core;
  for (size_t i = 0; i < limbs_.size(); ++i) {
    const auto [b, e] = limbs_[i];
    double lb = kFar, lower = 0;
    for (int k = b; k < e; ++k) {
      lb = std::min(lb, bound(k, p));
      lower += 0.25 * prims_[k].blend;
    }
    if (lb - lower >= core + limbBlend_[i]) continue;  // limb too far to matter
    f = std::min(f, smin(core, chainValue(b, e, p, kFar), limbBlend_[i]));
  }
  return f;
}

Eigen::Vector3d MannequinImplicit::gradient(const Eigen::Vector3d& p) const {
  constexpr double h = 1e-5;
  Eigen::Vector3d g;
  for (int i = 0; i < 3; ++i) {
    Eigen::Vector3d a = p, b = p;
    a[i] += h;
    b[i] -= h;
    g[i] = (value(a) - value(b)) / (2 * h);
  }
  return g;
}

Eigen::Vector3d MannequinImplicit::project(const Eigen::Vector3d& p0, int iterations) const {
  Eigen::Vector3d p = p0;
  double f = value(p);
  Eigen::Vector3d g;
  for (int it = 0; it < iterations && std::abs(f) > 1e-10; ++it) {
    if (it % 2 == 0) {  // forward-difference gradient, refreshed every other step
      constexpr double h = 1e-6;
      for (int i = 0; i < 3; ++i) {
        Eigen::Vector3d q = p;
        q[i] += h;
        g[i] = (value(q) - f) / h;
      }
    }
    const double g2 = g.squaredNorm();
    if (g2 < 1e-12) break;
    Eigen::Vector3d step = f / g2 * g;
    if (step.norm() > 0.02) step *= 0.02 / step.norm();
    p -= step;
    f = value(p);
  }
  return p;
}

LoftCoords MannequinImplicit::coords(int k, const Eigen::Vector3d& p) const {
  const Loft& l = prims_[k];
  const Eigen::Vector3d q = p - l.origin;
  const double s = q.dot(l.axis);
  LoftCoords c;
  double tt;
  if (s < 0) {
    c.axial = s / l.capStart;
    tt = 0;
  } else if (s > l.length || l.length <= 0) {
    c.axial = 1 + (s - l.length) / l.capEnd;
    tt = 1;
  } else {
    tt = s / l.length;
    c.axial = l.knotSpace(tt);
  }
  const Eigen::Vector4d sc = l.section(l.length > 0 ? tt : 0);
  c.xi = (q.dot(l.u) - sc[2]) / sc[0];
  c.eta = (q.dot(l.v) - sc[3]) / sc[1];
  return c;
}

Eigen::Vector3d MannequinImplicit::position(int k, const LoftCoords& c) const {
  const Loft& l = prims_[k];
  double s, tt;
  if (c.axial < 0) {
    s = c.axial * l.capStart;
    tt = 0;
  } else if (c.axial <= 1 && l.length > 0) {
    tt = l.fromKnotSpace(c.axial);
    s = tt * l.length;
  } else {
    s = l.length + (c.axial - 1) * l.capEnd;
    tt = 1;
  }
  const Eigen::Vector4d sc = l.section(l.length > 0 ? tt : 0);
  return l.origin + s * l.axis + (sc[2] + c.xi * sc[0]) * l.u + (sc[3] + c.eta * sc[1]) * l.v;
}

Eigen::Vector3d MannequinImplicit::boxMin() const {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(kFar);
  for (const Loft& l : prims_)
    for (const Eigen::Vector3d& e : {Eigen::Vector3d(l.origin - l.capStart * l.axis),
                                     Eigen::Vector3d(l.origin + (l.length + l.capEnd) * l.axis)})
      lo = lo.cwiseMin(e - Eigen::Vector3d::Constant(l.boundRadius + 0.02));
  return lo;
}

Eigen::Vector3d MannequinImplicit::boxMax() const {
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-kFar);
  for (const Loft& l : prims_)
    for (const Eigen::Vector3d& e : {Eigen::Vector3d(l.origin - l.capStart * l.axis),
                                     Eigen::Vector3d(l.origin + (l.length + l.capEnd) * l.axis)})
      hi = hi.cwiseMax(e + Eigen::Vector3d::Constant(l.boundRadius + 0.02));
  return hi;
}

// === Tape measures on the implicit surface

double MannequinImplicit::sectionGirth(const Eigen::Vector3d& centre,
                                       const Eigen::Vector3d& normal) const {
  const Eigen::Vector3d n = normal.normalized();
  Eigen::Vector3d e1 =
      (std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY());
  e1 = (e1 - e1.dot(n) * n).normalized();
  const Eigen::Vector3d e2 = n.cross(e1);
  constexpr int kRays = 120;
  std::vector<Eigen::Vector2d> pts;
  double r = 0.02;
  for (int i = 0; i < kRays; ++i) {
    const double ang = 2 * kPi * i / kRays;
    const Eigen::Vector3d d = std::cos(ang) * e1 + std::sin(ang) * e2;
    auto inside = [&](double rr) { return value(centre + rr * d) < 0; };
    double lo = r, hi = r;
    constexpr double step = 0.004;
    if (inside(r)) {
      while (inside(hi) && hi < 1.0) hi += step;
      lo = hi - step;
    } else {
      while (lo > 0 && !inside(lo)) lo -= step;
      lo = std::max(lo, 0.0);
      hi = lo + step;
    }
    for (int b = 0; b < 16; ++b) {
      const double mid = 0.5 * (lo + hi);
      (inside(mid) ? lo : hi) = mid;
    }
    r = 0.5 * (lo + hi);
    pts.emplace_back(r * std::cos(ang), r * std::sin(ang));
  }
  return hullPerimeter(pts);
}

double MannequinImplicit::headTop() const {
  const Loft& cranium = prims_[2];
  const Eigen::Vector3d c = cranium.origin;
  double lo = c.y(), hi = c.y() + 0.3;
  for (int b = 0; b < 50; ++b) {
    const double mid = 0.5 * (lo + hi);
    (value({c.x(), mid, c.z()}) < 0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double MannequinImplicit::crotch() const {
  const double yStart = joints_(kMjLeftHip, 1);
  double lo = 0.3 * m_.inseam, hi = yStart;  // lo outside (between the legs), hi inside
  for (int b = 0; b < 50; ++b) {
    const double mid = 0.5 * (lo + hi);
    (value({0, mid, crotchZ_}) < 0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

Eigen::Vector3d MannequinImplicit::thighTapeCentre(bool left) const {
  const int jh = left ? kMjLeftHip : kMjRightHip, jk = left ? kMjLeftKnee : kMjRightKnee;
  const Eigen::Vector3d H = joints_.row(jh), K = joints_.row(jk);
  const double y = m_.inseam - 0.05 * m_.height / 1.75;
  return H + (K - H) * (H.y() - y) / (H.y() - K.y());
}

Eigen::Vector3d MannequinImplicit::upperArmTapeCentre(bool left, Eigen::Vector3d* normal) const {
  const Eigen::Vector3d S = joints_.row(left ? kMjLeftShoulder : kMjRightShoulder);
  const Eigen::Vector3d E = joints_.row(left ? kMjLeftElbow : kMjRightElbow);
  if (normal) *normal = (E - S).normalized();
  return 0.5 * (S + E);
}

Eigen::Vector3d MannequinImplicit::neckTapeCentre(Eigen::Vector3d* normal) const {
  const Eigen::Vector3d a = joints_.row(kMjNeck), b = joints_.row(kMjHead);
  if (normal) *normal = (b - a).normalized();
  return a + 0.4 * (b - a);
}

}  // namespace s2p
