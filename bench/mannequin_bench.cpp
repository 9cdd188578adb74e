// Build time of the built-in mannequin (it is generated every time the default body is used).
#include <benchmark/benchmark.h>

#include "body/mannequin.h"

namespace {

// Calibrating the implicit body so that its tapes read the requested measurements.
void BM_MannequinImplicit(benchmark::State& state) {
  for (auto _ : state) {
    s2p::MannequinImplicit body{s2p::MannequinMeasurements{}};
    benchmark::DoNotOptimize(body.joints());
  }
}
BENCHMARK(BM_MannequinImplicit)->Unit(benchmark::kMillisecond);

// Meshing the implicit body at a given voxel size (mm), projection and relaxation included.
void BM_MannequinMesh(benchmark::State& state) {
  const s2p::MannequinImplicit body{s2p::MannequinMeasurements{}};
  for (auto _ : state) {
    const s2p::TriMesh mesh = s2p::meshMannequinImplicit(body, 1e-3 * state.range(0));
    state.counters["vertices"] = mesh.numVertices();
  }
}
BENCHMARK(BM_MannequinMesh)->Arg(13)->Arg(20)->Unit(benchmark::kMillisecond);

// The whole BodyModel: template, 10 blend shapes, regressor, weights, canonical map.
void BM_MakeMannequin(benchmark::State& state) {
  for (auto _ : state) {
    const s2p::BodyModel model =
        s2p::makeMannequin({.targetVertices = static_cast<int>(state.range(0)), .base = {}});
    state.counters["vertices"] = model.numVertices();
  }
}
BENCHMARK(BM_MakeMannequin)->Arg(15000)->Arg(5000)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace

BENCHMARK_MAIN();
