// Spatial queries on large meshes: MeshQuery construction, closest points, ray casts and fast
// winding numbers (with its accuracy and speed against the brute-force sum).
//   build/bench/spatial_bench --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <random>

#include "core/mesh_query.h"
#include "core/shapes.h"
#include "core/winding_number.h"

namespace s2p {
namespace {

// A bumpy closed UV sphere (radius ≈ 1 ± 0.1) with about `faces` triangles.
const TriMesh& bumpySphere(int faces) {
  static std::map<int, TriMesh> cache;
  auto it = cache.find(faces);
  if (it != cache.end()) return it->second;
  const int n = static_cast<int>(std::lround(std::sqrt(faces / 2.0)));
  TriMesh m = makeUvSphere(n + 1, n, 1.0);
  for (int v = 0; v < m.numVertices(); ++v) {
    const Eigen::Vector3d p = m.V.row(v);
    m.V.row(v) *= 1.0 + 0.1 * std::sin(5 * p.x()) * std::sin(4 * p.y()) * std::cos(3 * p.z());
  }
  return cache.emplace(faces, std::move(m)).first->second;
}

// The same with the top cap removed: a hole, as under a scan's feet.
const TriMesh& openBumpySphere(int faces) {
  static std::map<int, TriMesh> cache;
  auto it = cache.find(faces);
  if (it != cache.end()) return it->second;
  return cache.emplace(faces, cutByPlane(bumpySphere(faces), Eigen::Vector3d(0, 1, 0), 0.9))
      .first->second;
}

// Points within ±2 cm of the surface: the typical query of projection and ICP.
Eigen::MatrixX3d pointsNearSurface(const TriMesh& m, int count, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> vertex(0, m.numVertices() - 1);
  std::uniform_real_distribution<double> offset(-0.02, 0.02);
  Eigen::MatrixX3d P(count, 3);
  for (int i = 0; i < count; ++i)
    P.row(i) = m.V.row(vertex(rng)) + Eigen::RowVector3d(offset(rng), offset(rng), offset(rng));
  return P;
}

Eigen::MatrixX3d pointsInBox(int count, double half, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-half, half);
  Eigen::MatrixX3d P(count, 3);
  for (int i = 0; i < count; ++i) P.row(i) << u(rng), u(rng), u(rng);
  return P;
}

const MeshQuery& query1M() {
  static const MeshQuery q(openBumpySphere(1'000'000));
  return q;
}

void BM_BuildMeshQuery(benchmark::State& state) {
  const TriMesh& m = openBumpySphere(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    MeshQuery q(m);
    benchmark::DoNotOptimize(q);
  }
  state.SetItemsProcessed(state.iterations() * m.numFaces());
  state.counters["faces"] = m.numFaces();
}
BENCHMARK(BM_BuildMeshQuery)->Arg(200'000)->Arg(1'000'000)->Unit(benchmark::kMillisecond);

void BM_BuildWindingTree(benchmark::State& state) {
  const TriMesh& m = openBumpySphere(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    WindingNumberTree tree(m);
    benchmark::DoNotOptimize(tree);
  }
  state.SetItemsProcessed(state.iterations() * m.numFaces());
}
BENCHMARK(BM_BuildWindingTree)->Arg(200'000)->Arg(1'000'000)->Unit(benchmark::kMillisecond);

// One query at a time on one thread.
void BM_ClosestPoint1M(benchmark::State& state) {
  const MeshQuery& q = query1M();
  const Eigen::MatrixX3d P = pointsNearSurface(openBumpySphere(1'000'000), 4096, 1);
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(q.closestPoint(P.row(i).transpose()));
    i = (i + 1) % P.rows();
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ClosestPoint1M);

// closestPoints: 20k points per batch, TBB over the machine's cores.
void BM_ClosestPoints1MParallel(benchmark::State& state) {
  const MeshQuery& q = query1M();
  const Eigen::MatrixX3d P = pointsNearSurface(openBumpySphere(1'000'000), 20'000, 2);
  for (auto _ : state) benchmark::DoNotOptimize(q.closestPoints(P));
  state.SetItemsProcessed(state.iterations() * P.rows());
}
BENCHMARK(BM_ClosestPoints1MParallel)->Unit(benchmark::kMillisecond)->UseRealTime();

// Rays from points inside the body in random directions (all hit).
void BM_RayCast1M(benchmark::State& state) {
  const MeshQuery& q = query1M();
  const Eigen::MatrixX3d O = pointsInBox(4096, 0.4, 3);
  const Eigen::MatrixX3d D = pointsInBox(4096, 1.0, 4);
  int i = 0, hits = 0;
  for (auto _ : state) {
    const auto hit = q.rayCast(O.row(i).transpose(), D.row(i).transpose());
    hits += hit.has_value();
    i = (i + 1) % O.rows();
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["hit_ratio"] = static_cast<double>(hits) / state.iterations();
}
BENCHMARK(BM_RayCast1M);

void BM_WindingNumber1M(benchmark::State& state) {
  const MeshQuery& q = query1M();
  q.windingNumber(Eigen::Vector3d::Zero());  // builds the tree outside the timing
  const Eigen::MatrixX3d P = pointsInBox(4096, 1.3, 5);
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(q.windingNumber(P.row(i).transpose()));
    i = (i + 1) % P.rows();
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_WindingNumber1M);

void BM_WindingNumbers1MParallel(benchmark::State& state) {
  const MeshQuery& q = query1M();
  q.windingNumber(Eigen::Vector3d::Zero());
  const Eigen::MatrixX3d P = pointsInBox(20'000, 1.3, 6);
  for (auto _ : state) benchmark::DoNotOptimize(q.windingNumbers(P));
  state.SetItemsProcessed(state.iterations() * P.rows());
}
BENCHMARK(BM_WindingNumbers1MParallel)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_WindingNumberBruteForce1M(benchmark::State& state) {
  const TriMesh& m = openBumpySphere(1'000'000);
  const Eigen::MatrixX3d P = pointsInBox(64, 1.3, 7);
  int i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(windingNumberBruteForce(m, P.row(i).transpose()));
    i = (i + 1) % P.rows();
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_WindingNumberBruteForce1M)->Unit(benchmark::kMillisecond);

// Accuracy of the tree against the brute-force sum on 1M faces, per (β, order): 100 points in
// the box and 100 within 2 cm of the surface. Time is per fast query.
void BM_WindingAccuracy1M(benchmark::State& state) {
  const TriMesh& m = openBumpySphere(1'000'000);
  const double beta = state.range(0) / 10.0;
  const int order = static_cast<int>(state.range(1));
  static Eigen::MatrixX3d P;
  static Eigen::VectorXd exact;
  if (P.rows() == 0) {
    P.resize(200, 3);
    P << pointsInBox(100, 1.3, 8), pointsNearSurface(m, 100, 9);
    exact.resize(P.rows());
    for (int i = 0; i < P.rows(); ++i) exact(i) = windingNumberBruteForce(m, P.row(i).transpose());
  }
  const WindingNumberTree tree(m, beta, order);
  double maxErr = 0, sumErr = 0;
  for (auto _ : state) {
    maxErr = sumErr = 0;
    for (int i = 0; i < P.rows(); ++i) {
      const double err = std::abs(tree.evaluate(P.row(i).transpose()) - exact(i));
      maxErr = std::max(maxErr, err);
      sumErr += err;
    }
  }
  state.SetItemsProcessed(state.iterations() * P.rows());
  state.counters["max_err"] = maxErr;
  state.counters["mean_err"] = sumErr / P.rows();
}
BENCHMARK(BM_WindingAccuracy1M)
    ->Args({20, 1})
    ->Args({80, 1})
    ->Args({20, 3})
    ->Args({30, 3})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace s2p

BENCHMARK_MAIN();
