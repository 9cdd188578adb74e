#include "body/posing.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>

#include "core/error.h"
#include "core/mesh_query.h"

namespace s2p {

namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d K;
  K << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return K;
}

// Coefficients of exp([θ]×) = I + a K + b K² and J_l = I + b K + c K², K = [θ]× (unnormalised);
// Taylor series below |θ| = 1e-2 where the closed forms cancel catastrophically.
struct So3Coefficients {
  double a, b, c;
};

So3Coefficients so3Coefficients(double t2) {
  if (t2 < 1e-4) {
    return {1.0 - t2 / 6.0 + t2 * t2 / 120.0 - t2 * t2 * t2 / 5040.0,
            0.5 - t2 / 24.0 + t2 * t2 / 720.0 - t2 * t2 * t2 / 40320.0,
            1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0 - t2 * t2 * t2 / 362880.0};
  }
  const double t = std::sqrt(t2), s = std::sin(t), c = std::cos(t);
  return {s / t, (1.0 - c) / t2, (t - s) / (t2 * t)};
}

std::string describe(const BodyModel& model) {
  return "body model '" + model.source + "'";
}

// β from params (empty → zeros), checked against the model.
Eigen::VectorXd shapeOf(const BodyModel& model, const Eigen::VectorXd& shape) {
  if (shape.size() == 0) return Eigen::VectorXd::Zero(model.numShapes());
  if (shape.size() != model.numShapes())
    throw InputError(describe(model) + ": shape vector has " + std::to_string(shape.size()) +
                     " entries, the model has " + std::to_string(model.numShapes()) +
                     " shape parameters");
  if (!shape.allFinite()) throw InputError(describe(model) + ": shape vector is not finite");
  return shape;
}

void checkPose(const BodyModel& model, const BodyPose& pose) {
  if (pose.axisAngle.rows() != model.numJoints())
    throw InputError(describe(model) + ": pose has " + std::to_string(pose.axisAngle.rows()) +
                     " joint rotations, the model has " + std::to_string(model.numJoints()) +
                     " joints");
  if (!pose.axisAngle.allFinite() || !pose.translation.allFinite())
    throw InputError(describe(model) + ": pose has non-finite entries");
}

// Forward kinematics state for one pose.
struct Kinematics {
  std::vector<Eigen::Matrix3d> localR;  // #J, R_j = exp([θ_j]×)
  std::vector<Eigen::Matrix3d> worldR;  // #J, accumulated along parents
  std::vector<Eigen::Vector3d> worldT;  // #J, posed joint positions without global translation
  std::vector<Eigen::Vector3d> disp;    // #J, worldT − rest joint (exactly 0 at the rest pose)
  Eigen::VectorXd feature;              // 9(#J−1), (R_j − I) row-major for j ≥ 1
};

Kinematics forwardKinematics(const BodyModel& model, const Eigen::MatrixX3d& joints,
                             const Eigen::MatrixX3d& axisAngle) {
  const int nj = model.numJoints();
  Kinematics k;
  k.localR.resize(nj);
  k.worldR.resize(nj);
  k.worldT.resize(nj);
  k.disp.resize(nj);
  k.feature.resize(9 * (nj - 1));
  for (int j = 0; j < nj; ++j) {
    k.localR[j] = axisAngleToMatrix(axisAngle.row(j).transpose());
    const int p = model.parents[j];
    if (p < 0) {
      k.worldR[j] = k.localR[j];
      k.disp[j].setZero();
    } else {
      k.worldR[j] = k.worldR[p] * k.localR[j];
      k.disp[j] = k.disp[p] + (k.worldR[p] - Eigen::Matrix3d::Identity()) *
                                  (joints.row(j) - joints.row(p)).transpose();
    }
    k.worldT[j] = joints.row(j).transpose() + k.disp[j];
    if (j > 0)
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          k.feature(9 * (j - 1) + 3 * a + b) = k.localR[j](a, b) - (a == b ? 1.0 : 0.0);
  }
  return k;
}

