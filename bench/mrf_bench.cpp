// The MRF baseline segmenter (segment/mrf.h) on a person-sized open cylinder (radius 0.15 m,
// height 1.75 m) painted in four bands (foot, lower, upper, skin) with 2 % salt-and-pepper
// noise, four labels, default options: the whole segmentation (colour smoothing + GMM fits +
// prior + alpha-expansion, counter `correct`: the fraction of vertices labelled with their band)
// and the alpha-expansion alone on random unaries, at ≈ 12k and ≈ 50k vertices.
//   OPENBLAS_NUM_THREADS=1 build/bench/mrf_bench --benchmark_min_time=0.5
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <random>

#include "core/mesh_topology.h"
#include "core/shapes.h"
#include "segment/mrf.h"

namespace s2p {
namespace {

struct Scene {
  TriMesh mesh;
  Eigen::MatrixX3d srgb;  // #V×3
  std::vector<MrfRegion> regions;
  Eigen::VectorXi truth;  // #V, band before the noise
};

// Cached per vertex count n.
const Scene& scene(int n) {
  static std::map<int, Scene> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  Scene s;
  const int segments = static_cast<int>(std::lround(std::sqrt(n * 0.5)));
  s.mesh = makeCylinder(n / segments - 1, segments, 0.15, 1.75);
  const Eigen::RowVector3d colours[4] = {
      {0.2, 0.15, 0.1}, {0.1, 0.2, 0.6}, {0.8, 0.1, 0.1}, {0.85, 0.65, 0.55}};
  const double edges[3] = {0.1, 0.9, 1.4};  // band edges in y, metres
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  std::normal_distribution<double> noise(0, 0.01);
  s.srgb.resize(s.mesh.numVertices(), 3);
  s.regions.resize(4);
  s.truth.resize(s.mesh.numVertices());
  for (int v = 0; v < s.mesh.numVertices(); ++v) {
    const double y = s.mesh.V(v, 1);
    const int band = y < edges[0] ? 0 : (y < edges[1] ? 1 : (y < edges[2] ? 2 : 3));
    s.truth[v] = band;
    const int painted = u(rng) < 0.02 ? static_cast<int>(u(rng) * 4) % 4 : band;
    s.srgb.row(v) = colours[painted] + Eigen::RowVector3d(noise(rng), noise(rng), noise(rng));
    // Region points: every 5th vertex well inside its band.
    const double lo = band == 0 ? 0.0 : edges[band - 1], hi = band == 3 ? 1.75 : edges[band];
    if (v % 5 == 0 && y > lo + 0.3 * (hi - lo) && y < hi - 0.3 * (hi - lo))
      s.regions[band].points.push_back(SurfacePoint::atVertex(s.mesh.F, v));
  }
  for (int l = 0; l < 4; ++l) s.regions[l].label = l;
  return cache.emplace(n, std::move(s)).first->second;
}

void BM_MrfSegmentation(benchmark::State& state) {
  const Scene& s = scene(static_cast<int>(state.range(0)));
  MrfResult r;
  for (auto _ : state) {
    r = mrfSegmentation(s.mesh, s.srgb, s.regions);
    benchmark::DoNotOptimize(r.vertexLabel.data());
  }
  state.counters["vertices"] = s.mesh.numVertices();
  state.counters["sweeps"] = r.sweeps;
  state.counters["correct"] =
      static_cast<double>((r.vertexLabel.array() == s.truth.array()).count()) /
      s.mesh.numVertices();
}
BENCHMARK(BM_MrfSegmentation)->Arg(12000)->Arg(50000)->Unit(benchmark::kMillisecond);

void BM_AlphaExpansion(benchmark::State& state) {
  const Scene& s = scene(static_cast<int>(state.range(0)));
  const int nv = s.mesh.numVertices();
  // Random unaries in [0, 4] (the data term's range) and unit Potts weights on the mesh edges.
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0, 4);
  Eigen::MatrixXd unary(nv, 4);
  for (Eigen::Index i = 0; i < unary.size(); ++i) unary.data()[i] = u(rng);
  const MeshTopology topology(s.mesh.F, nv);
  const Eigen::VectorXd w = Eigen::VectorXd::Ones(topology.numEdges());
  PottsResult r;
  for (auto _ : state) {
    r = minimisePotts(unary, topology.edges(), w);
    benchmark::DoNotOptimize(r.label.data());
  }
  state.counters["vertices"] = nv;
  state.counters["sweeps"] = r.sweeps;
}
BENCHMARK(BM_AlphaExpansion)->Arg(12000)->Arg(50000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace s2p

BENCHMARK_MAIN();
