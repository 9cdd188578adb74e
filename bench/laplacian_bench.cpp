// Cotan Laplacian assembly, CHOLMOD factorisation of (M + 0.01·L) and one solve on UV spheres
// of about 10k, 50k, 200k and 1M vertices.
//   build/bench/laplacian_bench --benchmark_min_time=0.1
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>

#include "core/laplacian.h"
#include "core/mesh_topology.h"
#include "core/shapes.h"
#include "core/spd_solver.h"

namespace s2p {
namespace {

// UV sphere with rings = √(n/2) and twice as many segments: ≈ n vertices. Cached per size.
const TriMesh& sphere(int n) {
  static std::map<int, TriMesh> cache;
  auto it = cache.find(n);
  if (it == cache.end()) {
    const int rings = static_cast<int>(std::lround(std::sqrt(n / 2.0)));
    it = cache.emplace(n, makeUvSphere(rings, 2 * rings)).first;
  }
  return it->second;
}

Eigen::SparseMatrix<double> system(const TriMesh& m) {
  return massMatrix(m) + 0.01 * cotanLaplacian(m);
}

void BM_MeshTopology(benchmark::State& state) {
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    MeshTopology topo(m.F, m.numVertices());
    benchmark::DoNotOptimize(topo.numEdges());
  }
  state.counters["vertices"] = m.numVertices();
}

void BM_CotanLaplacian(benchmark::State& state) {
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    Eigen::SparseMatrix<double> L = cotanLaplacian(m);
    benchmark::DoNotOptimize(L.valuePtr());
  }
  state.counters["vertices"] = m.numVertices();
}

void BM_MassMatrix(benchmark::State& state) {
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    Eigen::SparseMatrix<double> M = massMatrix(m);
    benchmark::DoNotOptimize(M.valuePtr());
  }
  state.counters["vertices"] = m.numVertices();
}

void BM_Gradient(benchmark::State& state) {
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    Eigen::SparseMatrix<double> G = gradientOperator(m);
    benchmark::DoNotOptimize(G.valuePtr());
  }
  state.counters["vertices"] = m.numVertices();
}

void BM_Factor(benchmark::State& state) {
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  const Eigen::SparseMatrix<double> A = system(m);
  for (auto _ : state) {
    SpdSolver solver;
    solver.compute(A);
    benchmark::DoNotOptimize(solver.ready());
  }
  state.counters["vertices"] = m.numVertices();
}

void BM_Refactor(benchmark::State& state) {
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  const Eigen::SparseMatrix<double> A = system(m);
  SpdSolver solver;
  solver.compute(A);
  for (auto _ : state) {
    solver.refactor(A);
    benchmark::DoNotOptimize(solver.ready());
  }
  state.counters["vertices"] = m.numVertices();
}

void BM_FactorMetis(benchmark::State& state) {
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  const Eigen::SparseMatrix<double> A = system(m);
  for (auto _ : state) {
    SpdSolver solver(SpdSolver::Ordering::Metis);
    solver.compute(A);
    benchmark::DoNotOptimize(solver.ready());
  }
  state.counters["vertices"] = m.numVertices();
}

void BM_RefactorMetis(benchmark::State& state) {
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  const Eigen::SparseMatrix<double> A = system(m);
  SpdSolver solver(SpdSolver::Ordering::Metis);
  solver.compute(A);
  for (auto _ : state) {
    solver.refactor(A);
    benchmark::DoNotOptimize(solver.ready());
  }
  state.counters["vertices"] = m.numVertices();
}

void BM_Solve(benchmark::State& state) {
  const TriMesh& m = sphere(static_cast<int>(state.range(0)));
  SpdSolver solver;
  solver.compute(system(m));
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(m.numVertices(), -1.0, 1.0);
  for (auto _ : state) {
    Eigen::VectorXd x = solver.solve(b);
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["vertices"] = m.numVertices();
}

#define S2P_SIZES Arg(10'000)->Arg(50'000)->Arg(200'000)->Arg(1'000'000)
BENCHMARK(BM_MeshTopology)->S2P_SIZES->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CotanLaplacian)->S2P_SIZES->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MassMatrix)->S2P_SIZES->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Gradient)->S2P_SIZES->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Factor)->S2P_SIZES->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Refactor)->S2P_SIZES->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FactorMetis)->S2P_SIZES->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RefactorMetis)->S2P_SIZES->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Solve)->S2P_SIZES->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace s2p

BENCHMARK_MAIN();