// 3V offsets of the pose-corrected template from rest.V: shapeDirs·β + poseDirs·feature.
Eigen::VectorXd templateOffsets(const BodyModel& model, const Eigen::VectorXd& beta,
                                const Eigen::VectorXd* feature) {
  Eigen::VectorXd off = Eigen::VectorXd::Zero(3 * model.numVertices());
  if (model.numShapes() > 0) off.noalias() += model.shapeDirs * beta;
  if (feature && model.poseDirs.size() != 0) off.noalias() += model.poseDirs * (*feature);
  return off;
}

}  // namespace

// === Rotations

Eigen::Matrix3d axisAngleToMatrix(const Eigen::Vector3d& axisAngle) {
  const So3Coefficients co = so3Coefficients(axisAngle.squaredNorm());
  const Eigen::Matrix3d K = skew(axisAngle);
  return Eigen::Matrix3d::Identity() + co.a * K + co.b * K * K;
}

Eigen::Matrix3d so3LeftJacobian(const Eigen::Vector3d& axisAngle) {
  const So3Coefficients co = so3Coefficients(axisAngle.squaredNorm());
  const Eigen::Matrix3d K = skew(axisAngle);
  return Eigen::Matrix3d::Identity() + co.b * K + co.c * K * K;
}

Eigen::Vector3d matrixToAxisAngle(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(Eigen::Quaterniond(R).normalized());
  double angle = aa.angle();
  Eigen::Vector3d axis = aa.axis();
  if (angle > std::numbers::pi) {  // keep the angle in [0, π]
    angle = 2 * std::numbers::pi - angle;
    axis = -axis;
  }
  return angle * axis;
}

// === Poser

Poser::Poser(const BodyModel& model) : model_(model) {
  const int nj = model.numJoints(), ns = model.numShapes(), nv = model.numVertices();
  if (nj < 1) throw InputError(describe(model) + ": has no joints");
  for (int j = 0; j < nj; ++j)
    if (model.parents[j] >= j || (j > 0 && model.parents[j] < 0) ||
        (j == 0 && model.parents[0] != -1))
      throw InputError(describe(model) + ": joint " + std::to_string(j) + " has parent " +
                       std::to_string(model.parents[j]) +
                       ": the root must be joint 0 and parents must precede their children");
  if (model.jointRegressor.rows() != nj || model.jointRegressor.cols() != nv)
    throw InputError(describe(model) + ": joint regressor is " +
                     std::to_string(model.jointRegressor.rows()) + "×" +
                     std::to_string(model.jointRegressor.cols()) + ", expected #J×#V");
  if (model.shapeDirs.rows() != 3 * nv && ns > 0)
    throw InputError(describe(model) + ": shapeDirs must have 3·#V rows");
  if (model.weights.rows() != nv || model.weights.cols() != nj)
    throw InputError(describe(model) + ": skinning weights must be #V×#J");
  if (model.poseDirs.size() != 0 &&
      (model.poseDirs.rows() != 3 * nv || model.poseDirs.cols() != 9 * (nj - 1)))
    throw InputError(describe(model) + ": poseDirs must be (3#V)×9(#J−1) or empty");
  joints0_ = model.jointRegressor * model.rest.V;
  jointShapeDirs_ = Eigen::MatrixXd::Zero(3 * nj, ns);
  for (int j = 0; j < nj; ++j)
    for (RowSparse::InnerIterator it(model.jointRegressor, j); it; ++it)
      for (int k = 0; k < 3; ++k)
        jointShapeDirs_.row(3 * j + k) += it.value() * model.shapeDirs.row(3 * it.col() + k);
}

int Poser::numParams() const {
  return model_.numShapes() + 3 * model_.numJoints() + 3;
}

Eigen::MatrixX3d Poser::shapedTemplate(const Eigen::VectorXd& shape) const {
  const Eigen::VectorXd off = templateOffsets(model_, shapeOf(model_, shape), nullptr);
  Eigen::MatrixX3d T = model_.rest.V;
  for (int v = 0; v < T.rows(); ++v) T.row(v) += off.segment<3>(3 * v).transpose();
  return T;
}

Eigen::MatrixX3d Poser::restJoints(const Eigen::VectorXd& shape) const {
  const Eigen::VectorXd beta = shapeOf(model_, shape);
  Eigen::MatrixX3d J = joints0_;
  if (beta.size() > 0) {
    const Eigen::VectorXd d = jointShapeDirs_ * beta;
    for (int j = 0; j < J.rows(); ++j) J.row(j) += d.segment<3>(3 * j).transpose();
  }
  return J;
}

