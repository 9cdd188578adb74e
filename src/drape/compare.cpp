#include "drape/compare.h"

#include <algorithm>
#include <numeric>
#include <vector>

#include "core/mesh_query.h"

namespace s2p {

double MeshComparison::meanMm() const {
  return std::max(aToB.meanMm, bToA.meanMm);
}
double MeshComparison::p95Mm() const {
  return std::max(aToB.p95Mm, bToA.p95Mm);
}
double MeshComparison::maxMm() const {
  return std::max(aToB.maxMm, bToA.maxMm);
}

namespace {

// Vertex areas: a third of each incident face (a vertex on no face weighs nothing; if no face
// has area, every vertex weighs the same).
Eigen::VectorXd vertexWeights(const TriMesh& mesh) {
  Eigen::VectorXd weight = Eigen::VectorXd::Zero(mesh.numVertices());
  const Eigen::VectorXd area = faceAreas(mesh);
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) weight[mesh.F(f, k)] += area[f] / 3;
  if (!(weight.sum() > 0)) weight.setOnes();
  return weight;
}

// The smallest value at or below which `fraction` of the weight lies (values non-empty).
double weightedQuantile(const Eigen::VectorXd& value, const Eigen::VectorXd& weight,
                        double fraction) {
  std::vector<int> order(static_cast<size_t>(value.size()));
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int l, int r) { return value[l] < value[r]; });
  const double target = fraction * weight.sum();
  double acc = 0;
  for (int v : order) {
    acc += weight[v];
    if (acc >= target) return value[v];
  }
  return value[order.back()];
}

}  // namespace

SurfaceDistanceStats distanceStats(const TriMesh& mesh, const Eigen::VectorXd& distance) {
  SurfaceDistanceStats s;
  const int nv = mesh.numVertices();
  if (nv == 0 || distance.size() != nv) return s;
  const Eigen::VectorXd weight = vertexWeights(mesh);
  s.meanMm = 1e3 * weight.dot(distance) / weight.sum();
  distance.maxCoeff(&s.argmax);
  s.maxMm = 1e3 * distance[s.argmax];
  s.worst = mesh.V.row(s.argmax).transpose();
  s.p95Mm = 1e3 * weightedQuantile(distance, weight, 0.95);
  return s;
}

double topDropMm(const TriMesh& draped, const TriMesh& scanned, const Eigen::Vector3d& up) {
  validateMesh(draped, "draped mesh");
  validateMesh(scanned, "scanned mesh");
  const auto top = [&](const TriMesh& m) {
    return weightedQuantile(m.V * up, vertexWeights(m), 0.98);
  };
  return 1e3 * (top(scanned) - top(draped));
}

MeshComparison compareMeshes(const TriMesh& a, const TriMesh& b) {
  validateMesh(a, "compared mesh A");
  validateMesh(b, "compared mesh B");
  const MeshQuery qa(a), qb(b);
  MeshComparison c;
  auto distances = [](const MeshQuery& q, const Eigen::MatrixX3d& P) {
    const std::vector<ClosestHit> hits = q.closestPoints(P);
    Eigen::VectorXd d(P.rows());
    for (Eigen::Index i = 0; i < P.rows(); ++i) d[i] = hits[i].distance;
    return d;
  };
  c.distanceA = distances(qb, a.V);
  c.distanceB = distances(qa, b.V);
  c.aToB = distanceStats(a, c.distanceA);
  c.bToA = distanceStats(b, c.distanceB);
  return c;
}

}  // namespace s2p
