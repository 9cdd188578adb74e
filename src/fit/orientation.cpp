#include "fit/orientation.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>

#include "core/error.h"

namespace s2p {
namespace {

// Area-weighted face centroids: sampling independent of the scan's resolution.
struct Samples {
  Eigen::MatrixX3d P;  // #F×3 centroids
  Eigen::VectorXd w;   // #F areas
  double y0 = 0, height = 0;
  double h(int i) const { return (P(i, 1) - y0) / height; }  // height fraction in [0, 1]
};

Samples sampleFaces(const TriMesh& m) {
  Samples s;
  s.P.resize(m.numFaces(), 3);
  s.w = faceAreas(m);
  for (int f = 0; f < m.numFaces(); ++f)
    s.P.row(f) = (m.V.row(m.F(f, 0)) + m.V.row(m.F(f, 1)) + m.V.row(m.F(f, 2))) / 3.0;
  const BoundingBox box = boundingBox(m.V);
  s.y0 = box.min.y();
  s.height = box.extent().y();
  return s;
}

// Horizontal (x, z) statistics of the samples whose height fraction lies in [lo, hi].
struct Slab {
  double weight = 0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  Eigen::Vector2d min = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d max = -Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
};

Slab slab(const Samples& s, double lo, double hi) {
  Slab r;
  for (int i = 0; i < s.P.rows(); ++i) {
    const double h = s.h(i);
    if (h < lo || h > hi || s.w[i] <= 0) continue;
    const Eigen::Vector2d q(s.P(i, 0), s.P(i, 2));
    r.weight += s.w[i];
    r.mean += s.w[i] * q;
    r.min = r.min.cwiseMin(q);
    r.max = r.max.cwiseMax(q);
  }
  if (r.weight <= 0) return r;
  r.mean /= r.weight;
  for (int i = 0; i < s.P.rows(); ++i) {
    const double h = s.h(i);
    if (h < lo || h > hi) continue;
    const Eigen::Vector2d q = Eigen::Vector2d(s.P(i, 0), s.P(i, 2)) - r.mean;
    r.cov += s.w[i] * q * q.transpose();
  }
  r.cov /= r.weight;
  return r;
}

// Front extent minus back extent along d about the slab's own centroid (a protrusion in
// front, such as the nose, gives a positive value).
double protrusion(const Samples& s, double lo, double hi, const Eigen::Vector2d& d) {
  const Slab sl = slab(s, lo, hi);
  if (sl.weight <= 0) return 0;
  double front = -std::numeric_limits<double>::infinity(), back = front;
  for (int i = 0; i < s.P.rows(); ++i) {
    const double h = s.h(i);
    if (h < lo || h > hi) continue;
    const double t = (Eigen::Vector2d(s.P(i, 0), s.P(i, 2)) - sl.mean).dot(d);
    front = std::max(front, t);
    back = std::max(back, -t);
  }
  return front - back;
}

// The feet point forward: per foot (the low samples split at their lateral mean), the sole
// reaches farther in front of the shin above it than behind it (toes ≈ 15 cm, heel ≈ 5 cm).
// Each foot is measured against its own shin, so a walking stance, one foot ahead of the
// other, does not bias the vote as a comparison of all soles with all ankles would.
double feetCue(const Samples& s, const Eigen::Vector2d& d) {
  const Eigen::Vector2d e(-d.y(), d.x());  // lateral
  const Slab low = slab(s, 0.0, 0.12);
  if (low.weight <= 0) return 0;
  double vote = 0;
  for (const double side : {-1.0, 1.0}) {
    Eigen::Vector2d shin = Eigen::Vector2d::Zero();
    double w = 0;
    for (int i = 0; i < s.P.rows(); ++i) {
      const Eigen::Vector2d q(s.P(i, 0), s.P(i, 2));
      const double h = s.h(i);
      if (h < 0.09 || h > 0.12 || side * (q - low.mean).dot(e) <= 0) continue;
      shin += s.w[i] * q;
      w += s.w[i];
    }
    if (w <= 0) continue;
    shin /= w;
    double front = 0, back = 0;
    for (int i = 0; i < s.P.rows(); ++i) {
      const Eigen::Vector2d q(s.P(i, 0), s.P(i, 2));
      if (s.h(i) > 0.035 || side * (q - low.mean).dot(e) <= 0) continue;
      const double t = (q - shin).dot(d);
      front = std::max(front, t);
      back = std::max(back, -t);
    }
    vote += 0.5 * (front - back);
  }
  return vote;
}

std::string fmt2(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", x);
  return b;
}

}  // namespace

Eigen::Matrix3d yawRotation(double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
}

Eigen::Affine3d turnAboutVertical(const TriMesh& mesh, double yaw) {
  const Eigen::Vector3d c = boundingBox(mesh.V).centre();
  const Eigen::Vector3d pivot(c.x(), 0, c.z());
  return Eigen::Translation3d(pivot) * Eigen::Affine3d(yawRotation(yaw)) *
         Eigen::Translation3d(-pivot);
}

TriMesh rotateAboutVertical(const TriMesh& mesh, double yaw) {
  const Eigen::Affine3d T = turnAboutVertical(mesh, yaw);
  TriMesh out = mesh;
  out.V = (mesh.V * T.linear().transpose()).rowwise() + T.translation().transpose();
  return out;
}

Orientation estimateOrientation(const TriMesh& scan, const OrientationOptions& opt) {
  const std::string what = "orientation: scan";
  if (scan.numVertices() < opt.minVertices || scan.numFaces() < opt.minVertices / 2)
    throw InputError(what + " has " + std::to_string(scan.numVertices()) + " vertices and " +
                     std::to_string(scan.numFaces()) +
                     " faces, far too few for a person (at least " +
                     std::to_string(opt.minVertices) + " vertices); give a full-body scan");
  validateMesh(scan, what);
  const Samples s = sampleFaces(scan);
  const double area = s.w.sum();
  if (!(area > 0) || !(s.height > 0)) throw InputError(what + " has zero surface area or height");
  // Lying down or not elongated: the vertical must dominate the area-weighted covariance.
  const Eigen::RowVector3d mean = (s.w.transpose() * s.P) / area;
  const Eigen::MatrixX3d Q = s.P.rowwise() - mean;
  const Eigen::Matrix3d C = (Q.transpose() * s.w.asDiagonal() * Q) / area;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> hEig(
      (Eigen::Matrix2d() << C(0, 0), C(0, 2), C(2, 0), C(2, 2)).finished());
  const double horizontal = hEig.eigenvalues()[1];
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(C);
  const Eigen::Vector3d major = eig.eigenvectors().col(2);
  if (C(1, 1) < 1.5 * horizontal || std::abs(major.y()) < std::cos(std::numbers::pi / 6))
    throw InputError(what + ": the vertical is not the main axis of the shape (vertical variance " +
                     fmt2(C(1, 1)) + " m², horizontal " + fmt2(horizontal) +
                     " m²): a person lying down, or not a person; rotate the scan so that the "
                     "person stands along +Y");

  if (!(s.height >= opt.minHeight && s.height <= opt.maxHeight))
    throw InputError(what + " is " + fmt2(s.height) + " m tall, not a standing person (" +
                     fmt2(opt.minHeight) + "–" + fmt2(opt.maxHeight) +
                     " m expected); check the units (metres) and that +Y is up");
  // Upside down: most surface lies above mid-height for a standing person (torso, arms and
  // head up, thin legs below) and the two feet make the lowest slab wider than the head top. A
  // long or A-line skirt or dress moves the centroid far down, but its wearer's head top stays
  // much narrower than the feet (or hem): a low centroid alone counts only when the top end is
  // not clearly the narrower one.
  const double centroid = (mean.y() - s.y0) / s.height;
  const Slab bottom = slab(s, 0.0, 0.04), top = slab(s, 0.96, 1.0);
  const double bottomSpan = bottom.weight > 0 ? (bottom.max - bottom.min).norm() : 0;
  const double topSpan = top.weight > 0 ? (top.max - top.min).norm() : 0;
  // A part of a person (only a torso, a bust): a head ends a standing person at one end or the
  // other, a slab about 0.15 m across (a wide hat 0.4 m, 0.25 of the height); the cut ends of a
  // torso are as wide as the body, 0.6 of its height.
  constexpr double kHeadSpan = 0.3;  // of the height: the narrower end's widest span
  if (std::min(topSpan, bottomSpan) > kHeadSpan * s.height)
    throw InputError(what + " has no head at either end: its top and bottom ends are " +
                     fmt2(topSpan) + " and " + fmt2(bottomSpan) + " m across for " + fmt2(s.height) +
                     " m of height; this looks like a part of a person (only a torso?): give a "
                     "scan of the whole person, head to feet");
  if ((centroid < 0.45 && topSpan > 0.7 * bottomSpan) || (centroid < 0.5 && topSpan > bottomSpan))
    throw InputError(what + " looks upside down: the surface centroid is at " +
                     fmt2(100 * centroid) + " % of the height and the top end is " +
                     (topSpan > bottomSpan ? "wider" : "narrower") +
                     " than the bottom end; flip the scan so that the head is at +Y");

  // Lateral axis: the shoulders are much wider than deep and barely move when the arms
  // swing; facing is the minor axis of the shoulder slab.
  const Slab torso = slab(s, 0.78, 0.84);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> tEig(torso.cov);
  Eigen::Vector2d d = tEig.eigenvectors().col(0);  // (x, z), smallest variance
  const double anisotropy =
      tEig.eigenvalues()[1] > 0 ? 1.0 - tEig.eigenvalues()[0] / tEig.eigenvalues()[1] : 0.0;

  // Sign cues along d, each positive when +d is the front.
  Orientation result;
  const double feet = feetCue(s, d);
  const double nose = protrusion(s, 0.89, 0.94, d);
  const double chest = protrusion(s, 0.70, 0.74, d);
  const double buttocks = -protrusion(s, 0.46, 0.52, d);
  result.cues = {{"feet", feet}, {"nose", nose}, {"chest", chest}, {"buttocks", buttocks}};
  const double weights[] = {2.0, 1.0, 0.5, 0.5};
  double vote = 0, total = 0;
  for (size_t i = 0; i < result.cues.size(); ++i) {
    vote += weights[i] * result.cues[i].vote;
    total += weights[i] * std::abs(result.cues[i].vote);
  }
  if (vote < 0) {
    d = -d;
    for (auto& c : result.cues) c.vote = -c.vote;
  }
  result.facing = Eigen::Vector3d(d.x(), 0, d.y()).normalized();
  result.yaw = -std::atan2(result.facing.x(), result.facing.z());
  result.confidence = total > 0 ? std::abs(vote) / total * std::min(1.0, 2.0 * anisotropy) : 0.0;
  return result;
}

}  // namespace s2p