PosedBody Poser::pose(const BodyParams& params) const {
  const BodyModel& m = model_;
  const Eigen::VectorXd beta = shapeOf(m, params.shape);
  checkPose(m, params.pose);
  const Eigen::MatrixX3d J = restJoints(beta);
  const Kinematics kin = forwardKinematics(m, J, params.pose.axisAngle);
  const Eigen::Vector3d t = params.pose.translation;
  const int nj = m.numJoints(), nv = m.numVertices();

  PosedBody out;
  out.skinning.resize(nj);
  out.joints.resize(nj, 3);
  for (int j = 0; j < nj; ++j) {
    Eigen::Affine3d A = Eigen::Affine3d::Identity();
    A.linear() = kin.worldR[j];
    A.translation() =
        kin.disp[j] - (kin.worldR[j] - Eigen::Matrix3d::Identity()) * J.row(j).transpose() + t;
    out.skinning[j] = A;
    out.joints.row(j) = (kin.worldT[j] + t).transpose();
  }
  const Eigen::VectorXd off = templateOffsets(m, beta, &kin.feature);
  out.mesh.F = m.rest.F;
  out.mesh.V.resize(nv, 3);
  for (int v = 0; v < nv; ++v) {
    const Eigen::Vector3d x = m.rest.V.row(v).transpose() + off.segment<3>(3 * v);
    // x + Σ w (A x − x) rather than Σ w A x: the rest pose reproduces the template exactly.
    Eigen::Vector3d p = x;
    for (RowSparse::InnerIterator it(m.weights, v); it; ++it) {
      const Eigen::Affine3d& A = out.skinning[it.col()];
      p += it.value() * (A.linear() * x + A.translation() - x);
    }
    out.mesh.V.row(v) = p.transpose();
  }
  out.canonical.resize(kNumCanonical, 3);
  for (int c = 0; c < kNumCanonical; ++c) {
    const CanonicalDef& d = m.canonical[c];
    if (d.joint >= 0 && d.joint < nj) {
      out.canonical.row(c) = out.joints.row(d.joint);
    } else {
      Eigen::RowVector3d p = Eigen::RowVector3d::Zero();
      for (const auto& [v, w] : d.vertices)
        if (v >= 0 && v < nv) p += w * out.mesh.V.row(v);
      out.canonical.row(c) = p;
    }
  }
  return out;
}

