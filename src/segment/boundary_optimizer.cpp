#include "segment/boundary_optimizer.h"

#include <tbb/parallel_invoke.h>

#include <chrono>
#include <cmath>
#include <optional>
#include <string>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/mesh_topology.h"
#include "core/spd_solver.h"
#include "segment/vertex_regions.h"

namespace s2p {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

Eigen::VectorXd regionSigns(const TriMesh& mesh, const MeshTopology& topology,
                            const Eigen::VectorXd& area, const Isoline& iso,
                            const Eigen::VectorXd& phiB,
                            const std::vector<ValueConstraint>& constraints,
                            const Eigen::VectorXd& votes) {
  const int nV = mesh.numVertices();
  std::vector<char> blocked(topology.edges().rows(), 0);
  for (const IsolineCurve& c : iso.curves)
    for (const IsolinePoint& p : c.points) blocked[p.edge] = 1;
  const VertexRegions vr = vertexRegions(topology, [&](int e) { return !blocked[e]; });
  const std::vector<int>& region = vr.region;
  const int regions = vr.count;
  Eigen::VectorXd vote = Eigen::VectorXd::Zero(regions), signVote = Eigen::VectorXd::Zero(regions);
  for (int v = 0; v < nV; ++v)
    if (votes[v] != 0) vote[region[v]] += area[v] * (votes[v] < 0 ? -1.0 : 1.0);
  for (const ValueConstraint& c : constraints) {
    if (c.value == 0) continue;
    int corner = 0;
    c.point.bary.maxCoeff(&corner);
    signVote[region[mesh.F(c.point.face, corner)]] += c.value;
  }
  Eigen::VectorXd sign(nV);
  for (int v = 0; v < nV; ++v) {
    const int r = region[v];
    const double s = signVote[r] != 0 ? signVote[r] : vote[r];
    sign[v] = s < 0 ? -1.0 : 1.0;
  }
  // Keep φ_b's own value where it agrees, so the kept curves stay exactly its zero set.
  for (int v = 0; v < nV; ++v)
    if ((phiB[v] < 0) == (sign[v] < 0)) sign[v] = phiB[v];
  return sign;
}

struct BoundaryOptimizer::Impl {
  TriMesh mesh;
  BoundaryOptions options;
  MeshTopology topology;
  Eigen::VectorXd area;  // #V lumped mass
  double totalArea = 0;
  Eigen::SparseMatrix<double> M;
  SpdSolver regulariser;  // M + βL
  std::optional<HeatDistance> heat;
  std::optional<FastMarchingDistance> marching;
  Biharmonic biharmonic;
  BoundaryTimings timings;

  Impl(const TriMesh& m, const BoundaryOptions& o, Biharmonic&& b)
      : mesh(m), options(o), topology(m.F, m.numVertices()), biharmonic(std::move(b)) {
    if (o.geodesic == GeodesicMethod::Heat)
      heat.emplace(m, o.heat);
    else
      marching.emplace(m);
  }

  // Signed distance from the zero isoline of φ_b (or of φ̄ on the fast path), signed by it;
  // components the curve misses get ±(largest finite distance) so the iteration stays finite.
  // With `constraints` (φ_b of those constraints): loops of the isoline that pass through no
  // constrained face are dropped — the biharmonic extrapolates far from its constraints and may
  // change sign there (around the feet, for B(U|S)); such a loop is not the spline — and each
  // region the kept curves enclose takes the sign of its sign points, else of most of its area
  // by `votes` (φ_b itself when null). In the iteration the votes are φ̄, the field whose zero
  // set φ_b is solved to pass through: φ_b's own sign far from the curve is extrapolation, and
  // a region it flips there (a whole leg, for B(U|L) under a long top) is not on the colour's
  // evidence.
  Eigen::VectorXd signedFromBiharmonic(const Eigen::VectorXd& phiB,
                                       const std::vector<ValueConstraint>* constraints = nullptr,
                                       const Eigen::VectorXd* votes = nullptr) {
    auto t0 = std::chrono::steady_clock::now();
    Isoline iso = extractIsoline(mesh, topology, phiB);
    timings.isoline += secondsSince(t0);
    Eigen::VectorXd sign = phiB;
    if (constraints && ((options.dropStrayCurves && dropStrayLoops(iso, *constraints)) || votes))
      sign = regionSigns(mesh, topology, area, iso, phiB, *constraints,
                         votes ? *votes : besideCurves(iso, phiB));
    if (iso.curves.empty()) return {};
    t0 = std::chrono::steady_clock::now();
    Eigen::VectorXd phi =
        heat ? heat->signedDistance(iso, sign) : marching->signedDistance(iso, sign);
    double far = 0;
    for (int v = 0; v < phi.size(); ++v)
      if (std::isfinite(phi[v])) far = std::max(far, std::abs(phi[v]));
    for (int v = 0; v < phi.size(); ++v)
      if (!std::isfinite(phi[v])) phi[v] = sign[v] < 0 ? -far : far;
    timings.geodesic += secondsSince(t0);
    return phi;
  }

