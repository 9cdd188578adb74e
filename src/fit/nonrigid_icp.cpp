#include "fit/nonrigid_icp.h"

#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "core/mesh_query.h"
#include "core/spd_solver.h"

namespace s2p {

NonrigidIcpResult runNonrigidIcp(const TriMesh& templ, const TriMesh& target,
                                 const std::vector<std::pair<int, Eigen::Vector3d>>& landmarks,
                                 const NonrigidIcpOptions& opt) {
  validateMesh(templ, "non-rigid ICP: template");
  validateMesh(target, "non-rigid ICP: target");
  if (opt.stiffness.empty() || opt.stiffness.size() != opt.landmarkWeight.size())
    throw InputError(
        "non-rigid ICP: the stiffness and landmark-weight schedules must be non-empty and of equal "
        "length");
  const int n = templ.numVertices();
  for (const auto& [v, p] : landmarks)
    if (v < 0 || v >= n || !p.allFinite())
      throw InputError("non-rigid ICP: landmark on vertex " + std::to_string(v) +
                       " is out of range or not finite (template has " + std::to_string(n) +
                       " vertices)");

  // Unit bounding-box diagonal frame so that the schedule means the same at every scale.
  const BoundingBox box = boundingBox(templ.V);
  const Eigen::RowVector3d centre = box.centre().transpose();
  const double scale = box.extent().norm() > 0 ? 1.0 / box.extent().norm() : 1.0;
  const Eigen::MatrixX3d Vt = (templ.V.rowwise() - centre) * scale;
  TriMesh targetN = target;
  targetN.V = (target.V.rowwise() - centre) * scale;
  const MeshQuery query(targetN);
  const Eigen::MatrixX3d targetNormals = faceNormals(targetN);

  // Edges (each once) for the stiffness term: L = MᵀM, the graph Laplacian.
  std::vector<std::pair<int, int>> edges;
  for (int f = 0; f < templ.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = templ.F(f, k), b = templ.F(f, (k + 1) % 3);
      edges.emplace_back(std::min(a, b), std::max(a, b));
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  const double G2[4] = {1, 1, 1, opt.gamma * opt.gamma};

  Eigen::MatrixXd X = Eigen::MatrixXd::Zero(4 * n, 3);  // per vertex a 4×3 block, rows 4i..4i+3
  for (int i = 0; i < n; ++i) X.block<3, 3>(4 * i, 0).setIdentity();
  auto deformed = [&] {
    Eigen::MatrixX3d V(n, 3);
    for (int i = 0; i < n; ++i) V.row(i) = Vt.row(i) * X.block<3, 3>(4 * i, 0) + X.row(4 * i + 3);
    return V;
  };

  NonrigidIcpResult result;
  // The pattern of A never changes (explicit zeros for unmatched vertices): one nested-dissection
  // analysis, then numeric refactorisations; none at all while α, β and the weights repeat.
  SpdSolver solver(SpdSolver::Ordering::Metis);
  std::vector<char> factoredWeights;  // #V: the 0/1 data weights of the current factor
  double factoredAlpha = -1, factoredBeta = -1;
  std::vector<int> hintFaces(n, -1);  // closest faces of the last update: the search's start
  const double maxDist = opt.maxDistance * scale;
  for (size_t step = 0; step < opt.stiffness.size(); ++step) {
    const double alpha = opt.stiffness[step], beta = opt.landmarkWeight[step];
    for (int it = 0; it < opt.maxInnerIterations; ++it) {
      TriMesh cur{deformed(), templ.F};
      const Eigen::MatrixX3d N =
          opt.weightsPerStep && it > 0 ? Eigen::MatrixX3d() : vertexNormals(cur);
      const std::vector<ClosestHit> hits = query.closestPoints(cur.V, hintFaces);
      for (int i = 0; i < n; ++i) hintFaces[i] = hits[i].face;
      std::vector<char> weights(n);
      if (opt.weightsPerStep && it > 0) {
        weights = factoredWeights;
      } else {
        for (int i = 0; i < n; ++i) {
          const ClosestHit& h = hits[i];
          weights[i] =
              h.distance <= maxDist && N.row(i).dot(targetNormals.row(h.face)) >= opt.minNormalDot;
        }
      }
      const bool sameMatrix = solver.ready() && alpha == factoredAlpha && beta == factoredBeta &&
                              weights == factoredWeights;
      std::vector<Eigen::Triplet<double>> T;
      if (!sameMatrix) T.reserve(16 * n + 8 * edges.size() + 4 * n);
      Eigen::MatrixXd B = Eigen::MatrixXd::Zero(4 * n, 3);
      if (!sameMatrix)
        for (const auto& [a, b] : edges)
          for (int k = 0; k < 4; ++k) {
            const double s = alpha * alpha * G2[k];
            T.emplace_back(4 * a + k, 4 * a + k, s);
            T.emplace_back(4 * b + k, 4 * b + k, s);
            T.emplace_back(4 * a + k, 4 * b + k, -s);
            T.emplace_back(4 * b + k, 4 * a + k, -s);
          }
      auto addPoint = [&](int i, double w2, const Eigen::Vector3d& u) {
        Eigen::Vector4d vt;
        vt << Vt.row(i).transpose(), 1.0;
        for (int r = 0; r < 4; ++r) {
          if (!sameMatrix)
            for (int c = 0; c < 4; ++c) T.emplace_back(4 * i + r, 4 * i + c, w2 * vt[r] * vt[c]);
          B.row(4 * i + r) += w2 * vt[r] * u.transpose();
        }
      };
      for (int i = 0; i < n; ++i)
        addPoint(i, weights[i] ? 1.0 : 0.0, hits[i].point);  // zeros keep the sparsity pattern
      if (beta > 0)
        for (const auto& [v, p] : landmarks)
          addPoint(v, beta * beta, (p.transpose() - centre).transpose() * scale);
      if (!sameMatrix) {
        for (int i = 0; i < 4 * n; ++i)
          T.emplace_back(i, i, 1e-10);  // keeps unmatched patches solvable
        Eigen::SparseMatrix<double> A(4 * n, 4 * n);
        A.setFromTriplets(T.begin(), T.end());
        if (solver.ready())
          solver.refactor(A);
        else
          solver.compute(A, 4);  // 4×4 blocks, one per vertex: analysed 0.4 s faster at 50k
        factoredAlpha = alpha;
        factoredBeta = beta;
        factoredWeights = std::move(weights);
        ++result.factorisations;
      }
      const Eigen::MatrixXd Xn = solver.solve(B);
      const double change = (Xn - X).norm() / std::sqrt(static_cast<double>(X.size()));
      X = Xn;
      ++result.iterations;
      if (change < opt.tolerance) break;
    }
  }
  result.mesh.F = templ.F;
  const Eigen::MatrixX3d Vn = deformed();
  result.mesh.V = (Vn / scale).rowwise() + centre;
  // Distances in the unit-diagonal frame, scaled back: no second spatial index of the target.
  const std::vector<ClosestHit> hits = query.closestPoints(Vn, hintFaces);
  for (const auto& h : hits) result.meanDistance += h.distance / scale / n;
  return result;
}

}  // namespace s2p
