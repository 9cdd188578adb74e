#include "body/measurements.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>
#include <set>

#include "body/plane_section.h"
#include "body/posing.h"
#include "core/error.h"

namespace s2p {
namespace {

using Field = double BodyMeasurements::*;
struct NamedField {
  const char* name;
  Field field;
};
constexpr NamedField kFields[] = {
    {"height", &BodyMeasurements::height},
    {"neck_girth", &BodyMeasurements::neckGirth},
    {"chest_girth", &BodyMeasurements::chestGirth},
    {"under_bust_girth", &BodyMeasurements::underBustGirth},
    {"waist_girth", &BodyMeasurements::waistGirth},
    {"hip_girth", &BodyMeasurements::hipGirth},
    {"thigh_girth", &BodyMeasurements::thighGirth},
    {"upper_arm_girth", &BodyMeasurements::upperArmGirth},
    {"shoulder_width", &BodyMeasurements::shoulderWidth},
    {"arm_length", &BodyMeasurements::armLength},
    {"inseam", &BodyMeasurements::inseam},
};

Field fieldOf(std::string_view name) {
  for (const auto& f : kFields)
    if (name == f.name) return f.field;
  throw InputError(fmt::format("measurements: unknown measurement \"{}\"; known names: {}", name,
                               fmt::join(measurementNames(), ", ")));
}

const Eigen::Vector3d kUp = Eigen::Vector3d::UnitY();

// A girth at one height / plane: NaN when no acceptable loop is there.
struct Sample {
  double at = 0;
  double girth = std::numeric_limits<double>::quiet_NaN();
  bool valid() const { return std::isfinite(girth); }
};

// Takes the measurements of one body; each intermediate height is computed once, on demand.
class Measurer {
 public:
  Measurer(const TriMesh& mesh, const Eigen::MatrixX3d& canonical) : slicer_(mesh), C_(canonical) {
    floor_ = mesh.V.col(1).minCoeff();
    height_ = mesh.V.col(1).maxCoeff() - floor_;
    if (!(height_ > 0))
      throw InputError("measure body: the mesh is flat (zero height); give an upright body");
    // Canonical points of another body (or another frame) would send the searches astray.
    const BoundingBox box = boundingBox(mesh.V);
    const Eigen::Vector3d margin = Eigen::Vector3d::Constant(0.5 * height_);
    for (int c = 0; c < kNumCanonical; ++c) {
      const Eigen::Vector3d p = C_.row(c).transpose();
      if ((p.array() < (box.min - margin).array()).any() ||
          (p.array() > (box.max + margin).array()).any())
        throw InputError(fmt::format(
            "measure body: canonical point '{}' ({:.3f}, {:.3f}, {:.3f}) is far outside the "
            "mesh; give the canonical points of this body, in its frame",
            toString(static_cast<Canonical>(c)), p.x(), p.y(), p.z()));
    }
  }

  double height() const { return height_; }
  double inseam() { return crotch() - floor_; }

  double chestGirth() { return bust().girth; }
  double underBustGirth() { return underBust().girth; }
  double hipGirth() { return hip().girth; }

  double waistGirth() {
    const double lo = hip().at + 0.02 * height_, hi = underBust().at;
    return require(searchTorso(lo, hi, false), "waist girth", lo, hi).girth;
  }

  double thighGirth() {
    const double y = crotch() - 0.03 * height_;
    double best = std::numeric_limits<double>::quiet_NaN();
    for (int side = 0; side < 2; ++side) {
      const Eigen::Vector3d p = legPoint(side, y), other = legPoint(1 - side, y);
      const auto loops = slicer_.section(p, kUp);
      const SectionLoop* loop = outermostAround(loops, p, kUp);
      if (!loop || loopEncloses(*loop, other, kUp) || enclosesArm(*loop, y)) continue;
      const double g = convexHullPerimeter(*loop, kUp);
      if (!(g <= best)) best = g;
    }
    if (!std::isfinite(best))
      throw InputError(fmt::format(
          "measure body: thigh girth: no loop around either thigh at height {:.3f} m (5 cm "
          "below the crotch); are the legs apart and free of the hands?",
          y));
    return best;
  }

