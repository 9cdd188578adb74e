#include "core/winding_number.h"

#include <Eigen/Geometry>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "core/error.h"

namespace s2p {
namespace {

constexpr int kLeafSize = 8;  // faces per leaf: below this, exact sums beat traversal

}  // namespace

double triangleSolidAngle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& c) {
  // tan(Ω/2) = a·(b×c) / (|a||b||c| + (a·b)|c| + (b·c)|a| + (c·a)|b|)
  const double la = a.norm(), lb = b.norm(), lc = c.norm();
  const double det = a.dot(b.cross(c));
  const double denom = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
  return 2.0 * std::atan2(det, denom);
}

double windingNumberBruteForce(const TriMesh& mesh, const Eigen::Vector3d& p) {
  validateMesh(mesh, "winding number mesh");
  double sum = 0;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)).transpose() - p;
    const Eigen::Vector3d b = mesh.V.row(mesh.F(f, 1)).transpose() - p;
    const Eigen::Vector3d c = mesh.V.row(mesh.F(f, 2)).transpose() - p;
    sum += triangleSolidAngle(a, b, c);
  }
  return sum / (4.0 * std::numbers::pi);
}

WindingNumberTree::WindingNumberTree(const TriMesh& mesh, double beta, int order)
    : beta_(beta), order_(order) {
  validateMesh(mesh, "winding number mesh");
  if (!(beta >= 1.0))
    throw InputError("WindingNumberTree: beta = " + std::to_string(beta) +
                     " must be >= 1 (the far-field expansion needs the query outside the "
                     "node's bounding sphere); use 2");
  if (order < 1 || order > 3)
    throw InputError("WindingNumberTree: expansion order " + std::to_string(order) +
                     " is not supported; use 1, 2 or 3");
  V_ = mesh.V;
  const int nf = mesh.numFaces();
  Eigen::MatrixX3d centroids(nf, 3);  // #F×3
  for (int f = 0; f < nf; ++f)
    centroids.row(f) =
        (mesh.V.row(mesh.F(f, 0)) + mesh.V.row(mesh.F(f, 1)) + mesh.V.row(mesh.F(f, 2))) / 3.0;
  std::vector<int> faceOrder(nf);
  for (int f = 0; f < nf; ++f) faceOrder[f] = f;
  nodes_.reserve(2 * (nf / kLeafSize + 1));
  build(faceOrder, 0, nf, centroids);
  F_.resize(nf, 3);
  for (int i = 0; i < nf; ++i) F_.row(i) = mesh.F.row(faceOrder[i]);
  if (order_ >= 2) first_.resize(nodes_.size());
  if (order_ >= 3) second_.resize(nodes_.size());
  // Nodes are independent given the face order: moments in parallel, each node writes its own.
  tbb::parallel_for(tbb::blocked_range<int>(0, static_cast<int>(nodes_.size()), 256),
                    [&](const tbb::blocked_range<int>& r) {
                      for (int n = r.begin(); n != r.end(); ++n) computeMoments(n);
                    });
}

// Median split along the longest axis of the centroids' bounding box.
int WindingNumberTree::build(std::vector<int>& order, int begin, int end,
                             const Eigen::MatrixX3d& centroids) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.push_back(Node{});
  nodes_[index].begin = begin;
  nodes_[index].end = end;
  if (end - begin <= kLeafSize) return index;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (int i = begin; i < end; ++i) {
    lo = lo.cwiseMin(centroids.row(order[i]).transpose());
    hi = hi.cwiseMax(centroids.row(order[i]).transpose());
  }
  int axis = 0;
  (hi - lo).maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  std::nth_element(order.begin() + begin, order.begin() + mid, order.begin() + end,
                   [&](int f, int g) { return centroids(f, axis) < centroids(g, axis); });
  const int left = build(order, begin, mid, centroids);
  const int right = build(order, mid, end, centroids);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

