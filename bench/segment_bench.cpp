// One iteration of the faithful boundary optimiser (Algorithm 1) broken into its parts, on a
// UV sphere of about 50k vertices (and 12k for scaling): factorisations built once, the
// biharmonic solve (numeric refactorisation + constrained solves), the heat-method distance, the
// isoline, one whole iteration (isoline → biharmonic → isoline → signed distance), and whole
// runs of the faithful and the fast path.
//   OPENBLAS_NUM_THREADS=1 build/bench/segment_bench --benchmark_min_time=0.2
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>

#include "core/mesh_query.h"
#include "core/shapes.h"
#include "segment/biharmonic.h"
#include "segment/boundary_optimizer.h"
#include "segment/geodesic.h"
#include "segment/isoline.h"

namespace s2p {
namespace {

// UV sphere (radius 0.15 m, a limb-sized scale) with ≈ n vertices. Cached per size.
const TriMesh& sphere(int n) {
  static std::map<int, TriMesh> cache;
  auto it = cache.find(n);
  if (it == cache.end()) {
    const int rings = static_cast<int>(std::lround(std::sqrt(n / 2.0)));
    it = cache.emplace(n, makeUvSphere(rings, 2 * rings, 0.15)).first;
  }
  return it->second;
}

// A slightly tilted latitude as the current implicit field.
Eigen::VectorXd field(const TriMesh& m) {
  return m.V.col(1) + 0.2 * m.V.col(0) - Eigen::VectorXd::Constant(m.numVertices(), 0.03);
}

std::vector<ValueConstraint> signs(const TriMesh& m) {
  const MeshQuery q(m);
  std::vector<ValueConstraint> s;
  for (double y : {0.14, -0.14}) {
    const ClosestHit h = q.closestPoint(Eigen::Vector3d(0.02, y, 0.0));
    s.push_back({SurfacePoint{h.face, h.bary}, y > 0 ? 1.0 : -1.0});
  }
  return s;
}

void BM_OptimizerSetup(benchmark::State& state) {  // all factorisations of one mesh
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    BoundaryOptimizer o(m);
    benchmark::DoNotOptimize(&o);
  }
  state.counters["vertices"] = m.numVertices();
}

void BM_HeatFactorisation(benchmark::State& state) {
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    HeatDistance h(m);
    benchmark::DoNotOptimize(&h);
  }
}

void BM_Isoline(benchmark::State& state) {
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  const MeshTopology topo(m.F, m.numVertices());
  const Eigen::VectorXd f = field(m);
  for (auto _ : state) benchmark::DoNotOptimize(extractIsoline(m, topo, f).numPoints());
}

void BM_HeatSolve(benchmark::State& state) {
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  const HeatDistance h(m);
  const Eigen::VectorXd f = field(m);
  const Isoline iso = extractIsoline(m, f);
  for (auto _ : state) benchmark::DoNotOptimize(h.signedDistance(iso, f).sum());
}

void BM_BiharmonicSolve(benchmark::State& state) {  // refactor + multiplier updates
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  Biharmonic b(m);
  std::vector<ValueConstraint> c = zeroConstraints(extractIsoline(m, field(m)));
  const std::vector<ValueConstraint> s = signs(m);
  c.insert(c.end(), s.begin(), s.end());
  b.solve(c);  // symbolic analysis outside the loop
  double updates = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(b.solve(c).sum());
    updates += b.lastStats().multiplierUpdates;
  }
  state.counters["constraints"] = static_cast<double>(c.size());
  state.counters["updates"] = benchmark::Counter(updates, benchmark::Counter::kAvgIterations);
}

void BM_Iteration(benchmark::State& state) {  // Algorithm 1 lines 6–7 (the bulk of one step)
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  BoundaryOptimizer o(m);
  const Eigen::VectorXd f = field(m);
  const std::vector<ValueConstraint> s = signs(m);
  o.recomputeImplicit(f, s);
  for (auto _ : state) benchmark::DoNotOptimize(o.recomputeImplicit(f, s).sum());
}

// A whole optimisation (setup excluded): start on the latitude y = 0.045 m, colour edge at
// y = 0 (φ_d = ±1), α = 5 mm, so ≈ 9 iterations; range(1) = 1 faithful, 0 fast path.
void BM_Run(benchmark::State& state) {
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  BoundaryOptions options;
  options.alpha = 0.005;
  options.faithful = state.range(1) != 0;
  BoundaryOptimizer o(m, options);
  const MeshQuery q(m);
  std::vector<SurfacePoint> ring;
  const double r = std::sqrt(0.15 * 0.15 - 0.045 * 0.045);
  for (int i = 0; i < 16; ++i) {
    const double a = 2 * M_PI * i / 16;
    const ClosestHit h = q.closestPoint(Eigen::Vector3d(r * std::cos(a), 0.045, r * std::sin(a)));
    ring.push_back({h.face, h.bary});
  }
  Eigen::VectorXd phiD(m.numVertices());
  for (int v = 0; v < m.numVertices(); ++v) phiD[v] = m.V(v, 1) >= 0 ? 1.0 : -1.0;
  int iterations = 0;
  double y = 0;
  for (auto _ : state) {
    const BoundaryResult res = o.run({ring}, signs(m), phiD);
    iterations = res.iterations;
    y = res.boundary.positions().col(1).mean();
  }
  state.counters["iterations"] = iterations;
  state.counters["boundary_y_mm"] = 1000 * y;
}

BENCHMARK(BM_Run)
    ->Args({12000, 1})
    ->Args({12000, 0})
    ->Args({50000, 1})
    ->Args({50000, 0})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
BENCHMARK(BM_OptimizerSetup)->Arg(12000)->Arg(50000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HeatFactorisation)->Arg(12000)->Arg(50000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Isoline)->Arg(12000)->Arg(50000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HeatSolve)->Arg(12000)->Arg(50000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BiharmonicSolve)->Arg(12000)->Arg(50000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Iteration)->Arg(12000)->Arg(50000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace s2p

BENCHMARK_MAIN();
