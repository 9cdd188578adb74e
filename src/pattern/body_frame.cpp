#include "pattern/body_frame.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/SparseCore>

#include "core/error.h"
#include "core/mesh_query.h"

namespace s2p {

namespace {

// Number of times the ray o + t·d (t ∈ (0, reach]) crosses the mesh.
int crossings(const MeshQuery& q, Eigen::Vector3d o, const Eigen::Vector3d& d, double reach) {
  int n = 0;
  double travelled = 0;
  for (int guard = 0; guard < 32; ++guard) {
    const auto hit = q.rayCast(o, d, 1e-5, reach - travelled);
    if (!hit) break;
    ++n;
    travelled += hit->t + 1e-5;
    o = hit->point + 1e-5 * d;
  }
  return n;
}

}  // namespace

double armpitHeight(const TriMesh& body, const BodyFrame& frame, bool left) {
  const MeshQuery q(body);
  const Canonical sc = left ? Canonical::LeftShoulder : Canonical::RightShoulder;
  const Eigen::Vector3d shoulder = frame.at(sc);
  const double top = frame.height(shoulder);
  const Eigen::Vector3d d = left ? frame.left() : Eigen::Vector3d(-frame.left());
  const Eigen::Vector3d base =
      frame.at(Canonical::Pelvis) + frame.frontal(shoulder) * frame.front();
  for (double h = top; h > top - 0.35; h -= 0.002) {
    const Eigen::Vector3d o = base + h * frame.up();
    if (crossings(q, o, d, 1.5) >= 3) return h;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

const char* toString(Limb limb) {
  switch (limb) {
    case Limb::Torso: return "torso";
    case Limb::Neck: return "neck";
    case Limb::LeftArm: return "left_arm";
    case Limb::RightArm: return "right_arm";
    case Limb::LeftLeg: return "left_leg";
    case Limb::RightLeg: return "right_leg";
  }
  return "?";
}

BodyFrame::BodyFrame(const Eigen::MatrixX3d& canonical) : canonical_(canonical) {
  if (canonical.rows() != kNumCanonical || !canonical.allFinite())
    throw InputError(fmt::format("pattern: the body's canonical points are {} finite rows, {} "
                                 "expected (a body.json from `fit` has them)",
                                 canonical.rows(), kNumCanonical));
  up_ = (at(Canonical::Neck) - at(Canonical::Pelvis)).normalized();
  const Eigen::Vector3d hips = at(Canonical::LeftHip) - at(Canonical::RightHip);
  left_ = (hips - hips.dot(up_) * up_).normalized();
  front_ = left_.cross(up_);
  if (!up_.allFinite() || !left_.allFinite())
    throw InputError("pattern: the body's canonical points are degenerate (hips or spine of zero "
                     "length)");
}

LimbPlace BodyFrame::placeOn(Limb limb, const Eigen::Vector3d& p) const {
  using C = Canonical;
  std::array<C, 3> chain{};  // every Limb sets it below
  int n = 3;
  switch (limb) {
    case Limb::Torso: chain = {C::Pelvis, C::Neck, C::Neck}; n = 2; break;
    case Limb::Neck: chain = {C::Neck, C::Head, C::Head}; n = 2; break;
    case Limb::LeftArm: chain = {C::LeftShoulder, C::LeftElbow, C::LeftWrist}; break;
    case Limb::RightArm: chain = {C::RightShoulder, C::RightElbow, C::RightWrist}; break;
    case Limb::LeftLeg: chain = {C::LeftHip, C::LeftKnee, C::LeftAnkle}; break;
    case Limb::RightLeg: chain = {C::RightHip, C::RightKnee, C::RightAnkle}; break;
  }
  double total = 0;
  for (int i = 0; i + 1 < n; ++i) total += (at(chain[i + 1]) - at(chain[i])).norm();
  LimbPlace best{limb, std::numeric_limits<double>::infinity(), 0};
  double before = 0;
  for (int i = 0; i + 1 < n; ++i) {
    const Eigen::Vector3d a = at(chain[i]), b = at(chain[i + 1]);
    const double len = (b - a).norm();
    const double u = len > 0 ? std::clamp((p - a).dot(b - a) / (len * len), 0.0, 1.0) : 0.0;
    const double d = (a + u * (b - a) - p).norm();
    if (d < best.distance) {
      best.distance = d;
      best.t = total > 0 ? (before + u * len) / total : 0;
    }
    before += len;
  }
  return best;
}

LimbPlace BodyFrame::nearestLimb(const Eigen::Vector3d& p) const {
  LimbPlace best{Limb::Torso, std::numeric_limits<double>::infinity(), 0};
  for (Limb l : {Limb::Torso, Limb::Neck, Limb::LeftArm, Limb::RightArm, Limb::LeftLeg,
                 Limb::RightLeg}) {
    const LimbPlace q = placeOn(l, p);
    if (q.distance < best.distance) best = q;
  }
  return best;
}

Eigen::MatrixXd limbWeights(const BodyModel& model) {
  using C = Canonical;
  const int nJ = model.numJoints();
  const std::array<std::pair<C, Limb>, 5> roots{{{C::LeftShoulder, Limb::LeftArm},
                                                 {C::RightShoulder, Limb::RightArm},
                                                 {C::LeftHip, Limb::LeftLeg},
                                                 {C::RightHip, Limb::RightLeg},
                                                 {C::Neck, Limb::Neck}}};
  std::vector<Limb> limbOf(static_cast<size_t>(nJ), Limb::Torso);
  for (int j = 0; j < nJ; ++j)
    for (int a = j; a >= 0; a = model.parents[a]) {
      bool found = false;
      for (const auto& [c, limb] : roots)
        if (model.canonical[static_cast<int>(c)].joint == a) {
          limbOf[j] = limb;
          found = true;
        }
      if (found) break;
    }
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(model.numVertices(), 6);
  for (int v = 0; v < model.weights.outerSize(); ++v)
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(model.weights, v); it; ++it)
      out(v, static_cast<int>(limbOf[it.col()])) += it.value();
  return out;
}

}  // namespace s2p
