// The drape simulator (drape/drape.h) with default options on two garments built in code
// (drape/cloth_shapes.h): a tube of two 0.5 × 0.7 m rectangles sewn around a closed cylinder
// (radius 0.15 m; gravity off: sewing and relaxing only) and a shirt-like garment of two T-shaped
// panels (torso 0.6 × 0.7 m, sleeves 0.25 × 0.2 m, side/underarm/shoulder seams) sewn around
// and draped on a body-sized closed cylinder (radius 0.15 m, height 0.75 m), at 20, 10 and 5 mm
// edge length. One run each (a run is seconds to minutes); counters: vertices, triangles,
// sewing and drape steps, constraint projections per second, final stitch gap, self-
// intersections, body penetrations, settled (1/0).
// BM_PatternFiles drapes a pattern written by `scan2pattern run`/`demo` (OUT/pattern/: panels.obj
// with one group per panel, panels_flat.obj with the same vertices flat, stitches.json,
// body_under.obj or else body_rest.obj) when S2P_DRAPE_PATTERN names that folder (skipped otherwise).
//   build/release/bench/drape_bench --benchmark_counters_tabular=true
//   S2P_DRAPE_PATTERN=/tmp/demo/pattern build/release/bench/drape_bench --benchmark_filter=Files
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "bench_obj.h"
#include "drape/cloth_shapes.h"
#include "drape/drape.h"

namespace s2p {
namespace {

// Budgets from the environment (S2P_DRAPE_SEW_STEPS, S2P_DRAPE_STEPS, S2P_DRAPE_SUBSTEPS), to
// bound a bench run on a large pattern; S2P_DRAPE_SELF=0, S2P_DRAPE_STRAIN_LIMIT=x and
// S2P_DRAPE_SEW_RINGS=n for diagnosis.
DrapeOptions envOptions() {
  DrapeOptions o;
  if (const char* v = std::getenv("S2P_DRAPE_SEW_STEPS")) o.sewMaxSteps = std::atoi(v);
  if (const char* v = std::getenv("S2P_DRAPE_STEPS")) o.drapeMaxSteps = std::atoi(v);
  if (const char* v = std::getenv("S2P_DRAPE_SUBSTEPS")) o.substeps = std::atoi(v);
  if (const char* v = std::getenv("S2P_DRAPE_SELF")) o.selfCollision = std::atoi(v) != 0;
  if (const char* v = std::getenv("S2P_DRAPE_STRAIN_LIMIT")) o.strainLimit = std::atof(v);
  if (const char* v = std::getenv("S2P_DRAPE_SEW_RINGS")) o.sewContactRings = std::atoi(v);
  return o;
}

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
  state.counters["sewn"] = r.sewnStitches;
  state.counters["stitches"] = static_cast<double>(in.stitches.size());
  state.counters["sew_strain"] = r.maxSewStrain;
  state.counters["max_strain"] = r.maxStrain;
  state.counters["failed"] = r.status == DrapeStatus::Failed ? 1 : 0;
  state.counters["searches"] = static_cast<double>(r.contactSearches);
  state.counters["constraints"] = r.numConstraints;
  state.counters["sim_s"] = r.seconds;
  state.counters["wrapped"] = static_cast<double>(r.wrappedPanels.size());
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
  for (auto _ : state) r = runDrape(in, envOptions());
  report(state, in, r);
}
BENCHMARK(BM_Shirt)
    ->Arg(20)
    ->Arg(10)
    ->Arg(5)
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

DrapeInput readPatternFiles(const std::string& dir) {
  const ObjFile placed = readObjFile(dir + "/panels.obj");
  const ObjFile flat = readObjFile(dir + "/panels_flat.obj");
  // The body under the clothes when the pattern has it (what `run` drapes on).
  const bool under = std::ifstream(dir + "/body_under.obj").good();
  const ObjFile body = readObjFile(dir + (under ? "/body_under.obj" : "/body_rest.obj"));
  const int np = static_cast<int>(placed.names.size());
  std::vector<int> lo(np, static_cast<int>(placed.V.size())), hi(np, -1);
  for (size_t f = 0; f < placed.F.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int g = placed.group[f];
      lo[g] = std::min(lo[g], placed.F[f][k]);
      hi[g] = std::max(hi[g], placed.F[f][k]);
    }
  DrapeInput in;
  std::vector<int> panelOf(placed.V.size(), -1);
  for (int p = 0; p < np; ++p) {
    ClothPanel c;
    c.name = placed.names[p];
    const int n = hi[p] - lo[p] + 1;
    c.rest2d.resize(n, 2);
    c.start.resize(n, 3);
    for (int v = 0; v < n; ++v) {
      c.start.row(v) = placed.V[lo[p] + v].transpose();
      c.rest2d.row(v) = flat.V[lo[p] + v].head<2>().transpose();
      panelOf[lo[p] + v] = p;
    }
    std::vector<Eigen::Vector3i> F;
    for (size_t f = 0; f < placed.F.size(); ++f)
      if (placed.group[f] == p) F.push_back(placed.F[f].array() - lo[p]);
    c.F.resize(static_cast<int>(F.size()), 3);
    for (size_t f = 0; f < F.size(); ++f) c.F.row(static_cast<int>(f)) = F[f].transpose();
    in.panels.push_back(std::move(c));
  }
  std::ifstream js(dir + "/stitches.json");
  const nlohmann::json j = nlohmann::json::parse(js);
  for (const auto& s : j.at("stitches"))
    for (const auto& pair : s.at("vertex_pairs")) {
      const int a = pair[0], b = pair[1];
      in.stitches.push_back({panelOf[a], a - lo[panelOf[a]], panelOf[b], b - lo[panelOf[b]]});
    }
  in.body.V.resize(static_cast<int>(body.V.size()), 3);
  for (size_t v = 0; v < body.V.size(); ++v)
    in.body.V.row(static_cast<int>(v)) = body.V[v].transpose();
  in.body.F.resize(static_cast<int>(body.F.size()), 3);
  for (size_t f = 0; f < body.F.size(); ++f)
    in.body.F.row(static_cast<int>(f)) = body.F[f].transpose();
  return in;
}

void BM_PatternFiles(benchmark::State& state) {
  const char* dir = std::getenv("S2P_DRAPE_PATTERN");
  if (!dir) {
    state.SkipWithError("set S2P_DRAPE_PATTERN to a pattern folder (OUT/pattern)");
    return;
  }
  const DrapeInput in = readPatternFiles(dir);
  const DrapeOptions o = envOptions();
  DrapeResult r;
  for (auto _ : state) r = runDrape(in, o);
  report(state, in, r);
  state.SetLabel(std::string(toString(r.status)) + (r.failure.empty() ? "" : ": " + r.failure));
  for (const std::string& w : r.warnings) std::fprintf(stderr, "%s\n", w.c_str());
}
BENCHMARK(BM_PatternFiles)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

}  // namespace
}  // namespace s2p

BENCHMARK_MAIN();
