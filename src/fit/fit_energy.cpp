#include "fit/fit_energy.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <mutex>
#include <numbers>
#include <string>

#include "core/error.h"

namespace s2p {

int Correspondences::numOutside() const {
  int n = 0;
  for (FitSide s : side) n += s == FitSide::Outside;
  return n;
}

int Correspondences::numInside() const {
  int n = 0;
  for (FitSide s : side) n += s == FitSide::Inside;
  return n;
}

ScanTarget::ScanTarget(const TriMesh& scan)
    : mesh_(scan), query_(scan), faceNormals_(s2p::faceNormals(scan)) {}

Correspondences findCorrespondences(const ScanTarget& scan, const TriMesh& body,
                                    const CorrespondenceOptions& opt,
                                    const std::vector<int>* subset) {
  const int n = body.numVertices();
  std::vector<int> all;
  if (!subset) {
    all.resize(n);
    for (int i = 0; i < n; ++i) all[i] = i;
  }
  const std::vector<int>& use = subset ? *subset : all;
  const int m = static_cast<int>(use.size());
  Correspondences c;
  c.closest = body.V;
  c.distance = Eigen::VectorXd::Zero(n);
  c.side.assign(n, FitSide::Ignored);
  c.winding = Eigen::VectorXd::Zero(n);
  c.face.assign(n, -1);
  c.sampled = m;
  Eigen::MatrixX3d P(m, 3);
  for (int k = 0; k < m; ++k) {
    if (use[k] < 0 || use[k] >= n)
      throw InputError("correspondences: vertex " + std::to_string(use[k]) + " out of range");
    P.row(k) = body.V.row(use[k]);
  }
  const std::vector<ClosestHit> hits = scan.query().closestPoints(P);
  const Eigen::VectorXd wn = scan.query().windingNumbers(P);
  const Eigen::MatrixX3d N = vertexNormals(body);
  for (int k = 0; k < m; ++k) {
    const int i = use[k];
    const ClosestHit& h = hits[k];
    c.closest.row(i) = h.point.transpose();
    c.distance[i] = h.distance;
    c.winding[i] = wn[k];
    c.face[i] = h.face;
    const bool inside = wn[k] > 0.5;
    if (opt.normalTest && N.row(i).dot(scan.faceNormals().row(h.face)) <= 0) continue;
    if (h.distance > (inside ? opt.pruneInside : opt.pruneOutside)) continue;
    c.side[i] = inside ? FitSide::Inside : FitSide::Outside;
  }
  return c;
}

struct FitEnergy::HitCache {
  std::mutex mutex;
  bool valid = false;
  Eigen::VectorXd params;        // packParams of the evaluation point
  std::vector<ClosestHit> hits;  // per active vertex
};

JointLimits defaultJointLimits(const BodyModel& model) {
  const int nj = model.numJoints();
  JointLimits l;
  l.lower = Eigen::MatrixX3d::Constant(nj, 3, -0.9 * std::numbers::pi);
  l.upper = -l.lower;
  auto jointOf = [&](Canonical c) { return model.canonical[static_cast<int>(c)].joint; };
  for (Canonical c : {Canonical::LeftKnee, Canonical::RightKnee}) {
    const int j = jointOf(c);
    if (j < 0) continue;
    l.lower.row(j) = Eigen::RowVector3d(-0.2, -0.3, -0.3);  // +x bends the shin backwards
    l.upper.row(j) = Eigen::RowVector3d(2.7, 0.3, 0.3);
  }
  for (Canonical c : {Canonical::Spine, Canonical::Chest, Canonical::Neck, Canonical::Head}) {
    const int j = jointOf(c);
    if (j <= 0) continue;
    l.lower.row(j).setConstant(-0.8);
    l.upper.row(j).setConstant(0.8);
  }
  if (nj > 0) {
    l.lower.row(0).setConstant(-1e9);
    l.upper.row(0).setConstant(1e9);
  }
  return l;
}

FitEnergy::FitEnergy(const Poser& poser, const ScanTarget& scan, const BodyParams& initial,
                     const FitWeights& weights, JointLimits limits)
    : poser_(poser),
      scan_(scan),
      initial_(initial),
      w_(weights),
      limits_(std::move(limits)),
      cache_(std::make_shared<HitCache>()) {
  const BodyModel& m = poser_.model();
  if (initial_.shape.size() == 0) initial_.shape = Eigen::VectorXd::Zero(m.numShapes());
  if (initial_.shape.size() != m.numShapes() || initial_.pose.axisAngle.rows() != m.numJoints())
    throw InputError("fit energy: the initial parameters do not match the body model " + m.source);
  if (limits_.lower.rows() != m.numJoints() || limits_.upper.rows() != m.numJoints())
    throw InputError("fit energy: joint limits must have one row per joint of " + m.source);
  // β_s is measured by the RMS vertex displacement it causes, in units of shapeRms: the prior
  // then means the same for every body source whatever its parameters' units.
  shapeScale_.resize(m.numShapes());
  for (int s = 0; s < m.numShapes(); ++s) {
    const double rms = m.shapeDirs.col(s).norm() / std::sqrt(std::max(1, m.numVertices()));
    shapeScale_[s] = rms > 0 ? rms / w_.shapeRms : 1.0;
  }
  corr_.closest = Eigen::MatrixX3d::Zero(m.numVertices(), 3);
  corr_.distance = Eigen::VectorXd::Zero(m.numVertices());
  corr_.side.assign(m.numVertices(), FitSide::Ignored);
  corr_.sampled = m.numVertices();
}

void FitEnergy::setCorrespondences(Correspondences c) {
  const int nv = poser_.model().numVertices();
  if (c.closest.rows() != nv || static_cast<int>(c.side.size()) != nv)
    throw InputError("fit energy: correspondences for " + std::to_string(c.closest.rows()) +
                     " vertices, the body has " + std::to_string(nv));
  corr_ = std::move(c);
  {
    const std::lock_guard<std::mutex> lock(cache_->mutex);
    cache_->valid = false;
  }
  active_.clear();
  for (int i = 0; i < nv; ++i)
    if (corr_.side[i] != FitSide::Ignored) active_.push_back(i);
}

int FitEnergy::numResiduals() const {
  const BodyModel& m = poser_.model();
  return m.numVertices() + m.numShapes() + 6 * (m.numJoints() - 1);
}

int FitEnergy::numCompactResiduals() const {
  const BodyModel& m = poser_.model();
  return static_cast<int>(active_.size()) + m.numShapes() + 6 * (m.numJoints() - 1);
}

void FitEnergy::evaluate(const BodyParams& params, Eigen::VectorXd* r, Eigen::MatrixXd* J,
                         bool needShapeAndPose) const {
  evaluateRows(params, r, J, needShapeAndPose, false);
}

void FitEnergy::evaluateCompact(const BodyParams& params, Eigen::VectorXd* r, Eigen::MatrixXd* J,
                                bool needShapeAndPose) const {
  evaluateRows(params, r, J, needShapeAndPose, true);
}

void FitEnergy::evaluateRows(const BodyParams& params, Eigen::VectorXd* r, Eigen::MatrixXd* J,
                             bool needShapeAndPose, bool compact) const {
  const BodyModel& m = poser_.model();
  const int ns = m.numShapes(), nj = m.numJoints();
  const int nv = compact ? static_cast<int>(active_.size()) : m.numVertices();  // data rows
  const int numRows = compact ? numCompactResiduals() : numResiduals();
  const int P = poser_.numParams();
  const PosedBody body = poser_.pose(params);
  const double scale = w_.referenceVertices / std::max(1, corr_.sampled);
  const double sOut = std::sqrt(w_.out * scale), sIn = std::sqrt(w_.in * scale);
  const double sig = w_.gmSigma, sig2 = sig * sig;

  r->setZero(numRows);
  const int na = static_cast<int>(active_.size());
  Eigen::MatrixXd Jv;  // (3·#active)×P
  if (J) {
    J->setZero(numRows, P);
    if (needShapeAndPose && na > 0) Jv = poser_.vertexJacobian(params, active_);
  }
  // Closest scan points of the active vertices at this evaluation point (BSE recomputes the
  // distances at every evaluation; only the side and the pruning stay fixed per ICP step).
  // The faces found with the correspondences are hints that make the search short.
  Eigen::MatrixX3d Pa(na, 3);
  std::vector<int> hints(na, -1);
  const bool haveFaces = static_cast<int>(corr_.face.size()) == m.numVertices();
  for (int a = 0; a < na; ++a) {
    Pa.row(a) = body.mesh.V.row(active_[a]);
    if (haveFaces) hints[a] = corr_.face[active_[a]];
  }
  const Eigen::VectorXd key = packParams(params);
  std::vector<ClosestHit> hits;
  {
    const std::lock_guard<std::mutex> lock(cache_->mutex);
    if (cache_->valid && cache_->params.size() == key.size() && cache_->params == key)
      hits = cache_->hits;
  }
  if (static_cast<int>(hits.size()) != na) {
    hits = scan_.query().closestPoints(Pa, hints);
    const std::lock_guard<std::mutex> lock(cache_->mutex);
    cache_->params = key;
    cache_->hits = hits;
    cache_->valid = true;
  }
  tbb::parallel_for(0, na, [&](int a) {
    const int i = active_[a];
    const int row = compact ? a : i;
    const Eigen::Vector3d d = Pa.row(a).transpose() - hits[a].point;
    const double dist = d.norm();
    double value, slope;  // residual and its derivative with respect to the distance
    if (corr_.side[i] == FitSide::Outside) {
      value = sOut * dist;
      slope = sOut;
    } else {
      // √GM: r = √λ · σ·|d|/√(σ² + |d|²), so r² = λ·GM(|d|²).
      const double q = sig2 + dist * dist;
      value = sIn * sig * dist / std::sqrt(q);
      slope = sIn * sig * sig2 / (q * std::sqrt(q));
    }
    (*r)[row] = value;
    if (!J || dist < 1e-12) return;
    const Eigen::RowVector3d g = (slope / dist) * d.transpose();  // ∂r/∂v: the distance gradient
    if (needShapeAndPose)
      J->row(row) = g * Jv.middleRows<3>(3 * a);
    else
      J->block<1, 3>(row, P - 3) = g;
  });

  int row = nv;
  const Eigen::VectorXd beta = params.shape.size() ? params.shape : Eigen::VectorXd::Zero(ns);
  const double sShape = std::sqrt(w_.shape), sPose = std::sqrt(w_.pose),
               sLim = std::sqrt(w_.limits);
  for (int s = 0; s < ns; ++s, ++row) {
    (*r)[row] = sShape * shapeScale_[s] * beta[s];
    if (J) (*J)(row, s) = sShape * shapeScale_[s];
  }
  for (int j = 1; j < nj; ++j)
    for (int k = 0; k < 3; ++k, ++row) {
      (*r)[row] = sPose * (params.pose.axisAngle(j, k) - initial_.pose.axisAngle(j, k));
      if (J) (*J)(row, ns + 3 * j + k) = sPose;
    }
  for (int j = 1; j < nj; ++j)
    for (int k = 0; k < 3; ++k, ++row) {
      const double x = params.pose.axisAngle(j, k);
      if (x > limits_.upper(j, k)) {
        (*r)[row] = sLim * (x - limits_.upper(j, k));
        if (J) (*J)(row, ns + 3 * j + k) = sLim;
      } else if (x < limits_.lower(j, k)) {
        (*r)[row] = sLim * (x - limits_.lower(j, k));
        if (J) (*J)(row, ns + 3 * j + k) = sLim;
      }
    }
}

FitEnergyTerms FitEnergy::terms(const BodyParams& params) const {
  const BodyModel& m = poser_.model();
  Eigen::VectorXd r;
  evaluate(params, &r, nullptr);
  FitEnergyTerms t;
  const int nv = m.numVertices(), ns = m.numShapes(), np = 3 * (m.numJoints() - 1);
  for (int i = 0; i < nv; ++i) {
    const double e = r[i] * r[i];
    if (corr_.side[i] == FitSide::Outside) t.out += e;
    if (corr_.side[i] == FitSide::Inside) t.in += e;
  }
  t.shape = r.segment(nv, ns).squaredNorm();
  t.pose = r.segment(nv + ns, np).squaredNorm();
  t.limits = r.segment(nv + ns + np, np).squaredNorm();
  return t;
}

Eigen::VectorXd packParams(const BodyParams& p) {
  const int ns = static_cast<int>(p.shape.size()), nj = static_cast<int>(p.pose.axisAngle.rows());
  Eigen::VectorXd x(ns + 3 * nj + 3);
  x.head(ns) = p.shape;
  for (int j = 0; j < nj; ++j) x.segment<3>(ns + 3 * j) = p.pose.axisAngle.row(j).transpose();
  x.tail<3>() = p.pose.translation;
  return x;
}

BodyParams unpackParams(const BodyModel& model, const Eigen::VectorXd& x) {
  const int ns = model.numShapes(), nj = model.numJoints();
  if (x.size() != ns + 3 * nj + 3)
    throw InputError("fit: parameter vector of size " + std::to_string(x.size()) + " for " +
                     model.source + " (expects " + std::to_string(ns + 3 * nj + 3) + ")");
  BodyParams p;
  p.shape = x.head(ns);
  p.pose = BodyPose::zero(nj);
  for (int j = 0; j < nj; ++j) p.pose.axisAngle.row(j) = x.segment<3>(ns + 3 * j).transpose();
  p.pose.translation = x.tail<3>();
  return p;
}

}  // namespace s2p
