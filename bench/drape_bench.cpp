// The drape simulator (drape/drape.h) with default options on two garments built in code
// (drape/cloth_shapes.h): a tube of two 0.5 × 0.7 m rectangles sewn around a closed cylinder
// (radius 0.15 m; gravity off: sewing and relaxing only) and a shirt-like garment of two T-shaped
// panels (torso 0.6 × 0.7 m, sleeves 0.25 × 0.2 m, side/underarm/shoulder seams) sewn around
// and draped on a body-sized closed cylinder (radius 0.15 m, height 0.75 m), at 20, 10 and 5 mm
// edge length. One run each (a run is seconds to minutes); counters: vertices, triangles,
// sewing and drape steps, constraint projections per second, final stitch gap, self-
// intersections, body penetrations, settled (1/0).
//   build/release/bench/drape_bench --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include "drape/cloth_shapes.h"
#include "drape/drape.h"

namespace s2p {
namespace {

void report(benchmark::State& state, const DrapeInput& in, const DrapeResult& r) {
  int nv = 0, nf = 0;
  for (const ClothPanel& p : in.panels) nv += p.numVertices(), nf += p.numFaces();
  state.counters["vertices"] = nv;
  state.counters["triangles"] = nf;
  state.counters["sew_steps"] = r.sewSteps;
  state.counters["drape_steps"] = r.drapeSteps;
  state.counters["Msolves_per_s"] = r.constraintSolvesPerSecond / 1e6;
  state.counters["gap_mm"] = 1e3 * r.maxStitchGap;
  state.counters["self_isect"] = r.selfIntersections;
  state.counters["penetrations"] = r.bodyPenetrations;
  state.counters["settled"] = r.settled ? 1 : 0;
  state.counters["failed"] = r.status == DrapeStatus::Failed ? 1 : 0;
}

void BM_Tube(benchmark::State& state) {
  const double edge = state.range(0) / 1000.0;
  const DrapeInput in = makeTubeGarment(0.5, 0.7, edge, 0.2, 0.15);
  DrapeOptions o;
  o.gravity.setZero();
  DrapeResult r;
  for (auto _ : state) r = runDrape(in, o);
  report(state, in, r);
}
BENCHMARK(BM_Tube)->Arg(10)->Arg(5)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

void BM_Shirt(benchmark::State& state) {
  const double edge = state.range(0) / 1000.0;
  const DrapeInput in = makeShirtGarment(edge);
  DrapeResult r;
  for (auto _ : state) r = runDrape(in, {});
  report(state, in, r);
}
BENCHMARK(BM_Shirt)
    ->Arg(20)
    ->Arg(10)
    ->Arg(5)
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

}  // namespace
}  // namespace s2p

BENCHMARK_MAIN();
