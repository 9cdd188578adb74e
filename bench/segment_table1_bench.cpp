// The paper's Table 1 (seconds per boundary optimisation, MacBook Pro i5 2.4 GHz) reproduced on
// synthetic scans of the same vertex counts, with the whole segmentation of segmentScan (true
// body, faithful Algorithm 1 or the fast path): seconds per boundary, and the ratio paper/ours.
// Subjects: c 7,277 (t-shirt, trousers), f 13,931 (one-piece dress: no B(U|L)), d 22,531 (knee
// skirt), h 31,218 (long sleeves, shorts), b 50,000 (t-shirt, trousers), m 49,483 (patterns).
// Also the resolution check of issue 5: the boundaries of one preset at 20k and 80k vertices,
// mean distance between them (mm).
//   OPENBLAS_NUM_THREADS=1 build/release/bench/segment_table1_bench
#include <benchmark/benchmark.h>

#include <array>
#include <map>

#include "body/body_json.h"
#include "segment/segmentation.h"
#include "synth/presets.h"
#include "synth/synthesize.h"

namespace s2p {
namespace {

struct Subject {
  const char* name;
  const char* preset;
  int vertices;
  std::array<double, 3> paper;  // B(U|S), B(L|S), B(U|L) seconds; 0: not in the table
};

constexpr std::array<Subject, 6> kSubjects = {{
    {"c", "tshirt_trousers", 7277, {11.1, 1.6, 1.5}},
    {"f", "dress", 13931, {29.6, 20.8, 0}},
    {"d", "sleeveless_knee_skirt", 22531, {34.8, 53.4, 13.8}},
    {"h", "longsleeve_shorts", 31218, {80.2, 29.5, 6.0}},
    {"b", "tshirt_trousers", 50000, {93.3, 36.9, 32.7}},
    {"m", "patterns", 49483, {92.7, 42.7, 49.3}},
}};

struct Prepared {
  SynthScan scan;
  BodyFromJson body;
};

const Prepared& prepared(const std::string& preset, int vertices) {
  static std::map<std::pair<std::string, int>, Prepared> cache;
  auto key = std::make_pair(preset, vertices);
  auto it = cache.find(key);
  if (it == cache.end()) {
    SynthOptions o = presetOptions(preset);
    o.geometry.targetVertices = vertices;
    SynthScan s = synthesize(o);
    BodyFromJson b = bodyFromJson(s.truth.body);
    it = cache.emplace(key, Prepared{std::move(s), std::move(b)}).first;
  }
  return it->second;
}

Segmentation segment(const Prepared& p, bool faithful) {
  SegmentationOptions opt;
  opt.boundary.faithful = faithful;
  return segmentScan(p.scan.scan.mesh, p.scan.scan.colour, p.body.posed.mesh, p.body.features,
                     opt);
}

void BM_Table1(benchmark::State& state) {
  const Subject& s = kSubjects[state.range(0)];
  const bool faithful = state.range(1) != 0;
  const Prepared& p = prepared(s.preset, s.vertices);
  Segmentation seg;
  for (auto _ : state) seg = segment(p, faithful);
  state.SetLabel(std::string(s.name) + " " + s.preset + (faithful ? " faithful" : " fast"));
  state.counters["vertices"] = p.scan.scan.mesh.numVertices();
  static const char* names[] = {"U|S", "L|S", "U|L"};
  static const char* keys[] = {"US", "LS", "UL"};
  for (int b = 0; b < 3; ++b)
    for (const BoundaryReport& r : seg.boundaries)
      if (r.name == names[b]) {
        state.counters[std::string(keys[b]) + "_s"] = r.seconds;
        state.counters[std::string(keys[b]) + "_it"] = r.iterations;
        if (s.paper[b] > 0) state.counters[std::string(keys[b]) + "_x"] = s.paper[b] / r.seconds;
      }
  state.counters["total_s"] = seg.seconds;
}

// Mean distance (mm) from the points of `a` to the polylines of `b`, over every boundary.
double meanDistanceMm(const Segmentation& a, const Segmentation& b) {
  double sum = 0;
  int n = 0;
  for (const BoundaryReport& ra : a.boundaries)
    for (const BoundaryReport& rb : b.boundaries) {
      if (ra.name != rb.name) continue;
      for (const Eigen::MatrixX3d& ca : ra.finalCurves)
        for (int i = 0; i < ca.rows(); ++i) {
          double best = 1e9;
          for (const Eigen::MatrixX3d& cb : rb.finalCurves)
            for (int k = 0; k + 1 < cb.rows(); ++k) {
              const Eigen::RowVector3d d = cb.row(k + 1) - cb.row(k);
              const double t = std::clamp((ca.row(i) - cb.row(k)).dot(d) / std::max(d.squaredNorm(), 1e-30), 0.0, 1.0);
              best = std::min(best, (cb.row(k) + t * d - ca.row(i)).norm());
            }
          sum += best;
          ++n;
        }
    }
  return n ? 1000 * sum / n : 0.0;
}

void BM_ResolutionIndependence(benchmark::State& state) {
  const Prepared& coarse = prepared("tshirt_trousers", 20000);
  const Prepared& fine = prepared("tshirt_trousers", 80000);
  Segmentation a, b;
  for (auto _ : state) {
    a = segment(coarse, true);
    b = segment(fine, true);
  }
  state.counters["coarse_to_fine_mm"] = meanDistanceMm(a, b);
  state.counters["fine_to_coarse_mm"] = meanDistanceMm(b, a);
}

BENCHMARK(BM_Table1)
    ->ArgsProduct({{0, 1, 2, 3, 4, 5}, {1, 0}})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);
BENCHMARK(BM_ResolutionIndependence)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace s2p

BENCHMARK_MAIN();