  double upperArmGirth() {
    double best = std::numeric_limits<double>::quiet_NaN();
    for (int side = 0; side < 2; ++side) {
      const Eigen::Vector3d s = P(side == 0 ? Canonical::LeftShoulder : Canonical::RightShoulder);
      const Eigen::Vector3d e = P(side == 0 ? Canonical::LeftElbow : Canonical::RightElbow);
      if ((e - s).norm() <= 0) continue;
      const Eigen::Vector3d n = (e - s).normalized();
      for (double t : {0.4, 0.45, 0.5, 0.55, 0.6}) {
        const Eigen::Vector3d p = s + t * (e - s);
        const auto loops = slicer_.section(p, n);
        const SectionLoop* loop = outermostAround(loops, p, n);
        // A loop around a spine joint is the torso (arm pressed to it): skip this plane.
        if (loop && !loopEncloses(*loop, P(Canonical::Spine), n) &&
            !loopEncloses(*loop, P(Canonical::Chest), n) &&
            !loopEncloses(*loop, P(Canonical::Neck), n)) {
          const double g = convexHullPerimeter(*loop, n);
          if (!(g <= best)) best = g;
        }
      }
    }
    if (!std::isfinite(best))
      throw InputError(
          "measure body: upper-arm girth: no section loop winds around either upper-arm bone; "
          "check the shoulder and elbow points");
    return best;
  }

  double neckGirth() {
    const Eigen::Vector3d a = P(Canonical::Neck), b = P(Canonical::Head);
    if (!((b - a).norm() > 0))
      throw InputError("measure body: neck girth: the neck and head points coincide");
    const Eigen::Vector3d n = (b - a).normalized();
    for (double t = 0.35; t <= 0.6 + 1e-9; t += 0.05) {
      const Eigen::Vector3d p = a + t * (b - a);
      const auto loops = slicer_.section(p, n);
      const SectionLoop* loop = outermostAround(loops, p, n);
      if (!loop) continue;
      if (loopEncloses(*loop, P(Canonical::LeftShoulder), n) ||
          loopEncloses(*loop, P(Canonical::RightShoulder), n))
        continue;
      return convexHullPerimeter(*loop, n);
    }
    throw InputError(
        "measure body: neck girth: no loop around the neck between 35 % and 60 % of the "
        "neck→head bone; check the neck and head points");
  }

  double shoulderWidth() { return (acromion(0) - acromion(1)).norm(); }

  double armLength() {
    double sum = 0;
    for (int side = 0; side < 2; ++side) {
      const Eigen::Vector3d e = P(side == 0 ? Canonical::LeftElbow : Canonical::RightElbow);
      const Eigen::Vector3d w = P(side == 0 ? Canonical::LeftWrist : Canonical::RightWrist);
      sum += (acromion(side) - e).norm() + (e - w).norm();
    }
    return 0.5 * sum;
  }

 private:
  Eigen::Vector3d P(Canonical c) const { return C_.row(static_cast<int>(c)).transpose(); }

  static const Sample& require(const std::optional<Sample>& s, const char* what, double lo,
                               double hi) {
    if (!s)
      throw InputError(fmt::format(
          "measure body: {}: no torso section between heights {:.3f} and {:.3f} m winds "
          "around the spine without taking in an arm; is the body upright with its arms away "
          "from the torso?",
          what, lo, hi));
    return *s;
  }

  // The outermost closed loop winding around `p` (projected along `n`), or null.
  static const SectionLoop* outermostAround(const std::vector<SectionLoop>& loops,
                                            const Eigen::Vector3d& p, const Eigen::Vector3d& n) {
    const SectionLoop* best = nullptr;
    double bestArea = -1;
    for (const auto& loop : loops)
      if (loopEncloses(loop, p, n)) {
        const double area = enclosedArea(loop, n);
        if (area > bestArea) best = &loop, bestArea = area;
      }
    return best;
  }

  // The point at height y on the polyline through `chain` (sorted by height; clamped).
  Eigen::Vector3d pointAtHeight(std::vector<Eigen::Vector3d> chain, double y) const {
    std::sort(chain.begin(), chain.end(),
              [](const auto& a, const auto& b) { return a.y() < b.y(); });
    Eigen::Vector3d p = chain.front();
    if (y >= chain.back().y()) p = chain.back();
    for (size_t i = 0; i + 1 < chain.size(); ++i)
      if (y >= chain[i].y() && y <= chain[i + 1].y()) {
        const double dy = chain[i + 1].y() - chain[i].y();
        const double t = dy > 0 ? (y - chain[i].y()) / dy : 0.0;
        p = chain[i] + t * (chain[i + 1] - chain[i]);
        break;
      }
    p.y() = y;
    return p;
  }