Eigen::MatrixXd Poser::vertexJacobian(const BodyParams& params,
                                      const std::vector<int>& vertices) const {
  const BodyModel& m = model_;
  const Eigen::VectorXd beta = shapeOf(m, params.shape);
  checkPose(m, params.pose);
  const int ns = m.numShapes(), nj = m.numJoints(), nv = m.numVertices();
  const int n = static_cast<int>(vertices.size());
  for (int v : vertices)
    if (v < 0 || v >= nv)
      throw InputError(describe(m) + ": Jacobian requested for vertex " + std::to_string(v) +
                       ", the model has " + std::to_string(nv) + " vertices");
  const Eigen::MatrixX3d J = restJoints(beta);
  const Kinematics kin = forwardKinematics(m, J, params.pose.axisAngle);
  const bool correctives = m.poseDirs.size() != 0;

  // Per joint: world axes of its three angle derivatives, Ω_k = R^w_parent · J_l(θ_k) (3×3),
  // and E_j = ∂t_j/∂β − R^w_j ∂J_j/∂β (3×S), the β-derivative of the skinning translation.
  std::vector<Eigen::Matrix3d> omega(nj);
  std::vector<Eigen::MatrixXd> dT(nj), E(nj);
  for (int j = 0; j < nj; ++j) {
    const int p = m.parents[j];
    const Eigen::Matrix3d Jl = so3LeftJacobian(params.pose.axisAngle.row(j).transpose());
    omega[j] = p < 0 ? Jl : Eigen::Matrix3d(kin.worldR[p] * Jl);
    const auto dJ = jointShapeDirs_.middleRows(3 * j, 3);
    if (p < 0)
      dT[j] = dJ;
    else
      dT[j] = dT[p] + kin.worldR[p] * (dJ - jointShapeDirs_.middleRows(3 * p, 3));
    E[j] = dT[j] - kin.worldR[j] * dJ;
  }

  // Many vertices: dense products over all vertices stream memory better than strided rows.
  const bool dense = 8 * n > nv;
  Eigen::VectorXd off;
  RowMatrix shapeRows;  // (3#V)×#S row-major copy when dense
  RowMatrix poseD;      // (3#V)×3(#J−1): poseDirs · ∂feature/∂θ when dense
  std::vector<Eigen::Matrix<double, 9, 3>> D(nj);  // ∂vec(R_k)/∂θ_k
  if (correctives)
    for (int k = 1; k < nj; ++k) {
      const Eigen::Matrix3d Jl = so3LeftJacobian(params.pose.axisAngle.row(k).transpose());
      for (int c = 0; c < 3; ++c) {
        const Eigen::Matrix3d dR = skew(Jl.col(c)) * kin.localR[k];
        for (int a = 0; a < 3; ++a)
          for (int b = 0; b < 3; ++b) D[k](3 * a + b, c) = dR(a, b);
      }
    }
  if (dense) {
    // One pass over poseDirs: per joint, [feature_k | D_k] gives both the template offsets
    // and the corrective derivatives.
    off = Eigen::VectorXd::Zero(3 * nv);
    if (ns > 0) off.noalias() += m.shapeDirs * beta;
    shapeRows = m.shapeDirs;
    if (correctives) {
      poseD.resize(3 * nv, 3 * (nj - 1));
      Eigen::Matrix<double, 9, 4> FD;
      Eigen::Matrix<double, Eigen::Dynamic, 4> tmp(3 * nv, 4);
      for (int k = 1; k < nj; ++k) {
        FD.col(0) = kin.feature.segment<9>(9 * (k - 1));
        FD.rightCols<3>() = D[k];
        tmp.noalias() = m.poseDirs.middleCols(9 * (k - 1), 9) * FD;
        off += tmp.col(0);
        poseD.middleCols(3 * (k - 1), 3) = tmp.rightCols<3>();
      }
    }
  }

  Eigen::MatrixXd jac = Eigen::MatrixXd::Zero(3 * n, numParams());
  // Rows of different vertices are independent: chunks run in parallel, same result.
  tbb::parallel_for(tbb::blocked_range<int>(0, n, 512), [&](const tbb::blocked_range<int>& range) {
    std::vector<Eigen::Vector3d> Q(nj);
    std::vector<double> W(nj, 0.0);
    std::vector<char> touched(nj, 0);
    std::vector<int> list;
    list.reserve(nj);
    Eigen::MatrixXd Eb(3, ns);
    for (int r = range.begin(); r < range.end(); ++r) {
      const int v = vertices[r];
      Eigen::Vector3d x = m.rest.V.row(v).transpose();
      if (dense) {
        x += off.segment<3>(3 * v);
      } else {
        if (ns > 0) x += m.shapeDirs.middleRows(3 * v, 3) * beta;
        if (correctives) x += m.poseDirs.middleRows(3 * v, 3) * kin.feature;
      }
      Eigen::Matrix3d M = Eigen::Matrix3d::Zero();  // blended world rotation
      Eb.setZero();
      list.clear();
      for (RowSparse::InnerIterator it(m.weights, v); it; ++it) {
        const int j = static_cast<int>(it.col());
        const double w = it.value();
        const Eigen::Vector3d q = w * (kin.worldR[j] * (x - J.row(j).transpose()) + kin.worldT[j]);
        M += w * kin.worldR[j];
        if (ns > 0) Eb += w * E[j];
        for (int k = j; k >= 0; k = m.parents[k]) {
          if (!touched[k]) {
            touched[k] = 1;
            list.push_back(k);
            Q[k].setZero();
            W[k] = 0;
          }
          Q[k] += q;
          W[k] += w;
        }
      }
      auto rows = jac.middleRows(3 * r, 3);
      if (ns > 0) {
        if (dense)
          rows.leftCols(ns).noalias() = M * shapeRows.middleRows(3 * v, 3) + Eb;
        else
          rows.leftCols(ns).noalias() = M * m.shapeDirs.middleRows(3 * v, 3) + Eb;
      }
      // A point moved by joints below k turns about t_k: ∂p/∂θ_kc = ω_kc × (p − t_k).
      for (int k : list) {
        rows.middleCols(ns + 3 * k, 3).noalias() = -skew(Q[k] - W[k] * kin.worldT[k]) * omega[k];
        touched[k] = 0;
      }
      if (correctives) {
        for (int k = 1; k < nj; ++k) {
          Eigen::Matrix3d dx;
          if (dense)
            dx = poseD.block<3, 3>(3 * v, 3 * (k - 1));
          else
            dx.noalias() = m.poseDirs.block(3 * v, 9 * (k - 1), 3, 9) * D[k];
          rows.middleCols(ns + 3 * k, 3).noalias() += M * dx;
        }
      }
      rows.rightCols(3).setIdentity();
    }
  });
  return jac;
}

