#include "fit/pose_init.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <optional>
#include <queue>
#include <string>
#include <unordered_map>

#include "body/posing.h"
#include "core/error.h"
#include "core/row_tree.h"
#include "fit/fit_energy.h"

namespace s2p {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Vertex adjacency with edge lengths (CSR), from the faces, plus bridges between pieces.
struct Graph {
  std::vector<int> start, nbr;
  std::vector<double> len;
};

// A scan in pieces (legs seen apart below a skirt, a hand or feet scanned apart): each piece of
// at least kMinBridgedVertices is joined to the nearest vertex of the larger pieces by one edge
// of that length, largest first, so that the geodesic walk from the torso reaches the feet.
// Appends the bridges to `e` (both directions).
void bridgePieces(const TriMesh& m, std::vector<std::pair<int, int>>& e) {
  constexpr int kMinBridgedVertices = 20;
  const int n = m.numVertices();
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const auto& [a, b] : e) parent[find(a)] = find(b);
  std::unordered_map<int, std::vector<int>> pieces;
  for (int v = 0; v < n; ++v) pieces[find(v)].push_back(v);
  if (pieces.size() < 2) return;
  std::vector<const std::vector<int>*> order;
  for (const auto& [root, verts] : pieces)
    if (static_cast<int>(verts.size()) >= kMinBridgedVertices) order.push_back(&verts);
  std::sort(order.begin(), order.end(), [](auto* a, auto* b) {
    return a->size() != b->size() ? a->size() > b->size() : a->front() < b->front();
  });
  std::vector<int> joined;  // the vertices of the pieces joined so far
  const RowCloud cloud{&m.V, &joined};
  for (size_t i = 0; i < order.size(); ++i) {
    if (i > 0) {
      const RowTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
      double best = kInf;
      int from = -1, to = -1;
      for (int v : *order[i]) {
        const Eigen::Vector3d q = m.V.row(v).transpose();
        std::uint32_t j = 0;
        double d2 = 0;
        tree.knnSearch(q.data(), 1, &j, &d2);
        if (d2 < best) best = d2, from = v, to = joined[j];
      }
      e.emplace_back(from, to);
      e.emplace_back(to, from);
    }
    joined.insert(joined.end(), order[i]->begin(), order[i]->end());
  }
}

Graph buildGraph(const TriMesh& m) {
  const int n = m.numVertices();
  std::vector<std::pair<int, int>> e;
  e.reserve(6 * m.numFaces());
  for (int f = 0; f < m.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = m.F(f, k), b = m.F(f, (k + 1) % 3);
      e.emplace_back(a, b);
      e.emplace_back(b, a);
    }
  bridgePieces(m, e);
  std::sort(e.begin(), e.end());
  e.erase(std::unique(e.begin(), e.end()), e.end());
  Graph g;
  g.start.assign(n + 1, 0);
  for (const auto& [a, b] : e) ++g.start[a + 1];
  for (int i = 0; i < n; ++i) g.start[i + 1] += g.start[i];
  g.nbr.resize(e.size());
  g.len.resize(e.size());
  for (size_t i = 0; i < e.size(); ++i) {
    g.nbr[i] = e[i].second;
    g.len[i] = (m.V.row(e[i].first) - m.V.row(e[i].second)).norm();
  }
  return g;
}

// Multi-source Dijkstra along mesh edges (an upper bound of the geodesic distance).
Eigen::VectorXd dijkstra(const Graph& g, const std::vector<int>& sources) {
  const int n = static_cast<int>(g.start.size()) - 1;
  Eigen::VectorXd d = Eigen::VectorXd::Constant(n, kInf);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
  for (int s : sources) {
    d[s] = 0;
    q.emplace(0.0, s);
  }
  while (!q.empty()) {
    const auto [dv, v] = q.top();
    q.pop();
    if (dv > d[v]) continue;
    for (int k = g.start[v]; k < g.start[v + 1]; ++k) {
      const double nd = dv + g.len[k];
      if (nd < d[g.nbr[k]]) {
        d[g.nbr[k]] = nd;
        q.emplace(nd, g.nbr[k]);
      }
    }
  }
  return d;
}

// Centroid of the vertices whose distance lies within ±width/2 of `at`; nullopt when empty.
std::optional<Eigen::Vector3d> ringCentroid(const TriMesh& m, const Eigen::VectorXd& d, double at,
                                            double width) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  int n = 0;
  for (int v = 0; v < m.numVertices(); ++v)
    if (std::abs(d[v] - at) <= 0.5 * width) {
      c += m.V.row(v).transpose();
      ++n;
    }
  if (n == 0) return std::nullopt;
  return Eigen::Vector3d(c / n);
}