  // On the spine (pelvis → spine → chest → neck) at height y.
  Eigen::Vector3d torsoPoint(double y) const {
    return pointAtHeight(
        {P(Canonical::Pelvis), P(Canonical::Spine), P(Canonical::Chest), P(Canonical::Neck)}, y);
  }

  // On the thigh bone (hip → knee) at height y; the hip joint above it.
  Eigen::Vector3d legPoint(int side, double y) const {
    const Eigen::Vector3d hip = P(side == 0 ? Canonical::LeftHip : Canonical::RightHip);
    const Eigen::Vector3d knee = P(side == 0 ? Canonical::LeftKnee : Canonical::RightKnee);
    return pointAtHeight({knee, hip}, y);
  }

  // Points on the arm bones that a horizontal plane at height y cuts through the arm: where a
  // bone crosses y, and along a bone lying (T-pose) less than 0.04 H above y.
  std::vector<Eigen::Vector3d> armPoints(double y) const {
    using C = Canonical;
    const C chains[2][4] = {{C::LeftShoulder, C::LeftElbow, C::LeftWrist, C::LeftHandTip},
                            {C::RightShoulder, C::RightElbow, C::RightWrist, C::RightHandTip}};
    std::vector<Eigen::Vector3d> pts;
    for (const auto& chain : chains)
      for (int i = 0; i < 3; ++i) {
        const Eigen::Vector3d a = P(chain[i]), b = P(chain[i + 1]);
        const double lo = std::min(a.y(), b.y()), hi = std::max(a.y(), b.y());
        if (y >= lo && y <= hi && hi > lo) {
          const double t = (y - a.y()) / (b.y() - a.y());
          pts.push_back(a + t * (b - a));
        } else if (lo > y && lo - y < 0.04 * height_) {
          // Skip the upper arm's first quarter: inside the torso at the shoulder.
          for (int k = i == 0 ? 2 : 0; k <= 8; ++k) {
            Eigen::Vector3d q = a + (k / 8.0) * (b - a);
            if (q.y() - y < 0.04 * height_) pts.push_back(q);
          }
        }
      }
    return pts;
  }

  bool enclosesArm(const SectionLoop& loop, double y) const {
    for (const auto& q : armPoints(y))
      if (loopEncloses(loop, q, kUp)) return true;
    return false;
  }

  // The torso girth at height y, NaN when there is no torso loop or it takes in an arm.
  Sample torsoAt(double y) const {
    Sample s{y};
    const Eigen::Vector3d p = torsoPoint(y);
    const auto loops = slicer_.section(p, kUp);
    const SectionLoop* loop = outermostAround(loops, p, kUp);
    if (loop && !enclosesArm(*loop, y)) s.girth = convexHullPerimeter(*loop, kUp);
    return s;
  }

  // Largest (or smallest) valid torso girth for heights in [lo, hi]: samples every
  // 0.004 H, then golden-section refinement around the best sample.
  std::optional<Sample> searchTorso(double lo, double hi, bool largest) const {
    if (hi < lo) std::swap(lo, hi);
    const int n = std::clamp(static_cast<int>(std::ceil((hi - lo) / (0.004 * height_))), 2, 1000);
    const double h = (hi - lo) / n;
    auto better = [&](const Sample& a, const Sample& b) {  // a better than b
      if (!a.valid()) return false;
      if (!b.valid()) return true;
      return largest ? a.girth > b.girth : a.girth < b.girth;
    };
    Sample best;
    for (int i = 0; i <= n; ++i) {
      const Sample s = torsoAt(lo + i * h);
      if (better(s, best)) best = s;
    }
    if (!best.valid()) return std::nullopt;
    double a = std::max(lo, best.at - h), b = std::min(hi, best.at + h);
    const double g = 0.5 * (std::sqrt(5.0) - 1);
    Sample c = torsoAt(b - g * (b - a)), d = torsoAt(a + g * (b - a));
    for (int it = 0; it < 12; ++it) {
      if (better(c, d) || (!d.valid() && !c.valid())) {
        b = d.at;
        d = c;
        c = torsoAt(b - g * (b - a));
      } else {
        a = c.at;
        c = d;
        d = torsoAt(a + g * (b - a));
      }
      if (better(c, best)) best = c;
      if (better(d, best)) best = d;
    }
    return best;
  }