// Barill et al. 2018 §3.2: p̃ = Σ a_f c_f / Σ a_f, dipole moment Σ a_f n_f, radius about p̃,
// and for higher orders the exact first and second moments of each face about p̃.
void WindingNumberTree::computeMoments(int index) {
  Node& node = nodes_[index];
  double area = 0;
  Eigen::Vector3d weighted = Eigen::Vector3d::Zero(), mean = Eigen::Vector3d::Zero();
  node.areaNormal.setZero();
  for (int i = node.begin; i < node.end; ++i) {
    const Eigen::Vector3d a = V_.row(F_(i, 0)), b = V_.row(F_(i, 1)), c = V_.row(F_(i, 2));
    const Eigen::Vector3d n2 = (b - a).cross(c - a);  // 2 a_f n_f
    const double af = 0.5 * n2.norm();
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    area += af;
    weighted += af * centroid;
    mean += centroid;
    node.areaNormal += 0.5 * n2;
  }
  node.centre =
      area > 0 ? Eigen::Vector3d(weighted / area) : Eigen::Vector3d(mean / (node.end - node.begin));
  double r2 = 0;
  for (int i = node.begin; i < node.end; ++i)
    for (int k = 0; k < 3; ++k)
      r2 = std::max(r2, (V_.row(F_(i, k)).transpose() - node.centre).squaredNorm());
  node.radius = std::sqrt(r2);
  if (order_ < 2) return;
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  std::array<Eigen::Matrix3d, 3> C = {Eigen::Matrix3d::Zero(), Eigen::Matrix3d::Zero(),
                                      Eigen::Matrix3d::Zero()};
  for (int i = node.begin; i < node.end; ++i) {
    const Eigen::Vector3d d0 = V_.row(F_(i, 0)).transpose() - node.centre;
    const Eigen::Vector3d d1 = V_.row(F_(i, 1)).transpose() - node.centre;
    const Eigen::Vector3d d2 = V_.row(F_(i, 2)).transpose() - node.centre;
    const Eigen::Vector3d an = 0.5 * (d1 - d0).cross(d2 - d0);  // a_f n_f
    const Eigen::Vector3d s = d0 + d1 + d2;
    M += an * (s / 3.0).transpose();  // ∫ n (x − p̃)ᵀ dA, n constant on the face
    if (order_ < 3) continue;
    // ∫ (x − p̃)(x − p̃)ᵀ dA = a/12 (Σ d_k d_kᵀ + s sᵀ) over a triangle; a n_i folds a in.
    const Eigen::Matrix3d S =
        (d0 * d0.transpose() + d1 * d1.transpose() + d2 * d2.transpose() + s * s.transpose()) /
        12.0;
    for (int k = 0; k < 3; ++k) C[k] += an(k) * S;
  }
  first_[index] = M;
  if (order_ >= 3) second_[index] = C;
}

// Taylor expansion of Ω = ∫ n·K(x − p) dA, K(r) = r/|r|³, about r = p̃ − p (Barill et al.
// 2018, Eq. 11 ff.): N·K + Σ ∂_j K_i M_ij + ½ Σ ∂_jk K_i C_i,jk.
double WindingNumberTree::farField(int index, const Eigen::Vector3d& r, double dist) const {
  const double inv2 = 1.0 / (dist * dist);
  const double inv3 = inv2 / dist;
  double omega = nodes_[index].areaNormal.dot(r) * inv3;  // dipole
  if (order_ < 2) return omega;
  const double inv5 = inv3 * inv2;
  const Eigen::Matrix3d& M = first_[index];
  omega += M.trace() * inv3 - 3.0 * r.dot(M * r) * inv5;
  if (order_ < 3) return omega;
  const std::array<Eigen::Matrix3d, 3>& C = second_[index];
  double diag = 0, trace = 0, cubic = 0;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d Cr = C[i] * r;
    diag += Cr(i);
    trace += r(i) * C[i].trace();
    cubic += r(i) * r.dot(Cr);
  }
  omega += 0.5 * (-3.0 * (2.0 * diag + trace) * inv5 + 15.0 * cubic * inv5 * inv2);
  return omega;
}

double WindingNumberTree::evaluate(const Eigen::Vector3d& p) const {
  double sum = 0;  // Σ solid angles, steradians
  int stack[128];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const int index = stack[--top];
    const Node& node = nodes_[index];
    const Eigen::Vector3d d = node.centre - p;
    const double dist = d.norm();
    if (dist > beta_ * node.radius) {
      sum += farField(index, d, dist);
    } else if (node.left < 0) {
      for (int i = node.begin; i < node.end; ++i)
        sum +=
            triangleSolidAngle(V_.row(F_(i, 0)).transpose() - p, V_.row(F_(i, 1)).transpose() - p,
                               V_.row(F_(i, 2)).transpose() - p);
    } else {
      stack[top++] = node.left;
      stack[top++] = node.right;
    }
  }
  return sum / (4.0 * std::numbers::pi);
}

}  // namespace s2p