Eigen::Vector3d areaCentroid(const TriMesh& m) {
  const Eigen::VectorXd a = faceAreas(m);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int f = 0; f < m.numFaces(); ++f)
    c += a[f] * (m.V.row(m.F(f, 0)) + m.V.row(m.F(f, 1)) + m.V.row(m.F(f, 2))).transpose() / 3.0;
  return a.sum() > 0 ? Eigen::Vector3d(c / a.sum()) : Eigen::Vector3d(m.V.colwise().mean());
}

Eigen::Vector3d row(const Eigen::MatrixX3d& M, Canonical c) {
  return M.row(static_cast<int>(c)).transpose();
}

// Inverse kinematics as one Ceres cost: parameter blocks θ (3#J) and t (3).
class IkCost : public ceres::CostFunction {
 public:
  IkCost(const Poser& poser, const Eigen::VectorXd& shape, const std::vector<JointTarget>& targets,
         double prior, const JointLimits& limits)
      : poser_(poser), shape_(shape), targets_(targets), prior_(std::sqrt(prior)), limits_(limits) {
    const int nj = poser.model().numJoints();
    set_num_residuals(3 * static_cast<int>(targets.size()) + 6 * (nj - 1));
    mutable_parameter_block_sizes()->push_back(3 * nj);
    mutable_parameter_block_sizes()->push_back(3);
  }

  bool Evaluate(double const* const* x, double* residuals, double** jacobians) const override {
    const BodyModel& m = poser_.model();
    const int nj = m.numJoints(), ns = m.numShapes();
    BodyParams p;
    p.shape = shape_;
    p.pose = BodyPose::zero(nj);
    for (int j = 0; j < nj; ++j)
      for (int k = 0; k < 3; ++k) p.pose.axisAngle(j, k) = x[0][3 * j + k];
    p.pose.translation = Eigen::Map<const Eigen::Vector3d>(x[1]);
    const PosedBody body = poser_.pose(p);
    Eigen::MatrixXd Jc;
    if (jacobians) Jc = poser_.canonicalJacobian(p);
    const int nr = num_residuals();
    Eigen::Map<Eigen::VectorXd> r(residuals, nr);
    r.setZero();
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    std::optional<Eigen::Map<RowMajor>> J0, J1;
    if (jacobians && jacobians[0]) J0.emplace(jacobians[0], nr, 3 * nj).setZero();
    if (jacobians && jacobians[1]) J1.emplace(jacobians[1], nr, 3).setZero();
    int rowIdx = 0;
    for (const JointTarget& t : targets_) {
      const int c = static_cast<int>(t.joint);
      const double s = std::sqrt(t.weight);
      r.segment<3>(rowIdx) = s * (body.canonical.row(c).transpose() - t.position);
      if (J0) J0->middleRows(rowIdx, 3) = s * Jc.block(3 * c, ns, 3, 3 * nj);
      if (J1) J1->middleRows(rowIdx, 3) = s * Jc.block(3 * c, ns + 3 * nj, 3, 3);
      rowIdx += 3;
    }
    for (int j = 1; j < nj; ++j)
      for (int k = 0; k < 3; ++k, ++rowIdx) {
        r[rowIdx] = prior_ * p.pose.axisAngle(j, k);
        if (J0) (*J0)(rowIdx, 3 * j + k) = prior_;
      }
    const double sl = std::sqrt(10.0);
    for (int j = 1; j < nj; ++j)
      for (int k = 0; k < 3; ++k, ++rowIdx) {
        const double a = p.pose.axisAngle(j, k);
        const double ex = a > limits_.upper(j, k)   ? a - limits_.upper(j, k)
                          : a < limits_.lower(j, k) ? a - limits_.lower(j, k)
                                                    : 0.0;
        r[rowIdx] = sl * ex;
        if (J0 && ex != 0) (*J0)(rowIdx, 3 * j + k) = sl;
      }
    return r.allFinite();
  }

 private:
  const Poser& poser_;
  Eigen::VectorXd shape_;
  std::vector<JointTarget> targets_;
  double prior_;
  JointLimits limits_;
};

}  // namespace