Eigen::MatrixXd Poser::jointJacobian(const BodyParams& params) const {
  const BodyModel& m = model_;
  const Eigen::VectorXd beta = shapeOf(m, params.shape);
  checkPose(m, params.pose);
  const int ns = m.numShapes(), nj = m.numJoints();
  const Eigen::MatrixX3d J = restJoints(beta);
  const Kinematics kin = forwardKinematics(m, J, params.pose.axisAngle);
  Eigen::MatrixXd jac = Eigen::MatrixXd::Zero(3 * nj, numParams());
  std::vector<Eigen::Matrix3d> omega(nj);
  for (int j = 0; j < nj; ++j) {
    const int p = m.parents[j];
    const Eigen::Matrix3d Jl = so3LeftJacobian(params.pose.axisAngle.row(j).transpose());
    omega[j] = p < 0 ? Jl : Eigen::Matrix3d(kin.worldR[p] * Jl);
    auto rows = jac.middleRows(3 * j, 3);
    if (ns > 0) {
      const auto dJ = jointShapeDirs_.middleRows(3 * j, 3);
      if (p < 0)
        rows.leftCols(ns) = dJ;
      else
        rows.leftCols(ns) = jac.block(3 * p, 0, 3, ns) +
                            kin.worldR[p] * (dJ - jointShapeDirs_.middleRows(3 * p, 3));
    }
    for (int k = p; k >= 0; k = m.parents[k])
      rows.middleCols(ns + 3 * k, 3) = -skew(kin.worldT[j] - kin.worldT[k]) * omega[k];
    rows.rightCols(3).setIdentity();
  }
  return jac;
}

Eigen::MatrixXd Poser::canonicalJacobian(const BodyParams& params) const {
  const BodyModel& m = model_;
  std::vector<int> verts;
  for (const CanonicalDef& d : m.canonical)
    if (d.joint < 0)
      for (const auto& vw : d.vertices) verts.push_back(vw.first);
  const Eigen::MatrixXd jj = jointJacobian(params);
  const Eigen::MatrixXd vj = vertexJacobian(params, verts);
  Eigen::MatrixXd jac = Eigen::MatrixXd::Zero(3 * kNumCanonical, numParams());
  int next = 0;
  for (int c = 0; c < kNumCanonical; ++c) {
    const CanonicalDef& d = m.canonical[c];
    if (d.joint >= 0) {
      if (d.joint >= m.numJoints())
        throw InputError(describe(m) + ": canonical '" + toString(static_cast<Canonical>(c)) +
                         "' refers to a missing joint");
      jac.middleRows(3 * c, 3) = jj.middleRows(3 * d.joint, 3);
    } else {
      for (const auto& vw : d.vertices)
        jac.middleRows(3 * c, 3) += vw.second * vj.middleRows(3 * next++, 3);
    }
  }
  return jac;
}

// === Free functions

Eigen::MatrixX3d shapedTemplate(const BodyModel& model, const Eigen::VectorXd& shape) {
  return Poser(model).shapedTemplate(shape);
}

Eigen::MatrixX3d restJoints(const BodyModel& model, const Eigen::VectorXd& shape) {
  return Poser(model).restJoints(shape);
}

PosedBody poseBody(const BodyModel& model, const BodyParams& params) {
  return Poser(model).pose(params);
}

