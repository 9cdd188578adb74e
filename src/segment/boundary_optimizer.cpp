#include "segment/boundary_optimizer.h"

#include <chrono>
#include <cmath>
#include <string>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/mesh_topology.h"
#include "core/spd_solver.h"

namespace s2p {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

struct BoundaryOptimizer::Impl {
  TriMesh mesh;
  BoundaryOptions options;
  MeshTopology topology;
  Eigen::VectorXd area;  // #V lumped mass
  double totalArea = 0;
  Eigen::SparseMatrix<double> M;
  SpdSolver regulariser;  // M + βL
  HeatDistance heat;
  Biharmonic biharmonic;
  BoundaryTimings timings;

  Impl(const TriMesh& m, const BoundaryOptions& o)
      : mesh(m),
        options(o),
        topology(m.F, m.numVertices()),
        heat(m, o.heat),
        biharmonic(m, o.biharmonic) {}

  // Signed distance from the zero isoline of φ_b (or of φ̄ on the fast path), signed by it;
  // components the curve misses get ±(largest finite distance) so the iteration stays finite.
  Eigen::VectorXd signedFromBiharmonic(const Eigen::VectorXd& phiB) {
    auto t0 = std::chrono::steady_clock::now();
    const Isoline iso = extractIsoline(mesh, topology, phiB);
    timings.isoline += secondsSince(t0);
    if (iso.curves.empty()) return {};
    t0 = std::chrono::steady_clock::now();
    Eigen::VectorXd phi = heat.signedDistance(iso, phiB);
    double far = 0;
    for (int v = 0; v < phi.size(); ++v)
      if (std::isfinite(phi[v])) far = std::max(far, std::abs(phi[v]));
    for (int v = 0; v < phi.size(); ++v)
      if (!std::isfinite(phi[v])) phi[v] = phiB[v] < 0 ? -far : far;
    timings.geodesic += secondsSince(t0);
    return phi;
  }

  Eigen::VectorXd solveBiharmonic(const std::vector<ValueConstraint>& zeros,
                                  const std::vector<ValueConstraint>& signs) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<ValueConstraint> c = zeros;
    c.insert(c.end(), signs.begin(), signs.end());
    Eigen::VectorXd phiB = biharmonic.solve(c);
    timings.biharmonic += secondsSince(t0);
    return phiB;
  }
};

BoundaryOptimizer::BoundaryOptimizer(const TriMesh& mesh, const BoundaryOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  validateMesh(mesh, "boundary optimisation mesh");
  if (!(options.alpha > 0) || !(options.beta >= 0) || options.maxIterations < 1 ||
      !(options.tolerance > 0) || !std::isfinite(options.alpha) || !std::isfinite(options.beta))
    throw InputError(
        "boundary optimisation: alpha > 0 (m), beta ≥ 0 (m²), maxIterations ≥ 1 "
        "and tolerance > 0 (m²) are required");
  impl_ = std::make_unique<Impl>(mesh, options);
  Impl& d = *impl_;
  d.area = vertexAreas(mesh);
  d.totalArea = d.area.sum();
  d.M = massMatrix(mesh);
  d.regulariser.compute(d.M + options.beta * cotanLaplacian(mesh));
  d.timings.setup = secondsSince(t0);
}

BoundaryOptimizer::~BoundaryOptimizer() = default;
BoundaryOptimizer::BoundaryOptimizer(BoundaryOptimizer&&) noexcept = default;
BoundaryOptimizer& BoundaryOptimizer::operator=(BoundaryOptimizer&&) noexcept = default;

Eigen::VectorXd BoundaryOptimizer::initialImplicit(
    const std::vector<std::vector<SurfacePoint>>& splines,
    const std::vector<ValueConstraint>& signs) {
  std::vector<ValueConstraint> zeros;
  for (const auto& s : splines)
    for (const auto& p : s) zeros.push_back({p, 0.0});
  if (zeros.empty())
    throw InputError(
        "boundary optimisation: the initial splines have no points (every anchor "
        "removed?)");
  Impl& d = *impl_;
  const Eigen::VectorXd phi = d.signedFromBiharmonic(d.solveBiharmonic(zeros, signs));
  if (phi.size() == 0)
    throw InputError(
        "boundary optimisation: the initial implicit function has no zero "
        "isoline; check that sign points of both signs surround the splines");
  return phi;
}

Eigen::VectorXd BoundaryOptimizer::recomputeImplicit(const Eigen::VectorXd& field,
                                                     const std::vector<ValueConstraint>& signs) {
  Impl& d = *impl_;
  auto t0 = std::chrono::steady_clock::now();
  const Isoline iso = extractIsoline(d.mesh, d.topology, field);
  d.timings.isoline += secondsSince(t0);
  if (iso.curves.empty()) return {};
  return d.signedFromBiharmonic(d.solveBiharmonic(zeroConstraints(iso), signs));
}

BoundaryResult BoundaryOptimizer::run(const std::vector<std::vector<SurfacePoint>>& splines,
                                      const std::vector<ValueConstraint>& signs,
                                      const Eigen::VectorXd& phiD) {
  Impl& d = *impl_;
  const int nV = d.mesh.numVertices();
  if (phiD.size() != nV || !phiD.allFinite())
    throw InputError("boundary optimisation: the displacement has " + std::to_string(phiD.size()) +
                     " values for " + std::to_string(nV) + " vertices or is not finite");
  bool pos = false, neg = false;
  for (const auto& s : signs) {
    pos |= s.value > 0;
    neg |= s.value < 0;
  }
  if (!pos || !neg)
    throw InputError("boundary optimisation: sign points of both signs are needed (" +
                     std::to_string(signs.size()) + " given)");
  const auto t0 = std::chrono::steady_clock::now();
  d.timings = BoundaryTimings{.setup = d.timings.setup};
  BoundaryResult r;
  Eigen::VectorXd phi = initialImplicit(splines, signs);
  r.initial = extractIsoline(d.mesh, d.topology, phi);
  const Eigen::VectorXd step = d.options.alpha * phiD;
  for (int it = 0; it < d.options.maxIterations; ++it) {
    auto t1 = std::chrono::steady_clock::now();
    const Eigen::VectorXd tilde = phi + step;  // Eq. (3)
    const Eigen::VectorXd bar =
        d.regulariser.solve(Eigen::VectorXd(d.area.cwiseProduct(tilde)));  // Eq. (4)
    d.timings.regularisation += secondsSince(t1);
    Eigen::VectorXd next =
        d.options.faithful ? recomputeImplicit(bar, signs) : d.signedFromBiharmonic(bar);
    r.iterations = it + 1;
    if (next.size() == 0) {
      r.vanished = true;
      break;
    }
    const double change = d.area.dot((next - phi).cwiseAbs2()) / d.totalArea;
    r.changes.push_back(change);
    phi = std::move(next);
    if (change < d.options.tolerance) {
      r.converged = true;
      break;
    }
  }
  r.phi = phi;
  r.boundary = extractIsoline(d.mesh, d.topology, phi);
  d.timings.total = secondsSince(t0) + d.timings.setup;
  r.timings = d.timings;
  return r;
}

BoundaryResult optimizeBoundary(const TriMesh& mesh,
                                const std::vector<std::vector<SurfacePoint>>& splines,
                                const std::vector<ValueConstraint>& signs,
                                const Eigen::VectorXd& phiD, const BoundaryOptions& options) {
  BoundaryOptimizer o(mesh, options);
  return o.run(splines, signs, phiD);
}

}  // namespace s2p
