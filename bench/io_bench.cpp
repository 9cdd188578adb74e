// Reading, cleaning and normalising a 1M-triangle binary PLY (written by the bench itself).
//   build/bench/io_bench --benchmark_min_time=1
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>

#include "core/shapes.h"
#include "io/cleanup.h"
#include "io/normalize.h"
#include "io/read_scan.h"
#include "io/write_mesh.h"

namespace {

namespace fs = std::filesystem;

// A 1.7 m cylinder-like body of 1,000,000 triangles (closed grid of 500 rings × 1000
// segments) with vertex colours, written once into a temp dir.
struct BigPly {
  fs::path dir, file;
  int faces = 0;
  BigPly() {
    dir = fs::temp_directory_path() / ("s2p_io_bench_" + std::to_string(getpid()));
    fs::create_directories(dir);
    file = dir / "body.ply";
    s2p::TriMesh m = s2p::makeCylinder(500, 1000, 0.15, 1.7);
    faces = m.numFaces();
    Eigen::MatrixX3d colour = (m.V.array() * 0.5 + 0.5).matrix().cwiseMax(0.0).cwiseMin(1.0);
    s2p::writePly(file, m, {.colour = &colour});
  }
  ~BigPly() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

const BigPly& bigPly() {
  static const BigPly ply;
  return ply;
}

void BM_ReadPly1M(benchmark::State& state) {
  const BigPly& ply = bigPly();
  for (auto _ : state) {
    s2p::Scan scan = s2p::readScan(ply.file);
    benchmark::DoNotOptimize(scan.mesh.V.data());
  }
  state.counters["faces"] = ply.faces;
}
BENCHMARK(BM_ReadPly1M)->Unit(benchmark::kMillisecond);

void BM_Cleanup1M(benchmark::State& state) {
  const s2p::Scan input = s2p::readScan(bigPly().file);
  for (auto _ : state) {
    state.PauseTiming();
    s2p::Scan scan = input;
    state.ResumeTiming();
    const s2p::CleanupReport r = s2p::cleanScan(scan);
    benchmark::DoNotOptimize(r.components);
  }
}
BENCHMARK(BM_Cleanup1M)->Unit(benchmark::kMillisecond);

// The same mesh split per face corner (as assimp imports OBJ): the weld does real work.
void BM_CleanupSplit1M(benchmark::State& state) {
  const s2p::Scan shared = s2p::readScan(bigPly().file);
  s2p::Scan input;
  input.mesh.V.resize(3 * shared.mesh.numFaces(), 3);
  input.mesh.F.resize(shared.mesh.numFaces(), 3);
  for (int f = 0; f < shared.mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      input.mesh.V.row(3 * f + k) = shared.mesh.V.row(shared.mesh.F(f, k));
      input.mesh.F(f, k) = 3 * f + k;
    }
  for (auto _ : state) {
    state.PauseTiming();
    s2p::Scan scan = input;
    state.ResumeTiming();
    const s2p::CleanupReport r = s2p::cleanScan(scan);
    benchmark::DoNotOptimize(r.weldedVertices);
  }
}
BENCHMARK(BM_CleanupSplit1M)->Unit(benchmark::kMillisecond);

void BM_Normalize1M(benchmark::State& state) {
  s2p::Scan input = s2p::readScan(bigPly().file);
  s2p::cleanScan(input);
  for (auto _ : state) {
    state.PauseTiming();
    s2p::Scan scan = input;
    state.ResumeTiming();
    const s2p::NormalizeReport r = s2p::normalizeScan(scan);
    benchmark::DoNotOptimize(r.heightMetres);
  }
}
BENCHMARK(BM_Normalize1M)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