Extremities findExtremities(const TriMesh& scan, const BodyModel& model,
                            const Eigen::VectorXd& shapeIn, const PoseInitOptions& opt) {
  if (scan.numVertices() < 100)
    throw InputError("pose initialisation: the scan has " + std::to_string(scan.numVertices()) +
                     " vertices, far too few for a person");
  validateMesh(scan, "pose initialisation: scan");
  const Eigen::VectorXd shape =
      shapeIn.size() ? shapeIn : Eigen::VectorXd(Eigen::VectorXd::Zero(model.numShapes()));
  const BoundingBox box = boundingBox(scan.V);
  const double H = box.extent().y(), y0 = box.min.y();

  // Seeds: the torso's band at waist height. The band may also cut an arm (arms down or in an
  // A-pose) or a hand, so it is split into connected pieces and the one with the largest area,
  // the torso, is kept (a vertex median can land on an arm when the arm is finely meshed).
  std::vector<char> inSlab(scan.numVertices(), 0);
  for (int v = 0; v < scan.numVertices(); ++v) {
    const double h = (scan.V(v, 1) - y0) / H;
    inSlab[v] = h >= 0.57 && h <= 0.63;
  }
  std::vector<int> parent(scan.numVertices());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  const Eigen::VectorXd areas = faceAreas(scan);
  for (int f = 0; f < scan.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = scan.F(f, k), b = scan.F(f, (k + 1) % 3);
      if (inSlab[a] && inSlab[b]) parent[find(a)] = find(b);
    }
  std::unordered_map<int, double> pieceArea;
  for (int f = 0; f < scan.numFaces(); ++f)
    if (inSlab[scan.F(f, 0)] && inSlab[scan.F(f, 1)] && inSlab[scan.F(f, 2)])
      pieceArea[find(scan.F(f, 0))] += areas[f];
  if (pieceArea.empty())
    throw InputError("pose initialisation: the scan has no surface at waist height");
  const int torso = std::max_element(pieceArea.begin(), pieceArea.end(), [](auto& a, auto& b) {
                      return a.second < b.second;
                    })->first;
  std::vector<int> seeds;
  for (int v = 0; v < scan.numVertices(); ++v)
    if (inSlab[v] && find(v) == torso) seeds.push_back(v);

  // The head first: the highest point reached from the torso (a standing person's arms and
  // hands stay below the top of the head). Then the geodesic farthest points from the torso and
  // the head: the hands and feet. Taking the head as one more farthest point let a skirt's hem,
  // 0.75 m round from the waist, beat a head 0.70 m up (a scan whose legs are a separate piece).
  const Graph g = buildGraph(scan);
  Eigen::VectorXd dist = dijkstra(g, seeds);
  std::vector<int> ext;
  std::vector<Eigen::VectorXd> fromExt;
  // The vertex reached from the torso with the largest score(v), or −1.
  const auto argmax = [&](auto score) {
    int best = -1;
    for (int v = 0; v < scan.numVertices(); ++v)
      if (std::isfinite(dist[v]) && (best < 0 || score(v) > score(best))) best = v;
    return best;
  };
  // An extremity found: distances are taken from it as well from now on.
  const auto take = [&](int v) {
    ext.push_back(v);
    fromExt.push_back(dijkstra(g, {v}));
    dist = dist.cwiseMin(fromExt.back());
  };
  const int top = argmax([&](int v) { return scan.V(v, 1); });
  if (top < 0 || dist[top] < opt.minSeparation)
    throw InputError(
        "pose initialisation: no head found above the torso on the scan (the highest point lies "
        "less than " +
        std::to_string(opt.minSeparation) +
        " m from the waist); this may not be a standing person");
  take(top);
  for (int k = 1; k < 5; ++k) {
    const int best = argmax([&](int v) { return dist[v]; });
    if (best < 0 || dist[best] < opt.minSeparation)
      throw InputError("pose initialisation: found only " + std::to_string(k) +
                       " extremities (head, hands, feet) separated by " +
                       std::to_string(opt.minSeparation) +
                       " m on the scan; the limbs may touch the body, or this is not a person");
    take(best);
  }

  // Head: the first; feet: the two lowest of the rest; left on +X.
  std::vector<int> order = {1, 2, 3, 4};
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return scan.V(ext[a], 1) < scan.V(ext[b], 1); });
  auto x = [&](int i) { return scan.V(ext[i], 0); };
  int lf = order[0], rf = order[1];
  if (x(lf) < x(rf)) std::swap(lf, rf);
  const int head = 0;
  int lh = order[2], rh = order[3];
  if (x(lh) < x(rh)) std::swap(lh, rh);

  Extremities out;
  auto P = [&](int i) { return Eigen::Vector3d(scan.V.row(ext[i]).transpose()); };
  out.headTop = P(head);
  out.leftHand = P(lh);
  out.rightHand = P(rh);
  out.leftFoot = P(lf);
  out.rightFoot = P(rf);

  // Limb lengths of the shaped model in its rest pose, scaled to the scan's height.
  BodyParams rest;
  rest.shape = shape;
  rest.pose = BodyPose::zero(model.numJoints());
  const PosedBody rb = poseBody(model, rest);
  const double scale = H / boundingBox(rb.mesh.V).extent().y();
  auto len = [&](Canonical a, Canonical b) {
    return scale * (row(rb.canonical, a) - row(rb.canonical, b)).norm();
  };
  struct Chain {
    int ext;
    Canonical tip;
    std::vector<Canonical> joints;  // from the tip inwards
  };
  const std::vector<Chain> chains = {
      {lh, Canonical::LeftHandTip, {Canonical::LeftWrist, Canonical::LeftElbow}},
      {rh, Canonical::RightHandTip, {Canonical::RightWrist, Canonical::RightElbow}},
      {lf, Canonical::LeftToeTip, {Canonical::LeftAnkle, Canonical::LeftKnee}},
      {rf, Canonical::RightToeTip, {Canonical::RightAnkle, Canonical::RightKnee}},
      {head, Canonical::HeadTop, {Canonical::Head}}};
  for (const Chain& c : chains) {
    out.targets.push_back({c.tip, P(c.ext), 0.5});
    double along = 0;
    Canonical prev = c.tip;
    for (Canonical j : c.joints) {
      along += len(prev, j);
      prev = j;
      const bool ankle = j == Canonical::LeftAnkle || j == Canonical::RightAnkle;
      if (auto q = ringCentroid(scan, fromExt[c.ext], along, opt.ringWidth))
        out.targets.push_back({j, *q, ankle ? 0.3 : 1.0});
    }
  }
  return out;
}