int numPoseParams(const BodyModel& model) {
  return model.numShapes() + 3 * model.numJoints() + 3;
}

Eigen::MatrixXd posedVertexJacobian(const BodyModel& model, const BodyParams& params,
                                    const std::vector<int>& vertices) {
  return Poser(model).vertexJacobian(params, vertices);
}

Eigen::MatrixXd posedJointJacobian(const BodyModel& model, const BodyParams& params) {
  return Poser(model).jointJacobian(params);
}

Eigen::MatrixXd posedCanonicalJacobian(const BodyModel& model, const BodyParams& params) {
  return Poser(model).canonicalJacobian(params);
}

// === Unposing

Eigen::MatrixX3d unposePoints(const PosedBody& body, int joint, const Eigen::MatrixX3d& P) {
  if (joint < 0 || joint >= static_cast<int>(body.skinning.size()))
    throw InputError("unposePoints: joint " + std::to_string(joint) + " out of range [0, " +
                     std::to_string(body.skinning.size()) + ")");
  const Eigen::Affine3d inv = body.skinning[joint].inverse(Eigen::Isometry);
  Eigen::MatrixX3d out(P.rows(), 3);
  for (int i = 0; i < P.rows(); ++i) out.row(i) = (inv * P.row(i).transpose()).transpose();
  return out;
}

Eigen::MatrixX3d unposeSkinned(const PosedBody& body, const RowSparse& weights,
                               const Eigen::MatrixX3d& P) {
  const int nj = static_cast<int>(body.skinning.size());
  if (weights.rows() != P.rows() || weights.cols() != nj)
    throw InputError("unposeSkinned: weights are " + std::to_string(weights.rows()) + "×" +
                     std::to_string(weights.cols()) +
                     ", expected #P×#J = " + std::to_string(P.rows()) + "×" + std::to_string(nj));
  Eigen::MatrixX3d out(P.rows(), 3);
  for (int i = 0; i < P.rows(); ++i) {
    Eigen::Matrix3d L = Eigen::Matrix3d::Zero();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    double sum = 0;
    for (RowSparse::InnerIterator it(weights, i); it; ++it) {
      L += it.value() * body.skinning[it.col()].linear();
      t += it.value() * body.skinning[it.col()].translation();
      sum += it.value();
    }
    const double det = L.determinant();
    if (!(std::abs(sum - 1.0) < 1e-4) || !(std::abs(det) > 1e-9))
      throw InputError("unposeSkinned: point " + std::to_string(i) + " has weights summing to " +
                       std::to_string(sum) + " or a singular blended transform (det " +
                       std::to_string(det) + ")");
    out.row(i) = L.inverse() * (P.row(i).transpose() - t);
  }
  return out;
}

Eigen::MatrixX3d poseSkinned(const PosedBody& body, const RowSparse& weights,
                             const Eigen::MatrixX3d& P) {
  const int nj = static_cast<int>(body.skinning.size());
  if (weights.rows() != P.rows() || weights.cols() != nj)
    throw InputError("poseSkinned: weights are " + std::to_string(weights.rows()) + "×" +
                     std::to_string(weights.cols()) +
                     ", expected #P×#J = " + std::to_string(P.rows()) + "×" + std::to_string(nj));
  Eigen::MatrixX3d out = Eigen::MatrixX3d::Zero(P.rows(), 3);
  for (int i = 0; i < P.rows(); ++i)
    for (RowSparse::InnerIterator it(weights, i); it; ++it)
      out.row(i) += it.value() * (body.skinning[it.col()] * P.row(i).transpose()).transpose();
  return out;
}

Eigen::SparseMatrix<double, Eigen::RowMajor> closestPointWeights(const BodyModel& model,
                                                                 const TriMesh& posedBody,
                                                                 const Eigen::MatrixX3d& P) {
  if (posedBody.numVertices() != model.numVertices())
    throw InputError("closestPointWeights: the posed body has " +
                     std::to_string(posedBody.numVertices()) + " vertices, the model " +
                     std::to_string(model.numVertices()));
  const MeshQuery query(posedBody);
  const std::vector<ClosestHit> hits = query.closestPoints(P);
  std::vector<Eigen::Triplet<double>> w;
  for (int i = 0; i < P.rows(); ++i)
    for (int k = 0; k < 3; ++k) {
      const int v = posedBody.F(hits[i].face, k);
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(model.weights, v); it;
           ++it)
        w.emplace_back(i, static_cast<int>(it.col()), hits[i].bary[k] * it.value());
    }
  Eigen::SparseMatrix<double, Eigen::RowMajor> W(P.rows(), model.numJoints());
  W.setFromTriplets(w.begin(), w.end());
  return W;
}

