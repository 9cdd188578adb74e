// Load time of the MPFB2 / MakeHuman body source (OBJ, ~76 gzipped targets, rig and weights
// JSON, regressor fit). Data: $S2P_MPFB2_DIR or ../shared/bodymodels/mpfb2 beside the repo.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>

#include "body/mpfb2_files.h"
#include "body/mpfb2_model.h"

namespace {

namespace fs = std::filesystem;

fs::path dataDir() {
  if (const char* env = std::getenv("S2P_MPFB2_DIR")) return env;
  return fs::path(__FILE__).parent_path().parent_path().parent_path() / "shared" / "bodymodels" /
         "mpfb2";
}

void BM_LoadMpfb2(benchmark::State& state) {
  const fs::path dir = dataDir();
  if (!fs::exists(dir / "3dobjs" / "base.obj")) {
    state.SkipWithError("MPFB2 data not found (set S2P_MPFB2_DIR)");
    return;
  }
  s2p::Mpfb2Options options;
  options.includeMeasureTargets = state.range(0) != 0;
  int vertices = 0;
  for (auto _ : state) {
    const s2p::BodyModel model = s2p::loadMpfb2(dir, options);
    vertices = model.numVertices();
    benchmark::DoNotOptimize(model.shapeDirs.data());
  }
  state.counters["vertices"] = vertices;
}
BENCHMARK(BM_LoadMpfb2)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->Iterations(3);

// The parts: the base OBJ alone, and one macro target.
void BM_ReadBaseObj(benchmark::State& state) {
  const fs::path file = dataDir() / "3dobjs" / "base.obj";
  if (!fs::exists(file)) {
    state.SkipWithError("MPFB2 data not found (set S2P_MPFB2_DIR)");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(s2p::readMpfb2Obj(file).V.data());
}
BENCHMARK(BM_ReadBaseObj)->Unit(benchmark::kMillisecond);

void BM_ReadTarget(benchmark::State& state) {
  const fs::path file = dataDir() / "targets" / "macrodetails" / "caucasian-female-young.target.gz";
  if (!fs::exists(file)) {
    state.SkipWithError("MPFB2 data not found (set S2P_MPFB2_DIR)");
    return;
  }
  for (auto _ : state) benchmark::DoNotOptimize(s2p::readMpfb2Target(file, 19158).index.data());
}
BENCHMARK(BM_ReadTarget)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