BodyParams solveInverseKinematics(const BodyModel& model, const BodyParams& start,
                                  const std::vector<JointTarget>& targets,
                                  const PoseInitOptions& opt) {
  const int nj = model.numJoints();
  if (start.pose.axisAngle.rows() != nj)
    throw InputError("inverse kinematics: the start pose does not match the body model " +
                     model.source);
  if (targets.empty()) throw InputError("inverse kinematics: no joint targets");
  for (const auto& t : targets)
    if (!t.position.allFinite() || !(t.weight >= 0))
      throw InputError(std::string("inverse kinematics: target for ") + toString(t.joint) +
                       " is not finite");
  const Poser poser(model);
  const Eigen::VectorXd shape =
      start.shape.size() ? start.shape : Eigen::VectorXd(Eigen::VectorXd::Zero(model.numShapes()));
  Eigen::VectorXd theta(3 * nj);
  for (int j = 0; j < nj; ++j) theta.segment<3>(3 * j) = start.pose.axisAngle.row(j).transpose();
  Eigen::Vector3d t = start.pose.translation;

  ceres::Problem problem;
  problem.AddResidualBlock(
      new IkCost(poser, shape, targets, opt.posePrior, defaultJointLimits(model)), nullptr,
      theta.data(), t.data());
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = opt.maxIterations;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (summary.termination_type == ceres::FAILURE)
    throw SolverError("inverse kinematics failed: " + summary.message);

  BodyParams out;
  out.shape = shape;
  out.pose = BodyPose::zero(nj);
  for (int j = 0; j < nj; ++j) out.pose.axisAngle.row(j) = theta.segment<3>(3 * j).transpose();
  out.pose.translation = t;
  return out;
}

BodyParams poseFromTargets(const BodyModel& model, const Eigen::VectorXd& shapeIn,
                           const std::vector<JointTarget>& targets, const PoseInitOptions& opt) {
  if (targets.size() < 4)
    throw InputError("pose initialisation: " + std::to_string(targets.size()) +
                     " usable joint targets; at least 4 are needed to pose the body");
  BodyParams start;
  start.shape =
      shapeIn.size() ? shapeIn : Eigen::VectorXd(Eigen::VectorXd::Zero(model.numShapes()));
  start.pose = BodyPose::zero(model.numJoints());
  // Start with the rest body's canonical centroid on the targets' centroid.
  const PosedBody rb = poseBody(model, start);
  Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero();
  for (const auto& t : targets) {
    a += t.position;
    b += row(rb.canonical, t.joint);
  }
  start.pose.translation = (a - b) / static_cast<double>(targets.size());
  return solveInverseKinematics(model, start, targets, opt);
}

BodyParams initialisePose(const TriMesh& scan, const BodyModel& model,
                          const Eigen::VectorXd& shapeIn, const PoseInitOptions& opt) {
  const Eigen::VectorXd shape =
      shapeIn.size() ? shapeIn : Eigen::VectorXd(Eigen::VectorXd::Zero(model.numShapes()));
  return poseFromTargets(model, shape, findExtremities(scan, model, shape, opt).targets, opt);
}

BodyParams poseOnScan(const TriMesh& scan, const BodyModel& model, const BodyPose& pose,
                      const Eigen::VectorXd& shape) {
  BodyParams p;
  p.shape = shape.size() ? shape : Eigen::VectorXd(Eigen::VectorXd::Zero(model.numShapes()));
  p.pose = pose;
  p.pose.translation.setZero();
  p.pose.translation = areaCentroid(scan) - areaCentroid(poseBody(model, p).mesh);
  return p;
}

BodyParams restPoseOnScan(const TriMesh& scan, const BodyModel& model,
                          const Eigen::VectorXd& shape) {
  return poseOnScan(scan, model, BodyPose::zero(model.numJoints()), shape);
}

}  // namespace s2p