// === Standard poses

namespace {

// Arms straight in the frontal plane, the left `downLeft`, the right `downRight` radians below
// horizontal; the legs turned out by kDrapeLegSpread when `drapeLegs`; everything else at rest.
BodyPose straightLimbsPose(const BodyModel& model, const Eigen::VectorXd& shape, double downLeft,
                           double downRight, bool drapeLegs) {
  BodyPose pose = BodyPose::zero(model.numJoints());
  const Eigen::MatrixX3d J = restJoints(model, shape);
  auto jointOf = [&](Canonical c) {
    const int j = model.canonical[static_cast<int>(c)].joint;
    if (j < 0 || j >= model.numJoints())
      throw InputError(describe(model) + ": standard poses need canonical '" + toString(c) +
                       "' to be a skeleton joint");
    return j;
  };
  auto isAncestor = [&](int a, int j) {
    for (int k = model.parents[j]; k >= 0; k = model.parents[k])
      if (k == a) return true;
    return false;
  };
  // A limb (root → middle → end joints) straightened along a target direction.
  struct Limb {
    Canonical root, middle, end;
    Eigen::Vector3d target;
  };
  const double side = 1.0;  // the body's left is on +X
  std::vector<Limb> limbs;
  for (const double s : {side, -side}) {
    const bool left = s > 0;
    const double down = left ? downLeft : downRight;
    limbs.push_back({left ? Canonical::LeftShoulder : Canonical::RightShoulder,
                     left ? Canonical::LeftElbow : Canonical::RightElbow,
                     left ? Canonical::LeftWrist : Canonical::RightWrist,
                     Eigen::Vector3d(s * std::cos(down), -std::sin(down), 0.0)});
    if (drapeLegs)
      limbs.push_back(
          {left ? Canonical::LeftHip : Canonical::RightHip,
           left ? Canonical::LeftKnee : Canonical::RightKnee,
           left ? Canonical::LeftAnkle : Canonical::RightAnkle,
           Eigen::Vector3d(s * std::sin(kDrapeLegSpread), -std::cos(kDrapeLegSpread), 0.0)});
  }
  for (const Limb& limb : limbs) {
    const int s = jointOf(limb.root), e = jointOf(limb.middle), w = jointOf(limb.end);
    if (!isAncestor(s, e) || !isAncestor(e, w))
      throw InputError(describe(model) + ": canonical " + toString(limb.root) + " → " +
                       toString(limb.middle) + " → " + toString(limb.end) +
                       " is not a chain of the skeleton");
    const Eigen::Vector3d upper = (J.row(e) - J.row(s)).transpose();
    const Eigen::Vector3d lower = (J.row(w) - J.row(e)).transpose();
    // Every ancestor of the root stays at rest, so its local rotation is a world rotation.
    const Eigen::Matrix3d Rs =
        Eigen::Quaterniond::FromTwoVectors(upper, limb.target).toRotationMatrix();
    const Eigen::Matrix3d Re =
        Eigen::Quaterniond::FromTwoVectors(lower, Rs.transpose() * limb.target).toRotationMatrix();
    pose.axisAngle.row(s) = matrixToAxisAngle(Rs).transpose();
    pose.axisAngle.row(e) = matrixToAxisAngle(Re).transpose();
  }
  return pose;
}

}  // namespace

BodyPose standardPose(const BodyModel& model, const Eigen::VectorXd& shape, StandardPose which) {
  if (which == StandardPose::Rest) return BodyPose::zero(model.numJoints());
  const double down = which == StandardPose::TPose ? 0.0 : kDrapeArmDown;
  return straightLimbsPose(model, shape, down, down, which == StandardPose::DrapePose);
}