  double armpit() {
    if (armpit_) return *armpit_;
    const double top = std::max(P(Canonical::LeftShoulder).y(), P(Canonical::RightShoulder).y());
    const double bottom = std::min(P(Canonical::Spine).y(), top);
    const double h = 0.005 * height_;
    auto free = [&](double y) { return torsoAt(y).valid(); };
    double y = top;
    if (free(y)) return *(armpit_ = top);
    while (y - h > bottom && !free(y - h)) y -= h;
    if (y - h <= bottom) return *(armpit_ = P(Canonical::Chest).y());  // arms never free
    double taken = y, freeY = y - h;  // bisect the first free height
    for (int it = 0; it < 8; ++it) {
      const double mid = 0.5 * (taken + freeY);
      (free(mid) ? freeY : taken) = mid;
    }
    return *(armpit_ = freeY);
  }

  const Sample& bust() {
    if (!bust_) {
      const double hi = armpit();
      const double lo = std::min(P(Canonical::Chest).y(), hi) - 0.05 * height_;
      bust_ = searchTorso(lo, hi, true);
      require(bust_, "chest girth", lo, hi);
    }
    return *bust_;
  }

  const Sample& underBust() {
    if (!underBust_) {
      const double lo = bust().at - 0.06 * height_, hi = bust().at - 0.02 * height_;
      underBust_ = searchTorso(lo, hi, false);
      require(underBust_, "under-bust girth", lo, hi);
    }
    return *underBust_;
  }

  const Sample& hip() {
    if (!hip_) {
      const double hipJoints = 0.5 * (P(Canonical::LeftHip).y() + P(Canonical::RightHip).y());
      const double lo = crotch() + 0.01 * height_;
      const double hi = std::max(hipJoints + 0.02 * height_, crotch() + 0.05 * height_);
      hip_ = searchTorso(lo, hi, true);
      require(hip_, "hip girth", lo, hi);
    }
    return *hip_;
  }

  // Are the two legs' bone points in one section loop at height y?
  bool legsJoined(double y) const {
    const Eigen::Vector3d l = legPoint(0, y), r = legPoint(1, y);
    const auto loops = slicer_.section(l, kUp);
    const SectionLoop* loop = outermostAround(loops, l, kUp);
    return loop && loopEncloses(*loop, r, kUp);
  }

  double crotch() {
    if (crotch_) return *crotch_;
    double split = 0.5 * (P(Canonical::LeftKnee).y() + P(Canonical::RightKnee).y());
    double joined = P(Canonical::Pelvis).y();
    if (!legsJoined(joined)) joined = std::max(joined, P(Canonical::Spine).y());
    if (legsJoined(split) || !legsJoined(joined))
      throw InputError(fmt::format(
          "measure body: crotch: the legs are not apart at the knees (height {:.3f} m) or not "
          "joined at the pelvis (height {:.3f} m); give an upright body with its legs apart",
          split, joined));
    while (joined - split > 1e-4) {
      const double mid = 0.5 * (split + joined);
      (legsJoined(mid) ? joined : split) = mid;
    }
    return *(crotch_ = 0.5 * (split + joined));
  }

  // Shoulder point: the first surface point straight above the shoulder joint.
  Eigen::Vector3d acromion(int side) {
    if (acromion_[side]) return *acromion_[side];
    const Eigen::Vector3d s = P(side == 0 ? Canonical::LeftShoulder : Canonical::RightShoulder);
    const TriMesh& m = slicer_.mesh();
    double best = std::numeric_limits<double>::infinity();
    for (int f = 0; f < m.numFaces(); ++f) {
      const Eigen::Vector3d a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
      // Barycentric coordinates of (s.x, s.z) in the triangle projected on the xz plane.
      const double det = (b.x() - a.x()) * (c.z() - a.z()) - (c.x() - a.x()) * (b.z() - a.z());
      if (det == 0) continue;
      const double u =
          ((s.x() - a.x()) * (c.z() - a.z()) - (c.x() - a.x()) * (s.z() - a.z())) / det;
      const double v =
          ((b.x() - a.x()) * (s.z() - a.z()) - (s.x() - a.x()) * (b.z() - a.z())) / det;
      if (u < 0 || v < 0 || u + v > 1) continue;
      const double y = a.y() + u * (b.y() - a.y()) + v * (c.y() - a.y());
      if (y > s.y() && y < best) best = y;
    }
    Eigen::Vector3d p = s;
    if (std::isfinite(best)) p.y() = best;
    return *(acromion_[side] = p);
  }