  // φ_b at the ends of the edges the curves of `iso` cross, 0 elsewhere: the votes of the first
  // φ_b's regions. φ_b is only trusted next to its constraints; far away it is extrapolation,
  // and a large region (everything above the ankle loops of B(L|S), whose sign points are all
  // on the feet) voting with its whole area once took the side φ_b turned to over the torso.
  Eigen::VectorXd besideCurves(const Isoline& iso, const Eigen::VectorXd& phiB) const {
    Eigen::VectorXd out = Eigen::VectorXd::Zero(phiB.size());
    for (const IsolineCurve& c : iso.curves)
      for (const IsolinePoint& p : c.points)
        for (int k = 0; k < 2; ++k) {
          const int v = topology.edges()(p.edge, k);
          out[v] = phiB[v];
        }
    return out;
  }

  // Removes the curves that cross no face next to a zero constraint; true when any was removed.
  bool dropStrayLoops(Isoline& iso, const std::vector<ValueConstraint>& constraints) {
    std::vector<char> near(mesh.numFaces(), 0);
    for (const ValueConstraint& c : constraints) {
      if (c.value != 0) continue;
      for (int k = 0; k < 3; ++k)
        for (int f : topology.vertexFaces(mesh.F(c.point.face, k))) near[f] = 1;
    }
    const size_t before = iso.curves.size();
    std::erase_if(iso.curves, [&](const IsolineCurve& c) {
      for (int f : c.faces)
        if (near[f]) return false;
      return true;
    });
    return iso.curves.size() != before;
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
  // The biharmonic's operator and the regulariser's factorisation are independent: built side
  // by side.
  std::optional<Biharmonic> biharmonic;
  Eigen::SparseMatrix<double> M;
  SpdSolver regulariser;
  tbb::parallel_invoke([&] { biharmonic.emplace(mesh, options.biharmonic); },
                       [&] {
                         M = massMatrix(mesh);
                         regulariser.compute(M + options.beta * cotanLaplacian(mesh));
                       });
  impl_ = std::make_unique<Impl>(mesh, options, std::move(*biharmonic));
  Impl& d = *impl_;
  d.area = vertexAreas(mesh);
  d.totalArea = d.area.sum();
  d.M = std::move(M);
  d.regulariser = std::move(regulariser);
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
  std::vector<ValueConstraint> all = zeros;
  all.insert(all.end(), signs.begin(), signs.end());
  const Eigen::VectorXd phi = d.signedFromBiharmonic(d.solveBiharmonic(zeros, signs), &all);
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
  std::vector<ValueConstraint> all = zeroConstraints(iso);
  const Eigen::VectorXd phiB = d.solveBiharmonic(all, signs);
  all.insert(all.end(), signs.begin(), signs.end());
  return d.signedFromBiharmonic(phiB, &all, &field);
}

BoundaryResult BoundaryOptimizer::run(const std::vector<std::vector<SurfacePoint>>& splines,
                                      const std::vector<ValueConstraint>& signs,
                                      const Eigen::VectorXd& phiD) {
  checkInputs(signs, phiD);
  const auto t0 = std::chrono::steady_clock::now();
  const double setup = impl_->timings.setup;
  impl_->timings = BoundaryTimings{.setup = setup};
  const Eigen::VectorXd phi0 = initialImplicit(splines, signs);
  BoundaryResult r = iterateFrom(phi0, signs, phiD, impl_->options.tolerance);
  impl_->timings.total = secondsSince(t0) + setup;
  r.timings = impl_->timings;
  return r;
}

BoundaryResult BoundaryOptimizer::iterate(const Eigen::VectorXd& phi0,
                                          const std::vector<ValueConstraint>& signs,
                                          const Eigen::VectorXd& phiD, double tolerance) {
  checkInputs(signs, phiD);
  if (!(tolerance >= 0) || !std::isfinite(tolerance))
    throw InputError("boundary optimisation: the tolerance must be ≥ 0 m² (0: the options')");
  if (phi0.size() != impl_->mesh.numVertices() || !phi0.allFinite())
    throw InputError("boundary optimisation: the start field has " + std::to_string(phi0.size()) +
                     " values for " + std::to_string(impl_->mesh.numVertices()) +
                     " vertices or is not finite");
  const auto t0 = std::chrono::steady_clock::now();
  const double setup = impl_->timings.setup;
  impl_->timings = BoundaryTimings{.setup = setup};
  BoundaryResult r =
      iterateFrom(phi0, signs, phiD, tolerance > 0 ? tolerance : impl_->options.tolerance);
  impl_->timings.total = secondsSince(t0);
  r.timings = impl_->timings;
  return r;
}

void BoundaryOptimizer::checkInputs(const std::vector<ValueConstraint>& signs,
                                    const Eigen::VectorXd& phiD) const {
  const int nV = impl_->mesh.numVertices();
  if (phiD.size() != nV || !phiD.allFinite())
    throw InputError("boundary optimisation: the displacement has " + std::to_string(phiD.size()) +
                     " values for " + std::to_string(nV) + " vertices or is not finite");
  bool nonzero = false;
  for (const auto& s : signs) nonzero |= s.value != 0;
  if (!nonzero)
    throw InputError(
        "boundary optimisation: at least one sign point with a non-zero value is "
        "needed (" +
        std::to_string(signs.size()) + " given)");
}

BoundaryResult BoundaryOptimizer::iterateFrom(const Eigen::VectorXd& phi0,
                                              const std::vector<ValueConstraint>& signs,
                                              const Eigen::VectorXd& phiD, double tolerance) {
  Impl& d = *impl_;
  BoundaryResult r;
  r.phi0 = phi0;
  Eigen::VectorXd phi = phi0;
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
    if (change < tolerance) {
      r.converged = true;
      break;
    }
  }
  r.phi = phi;
  r.boundary = extractIsoline(d.mesh, d.topology, phi);
  return r;
}

BoundaryResult optimizeBoundary(const TriMesh& mesh,
                                const std::vector<std::vector<SurfacePoint>>& splines,
                                const std::vector<ValueConstraint>& signs,
                                const Eigen::VectorXd& phiD, const BoundaryOptions& options) {
  BoundaryOptimizer o(mesh, options);
  return o.run(splines, signs, phiD);
}

int removeIslands(const TriMesh& mesh, Eigen::VectorXd& phi, double minArea,
                  const std::vector<ValueConstraint>& signs) {
  const MeshTopology topo(mesh.F, mesh.numVertices());
  const Eigen::VectorXd area = vertexAreas(mesh);
  const int nV = mesh.numVertices();
  const auto sameSide = [&](int e) {
    return (phi[topo.edges()(e, 0)] < 0) == (phi[topo.edges()(e, 1)] < 0);
  };
  const VertexRegions vr = vertexRegions(topo, sameSide);
  const std::vector<int>& region = vr.region;
  std::vector<double> regionArea(vr.count, 0.0);
  std::vector<char> negative(vr.count, 0);
  for (int v = 0; v < nV; ++v) {
    regionArea[region[v]] += area[v];
    negative[region[v]] = phi[v] < 0;
  }
  std::vector<char> fixed(vr.count, 0);  // holds a sign point or is large: keeps its sign
  for (const ValueConstraint& c : signs)
    for (int k = 0; k < 3; ++k) fixed[region[mesh.F(c.point.face, k)]] = 1;
  for (int r = 0; r < vr.count; ++r) fixed[r] = fixed[r] || regionArea[r] >= minArea;
  // Region adjacency: an edge whose ends lie on opposite sides joins their regions.
  std::vector<std::vector<int>> adjacent(vr.count);
  for (int e = 0; e < topo.numEdges(); ++e)
    if (!sameSide(e)) {
      const int a = region[topo.edges()(e, 0)], b = region[topo.edges()(e, 1)];
      adjacent[a].push_back(b);
      adjacent[b].push_back(a);
    }
  // Outward from the fixed regions, each free region takes the final side of the region it is
  // reached from: nested islands (a biharmonic that swings + − + along a limb far from its
  // constraints) end on one side, where flipping every free region at once would only move
  // the loops.
  std::vector<char> finalNegative = negative, done = fixed;
  std::vector<int> queue;
  for (int r = 0; r < vr.count; ++r)
    if (fixed[r]) queue.push_back(r);
  for (size_t i = 0; i < queue.size(); ++i)
    for (int b : adjacent[queue[i]])
      if (!done[b]) {
        done[b] = 1;
        finalNegative[b] = finalNegative[queue[i]];
        queue.push_back(b);
      }
  int flipped = 0;
  std::vector<char> flip(vr.count, 0);
  for (int r = 0; r < vr.count; ++r)
    if (finalNegative[r] != negative[r]) {
      flip[r] = 1;
      ++flipped;
    }
  for (int v = 0; v < nV; ++v)
    if (flip[region[v]]) phi[v] = phi[v] < 0 ? std::max(-phi[v], 1e-9) : std::min(-phi[v], -1e-9);
  return flipped;
}

std::vector<PieceSide> sidePiecesByVotes(const TriMesh& mesh, Eigen::VectorXd& phi,
                                         const std::vector<SurfacePoint>& anchors,
                                         const std::vector<SideVote>& votes, int minVotes,
                                         double minShare) {
  if (phi.size() != mesh.numVertices())
    throw InputError("sidePiecesByVotes: φ has " + std::to_string(phi.size()) + " values for " +
                     std::to_string(mesh.numVertices()) + " vertices");
  const MeshTopology topo(mesh.F, mesh.numVertices());
  const Eigen::VectorXi& pieceOf = topo.faceComponent();
  const int n = topo.numComponents();
  std::vector<char> anchored(n, 0), positive(n, 0), negative(n, 0);
  std::vector<int> vertices(n, 0), plus(n, 0), minus(n, 0);
  for (const SurfacePoint& a : anchors) anchored[pieceOf[a.face]] = 1;
  for (const SideVote& v : votes) (v.side > 0 ? plus : minus)[pieceOf[v.point.face]]++;
  std::vector<int> vertexPiece(mesh.numVertices(), -1);
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) vertexPiece[mesh.F(f, k)] = pieceOf[f];
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const int p = vertexPiece[v];
    if (p < 0) continue;
    ++vertices[p];
    (phi[v] < 0 ? negative : positive)[p] = 1;
  }
  std::vector<PieceSide> out;
  std::vector<char> flip(n, 0);
  for (int p = 0; p < n; ++p) {
    if (anchored[p] || (positive[p] && negative[p])) continue;
    PieceSide s{p, vertices[p], plus[p], minus[p], false};
    const int total = plus[p] + minus[p];
    if (total >= minVotes) {
      const bool wantPositive = plus[p] >= minShare * total;
      const bool wantNegative = minus[p] >= minShare * total;
      s.flipped = (wantPositive && negative[p]) || (wantNegative && positive[p]);
    }
    flip[p] = s.flipped;
    out.push_back(s);
  }
  for (int v = 0; v < mesh.numVertices(); ++v)
    if (vertexPiece[v] >= 0 && flip[vertexPiece[v]])
      phi[v] = phi[v] < 0 ? std::max(-phi[v], 1e-9) : std::min(-phi[v], -1e-9);
  return out;
}

}  // namespace s2p