double armAngleBelowHorizontal(const PosedBody& body, bool left) {
  auto at = [&](Canonical c) -> Eigen::Vector3d {
    return body.canonical.row(static_cast<int>(c)).transpose();
  };
  const Eigen::Vector3d up = at(Canonical::Neck) - at(Canonical::Pelvis);
  const Eigen::Vector3d arm = left ? at(Canonical::LeftElbow) - at(Canonical::LeftShoulder)
                                   : at(Canonical::RightElbow) - at(Canonical::RightShoulder);
  if (up.norm() < 1e-9 || arm.norm() < 1e-9) return kDrapeArmDown;
  return std::asin(std::clamp(-arm.normalized().dot(up.normalized()), -1.0, 1.0));
}

DrapePoseChoice drapePoseFor(const BodyModel& model, const Eigen::VectorXd& shape,
                             const PosedBody& fitted) {
  DrapePoseChoice out;
  out.downLeft = std::clamp(armAngleBelowHorizontal(fitted, true), 0.0, kDrapeArmDown);
  out.downRight = std::clamp(armAngleBelowHorizontal(fitted, false), 0.0, kDrapeArmDown);
  out.pose = straightLimbsPose(model, shape, out.downLeft, out.downRight, true);
  return out;
}

BodyPose armsDownPose(const BodyModel& model, const Eigen::VectorXd& shape, double down) {
  return straightLimbsPose(model, shape, down, down, false);
}

// === Pose JSON

BodyPose readPoseJson(const std::filesystem::path& path, const BodyModel& model) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError("cannot open pose file '" + path.string() + "'");
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw FormatError("pose file '" + path.string() + "' is not valid JSON: " + e.what());
  }
  if (!doc.is_object())
    throw FormatError("pose file '" + path.string() +
                      "' must hold an object {\"joint_name\": [ax, ay, az], ...}");
  auto vec3 = [&](const nlohmann::json& v, const std::string& key) {
    if (!v.is_array() || v.size() != 3)
      throw InputError("pose file '" + path.string() + "': '" + key +
                       "' must be an array of 3 numbers");
    Eigen::Vector3d out;
    for (int k = 0; k < 3; ++k) {
      if (!v[k].is_number())
        throw InputError("pose file '" + path.string() + "': '" + key +
                         "' must be an array of 3 numbers");
      out(k) = v[k].get<double>();
    }
    if (!out.allFinite())
      throw InputError("pose file '" + path.string() + "': '" + key + "' is not finite");
    return out;
  };
  BodyPose pose = BodyPose::zero(model.numJoints());
  for (const auto& [key, value] : doc.items()) {
    if (key == "translation") {
      pose.translation = vec3(value, key);
      continue;
    }
    int j = model.jointIndex(key);
    if (j < 0)
      if (const auto c = parseCanonical(key)) j = model.canonical[static_cast<int>(*c)].joint;
    if (j < 0)
      throw InputError("pose file '" + path.string() + "': unknown joint '" + key +
                       "' (not a joint of " + describe(model) + " nor a canonical joint)");
    pose.axisAngle.row(j) = vec3(value, key).transpose();
  }
  return pose;
}

void writePoseJson(const std::filesystem::path& path, const BodyModel& model,
                   const BodyPose& pose) {
  checkPose(model, pose);
  if (static_cast<int>(model.jointNames.size()) != model.numJoints())
    throw InputError(describe(model) + ": " + std::to_string(model.jointNames.size()) +
                     " joint names for " + std::to_string(model.numJoints()) + " joints");
  nlohmann::ordered_json doc;
  for (int j = 0; j < model.numJoints(); ++j)
    doc[model.jointNames[j]] = {pose.axisAngle(j, 0), pose.axisAngle(j, 1), pose.axisAngle(j, 2)};
  doc["translation"] = {pose.translation.x(), pose.translation.y(), pose.translation.z()};
  // Written beside the target and renamed, so a failure never leaves a half-written file.
  std::filesystem::path tmp = path;
  tmp += ".tmp";
  {
    std::ofstream out(tmp, std::ios::binary);
    if (!out) throw IoError("cannot write pose file '" + path.string() + "'");
    out << doc.dump(2) << '\n';
    if (!out) throw IoError("failed writing pose file '" + path.string() + "'");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw IoError("cannot write pose file '" + path.string() + "'");
  }
}

}  // namespace s2p