  MeshSlicer slicer_;
  const Eigen::MatrixX3d& C_;
  double floor_ = 0, height_ = 0;
  std::optional<double> armpit_, crotch_;
  std::optional<Sample> bust_, underBust_, hip_;
  std::optional<Eigen::Vector3d> acromion_[2];
};

// The rest-pose body (θ = 0, no translation) at shape β.
BodyMeasurements measureRest(const Poser& poser, const Eigen::VectorXd& shape,
                             const MeasureOptions& options) {
  const BodyModel& model = poser.model();
  if (shape.size() != model.numShapes())
    throw InputError(
        fmt::format("measure rest body: {} shape parameters given, body model \"{}\" has {}",
                    shape.size(), model.source, model.numShapes()));
  const PosedBody body = poser.pose({shape, BodyPose::zero(model.numJoints())});
  return measureBody(body.mesh, body.canonical, options);
}

}  // namespace

const std::vector<std::string>& measurementNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (const auto& f : kFields) n.emplace_back(f.name);
    return n;
  }();
  return names;
}

double& measurementField(BodyMeasurements& m, std::string_view name) {
  return m.*fieldOf(name);
}
double measurementField(const BodyMeasurements& m, std::string_view name) {
  return m.*fieldOf(name);
}

BodyMeasurements measureBody(const TriMesh& mesh, const Eigen::MatrixX3d& canonical,
                             const MeasureOptions& options) {
  if (canonical.rows() != kNumCanonical || !canonical.allFinite())
    throw InputError(
        fmt::format("measure body: the canonical points must be a finite {}×3 matrix (one row per "
                    "Canonical), got {} rows",
                    kNumCanonical, canonical.rows()));
  std::set<std::string_view> wanted;
  for (const auto& name : options.only) {
    fieldOf(name);
    wanted.insert(name);
  }
  auto want = [&](std::string_view name) { return wanted.empty() || wanted.count(name) > 0; };
  Measurer m(mesh, canonical);
  BodyMeasurements out;
  if (want("height")) out.height = m.height();
  if (want("inseam")) out.inseam = m.inseam();
  if (want("chest_girth")) out.chestGirth = m.chestGirth();
  if (want("under_bust_girth")) out.underBustGirth = m.underBustGirth();
  if (want("hip_girth")) out.hipGirth = m.hipGirth();
  if (want("waist_girth")) out.waistGirth = m.waistGirth();
  if (want("thigh_girth")) out.thighGirth = m.thighGirth();
  if (want("upper_arm_girth")) out.upperArmGirth = m.upperArmGirth();
  if (want("neck_girth")) out.neckGirth = m.neckGirth();
  if (want("shoulder_width")) out.shoulderWidth = m.shoulderWidth();
  if (want("arm_length")) out.armLength = m.armLength();
  return out;
}

nlohmann::json toJson(const BodyMeasurements& m) {
  nlohmann::json j = nlohmann::json::object();
  nlohmann::json cm = nlohmann::json::object();
  j["units"] = "m";
  for (const auto& f : kFields)
    if (std::isfinite(m.*f.field)) {
      j[f.name] = m.*f.field;
      cm[f.name] = std::round(m.*f.field * 1000.0) / 10.0;
    }
  j["cm"] = cm;
  return j;
}

BodyMeasurements measurementsFromJson(const nlohmann::json& json) {
  if (!json.is_object())
    throw InputError(fmt::format("measurements JSON: expected an object of name → metres, got {}",
                                 json.type_name()));
  BodyMeasurements m;
  for (const auto& [key, value] : json.items()) {
    if (key == "cm") continue;
    if (key == "units") {
      if (!value.is_string() || value.get<std::string>() != "m")
        throw InputError(
            "measurements JSON: \"units\" must be \"m\" (top-level values are metres)");
      continue;
    }
    double& field = m.*fieldOf(key);
    if (!value.is_number() || !std::isfinite(value.get<double>()) || value.get<double>() <= 0)
      throw InputError(
          fmt::format("measurements JSON: \"{}\" must be a positive number of metres, got {}", key,
                      value.dump()));
    field = value.get<double>();
  }
  return m;
}

MeasurementTargets toTargets(const BodyMeasurements& m) {
  MeasurementTargets t;
  for (const auto& f : kFields)
    if (std::isfinite(m.*f.field)) t.values[f.name] = m.*f.field;
  return t;
}

