// Preview renderer speed: a uv sphere stretched to a person's proportions (0.5 × 1.8 × 0.3 m),
// 1024 px tall, 2×2 supersampling, one view (front) or four (front, back, left, three-quarter).
//   build/bench/preview_bench --benchmark_min_time=2
#include <benchmark/benchmark.h>

#include <cmath>

#include "core/shapes.h"
#include "export/preview.h"

namespace s2p {
namespace {

// UV sphere with about `triangles` faces, scaled like a standing person.
TriMesh personSizedSphere(int triangles) {
  const int rings = static_cast<int>(std::sqrt(triangles / 3.2));  // segments = 1.6·rings
  TriMesh m = makeUvSphere(rings, static_cast<int>(1.6 * rings), 1.0);
  m.V.col(0) *= 0.25;
  m.V.col(1) = (m.V.col(1).array() + 1.0) * 0.9;
  m.V.col(2) *= 0.15;
  return m;
}

void BM_RenderPreview(benchmark::State& state) {
  const TriMesh mesh = personSizedSphere(static_cast<int>(state.range(0)));
  Scene scene;
  scene.meshes.push_back({.mesh = &mesh});
  RenderOptions options{.heightPx = 1024, .supersample = 2};
  if (state.range(1) == 4)
    options.views = {View::Front, View::Back, View::Left, View::ThreeQuarter};
  Image image;
  for (auto _ : state) {
    image = renderScene(scene, options);
    benchmark::DoNotOptimize(image.rgb.data());
  }
  state.counters["triangles"] = mesh.numFaces();
  state.counters["width_px"] = image.width;
}
BENCHMARK(BM_RenderPreview)
    ->ArgsProduct({{200'000, 1'000'000}, {1, 4}})
    ->ArgNames({"tris", "views"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace s2p

BENCHMARK_MAIN();