BodyMeasurements measureRestBody(const BodyModel& model, const Eigen::VectorXd& shape,
                                 const MeasureOptions& options) {
  model.validate();
  return measureRest(Poser(model), shape, options);
}

Eigen::VectorXd fitShapeToMeasurements(const BodyModel& model, const MeasurementTargets& targets,
                                       const MeasurementFitOptions& options) {
  model.validate();
  const Poser poser(model);
  const int ns = model.numShapes();
  if (ns == 0)
    throw InputError(fmt::format(
        "fit shape to measurements: body model \"{}\" has no shape parameters", model.source));
  if (targets.values.empty())
    throw InputError("fit shape to measurements: no target measurements given");
  MeasureOptions measure;
  std::vector<std::string> names;
  Eigen::VectorXd target(static_cast<Eigen::Index>(targets.values.size()));
  for (const auto& [name, value] : targets.values) {
    fieldOf(name);
    if (!std::isfinite(value) || value <= 0)
      throw InputError(fmt::format(
          "fit shape to measurements: target \"{}\" = {} is not a positive number of metres", name,
          value));
    target(static_cast<Eigen::Index>(names.size())) = value;
    names.push_back(name);
  }
  measure.only = names;
  const int nt = static_cast<int>(names.size());

  Eigen::VectorXd lo(ns), hi(ns);
  for (int s = 0; s < ns; ++s) {
    const bool named = s < static_cast<int>(model.shapeParams.size());
    lo(s) = named ? model.shapeParams[s].min : -5.0;
    hi(s) = named ? model.shapeParams[s].max : 5.0;
  }
  auto clampToRange = [&](const Eigen::VectorXd& b) -> Eigen::VectorXd {
    return b.cwiseMax(lo).cwiseMin(hi);
  };
  auto measured = [&](const Eigen::VectorXd& beta) {
    const BodyMeasurements m = measureRest(poser, beta, measure);
    Eigen::VectorXd r(nt);
    for (int i = 0; i < nt; ++i) r(i) = measurementField(m, names[i]);
    return r;
  };
  const double mu = options.regularization;
  auto cost = [&](const Eigen::VectorXd& r, const Eigen::VectorXd& beta) {
    return r.squaredNorm() + mu * beta.squaredNorm();
  };

  if (options.initial.size() != 0 && options.initial.size() != ns)
    throw InputError(
        fmt::format("fit shape to measurements: the initial shape has {} values, the model has {}",
                    options.initial.size(), ns));
  Eigen::VectorXd beta = options.initial.size() == ns && options.initial.allFinite()
                             ? clampToRange(options.initial)
                             : Eigen::VectorXd::Zero(ns);
  Eigen::VectorXd r = measured(beta) - target;
  double lambda = 1e-3;
  for (int it = 0; it < options.maxIterations; ++it) {
    if (r.cwiseAbs().maxCoeff() < options.tolerance) break;
    Eigen::MatrixXd J(nt, ns);  // ∂measurement/∂β, central differences inside the range
    for (int s = 0; s < ns; ++s) {
      Eigen::VectorXd bp = beta, bm = beta;
      bp(s) = std::min(hi(s), beta(s) + options.step);
      bm(s) = std::max(lo(s), beta(s) - options.step);
      J.col(s) = (measured(bp) - measured(bm)) / (bp(s) - bm(s));
    }
    const Eigen::MatrixXd JtJ = J.transpose() * J + mu * Eigen::MatrixXd::Identity(ns, ns);
    const Eigen::VectorXd g = J.transpose() * r + mu * beta;
    bool improved = false;
    for (int tries = 0; tries < 10 && !improved; ++tries) {
      Eigen::MatrixXd A = JtJ;
      A.diagonal() += lambda * JtJ.diagonal().cwiseMax(1e-12);
      const Eigen::VectorXd next = clampToRange(beta - A.ldlt().solve(g));
      Eigen::VectorXd rNext;
      try {  // a trial shape the measurements cannot be taken on is a rejected step
        rNext = measured(next) - target;
      } catch (const InputError&) {
        lambda *= 10;
        continue;
      }
      if (next.allFinite() && rNext.allFinite() && cost(rNext, next) < cost(r, beta)) {
        beta = next;
        r = rNext;
        lambda = std::max(lambda / 10, 1e-9);
        improved = true;
      } else {
        lambda *= 10;
      }
    }
    if (!improved) break;  // at a (bounded) minimum: the targets may be unreachable
  }
  return beta;
}

}  // namespace s2p
