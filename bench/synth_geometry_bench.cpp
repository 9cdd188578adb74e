// Synthetic clothed-scan geometry (issue 4): the whole makeClothedSurface at the default 4 mm
// voxel and 50k output vertices, per-stage times as counters, and the voxel size sweep (time
// vs level-set size). With S2P_SYNTH_PREVIEW_DIR set, also writes front/back label previews of
// a few outfits there (label colours: skin, upper, lower, shoes, hair, other, gap).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "body/mannequin.h"
#include "body/posing.h"
#include "export/preview.h"
#include "synth/clothed_surface.h"

namespace s2p {
namespace {

const BodyModel& model() {
  static const BodyModel m = makeMannequin();
  return m;
}

BodyParams params(bool walking) {
  BodyParams p;
  p.pose = BodyPose::zero(model().numJoints());
  if (walking) {
    auto joint = [&](Canonical c) { return model().canonical[static_cast<int>(c)].joint; };
    p.pose.axisAngle.row(joint(Canonical::LeftHip)) << -0.4, 0, 0;
    p.pose.axisAngle.row(joint(Canonical::RightHip)) << 0.35, 0, 0;
    p.pose.axisAngle.row(joint(Canonical::RightKnee)) << 0.4, 0, 0;
  }
  return p;
}

GarmentSpec spec(GarmentType type, double ease = 0.012, double looseness = 0) {
  GarmentSpec s;
  s.type = type;
  s.ease = ease;
  s.looseness = looseness;
  return s;
}

Outfit outfit(const std::string& name) {
  Outfit o;
  if (name == "casual")
    o.garments = {spec(GarmentType::TShirt), spec(GarmentType::Trousers),
                  spec(GarmentType::Shoes, 0.008)};
  else if (name == "dress")
    o.garments = {spec(GarmentType::Dress), spec(GarmentType::Shoes, 0.008),
                  spec(GarmentType::Hair, 0.015)};
  else if (name == "skirt")
    o.garments = {spec(GarmentType::LongSleeveShirt, 0.012, 0.5),
                  spec(GarmentType::LongSkirt, 0.012, 0.3), spec(GarmentType::Bag)};
  else if (name == "layered")
    o.garments = {spec(GarmentType::TShirt), spec(GarmentType::Shorts, 0.012, 0.6),
                  spec(GarmentType::Jacket, 0.02), spec(GarmentType::Shoes, 0.008)};
  return o;
}

void BM_ClothedSurface50k(benchmark::State& state) {
  GeometryOptions o;
  o.voxelSize = 0.004;
  o.targetVertices = 50000;
  GeometryStats st;
  int v = 0;
  for (auto _ : state) {
    const ClothedSurface s = makeClothedSurface(model(), params(false), outfit("casual"), o);
    st = s.stats;
    v = s.mesh.numVertices();
  }
  state.counters["vertices"] = v;
  state.counters["levelSetVertices"] = st.levelSetVertices;
  state.counters["activeVoxels"] = static_cast<double>(st.activeVoxels);
  state.counters["s_body"] = st.secondsBody;
  state.counters["s_union"] = st.secondsUnion;
  state.counters["s_labels"] = st.secondsLabels;
  state.counters["s_decimate"] = st.secondsDecimate;
  state.counters["s_boundaries"] = st.secondsBoundaries;
}
BENCHMARK(BM_ClothedSurface50k)->Unit(benchmark::kMillisecond)->Iterations(2);

// Voxel size (µm as the argument) vs time and level-set size, no decimation.
void BM_ClothedSurfaceVoxel(benchmark::State& state) {
  GeometryOptions o;
  o.voxelSize = state.range(0) * 1e-6;
  o.targetVertices = 0;
  GeometryStats st;
  for (auto _ : state) st = makeClothedSurface(model(), params(false), outfit("casual"), o).stats;
  state.counters["levelSetVertices"] = st.levelSetVertices;
  state.counters["s_union"] = st.secondsUnion;
  state.counters["s_labels"] = st.secondsLabels;
}
BENCHMARK(BM_ClothedSurfaceVoxel)
    ->Arg(3000)->Arg(4000)->Arg(6000)->Arg(8000)
    ->Unit(benchmark::kMillisecond)->Iterations(1);

void writePreviews(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const Eigen::Matrix<double, 7, 3> colours =
      (Eigen::Matrix<double, 7, 3>() << 0.87, 0.72, 0.60,  // skin
       0.20, 0.45, 0.85,                                   // upper
       0.85, 0.35, 0.20,                                   // lower
       0.15, 0.15, 0.15,                                   // shoes
       0.45, 0.28, 0.10,                                   // hair
       0.20, 0.70, 0.30,                                   // other
       0.95, 0.10, 0.85)                                   // gap
          .finished();
  for (const std::string name : {"casual", "dress", "skirt", "layered"}) {
    GeometryOptions o;
    o.targetVertices = 50000;
    const bool walking = name == "skirt" || name == "layered";
    const ClothedSurface s = makeClothedSurface(model(), params(walking), outfit(name), o);
    // Per-vertex colours from the face labels (each vertex takes its last face's label) so
    // label borders stay crisp at preview scale.
    Eigen::MatrixX3d C(s.mesh.numVertices(), 3);
    for (int f = 0; f < s.mesh.numFaces(); ++f)
      for (int k = 0; k < 3; ++k) C.row(s.mesh.F(f, k)) = colours.row(s.faceLabel[f]);
    Scene scene;
    scene.meshes.push_back({&s.mesh, &C});
    for (const TrueBoundary& b : s.boundaries)
      for (std::size_t i = 0; i < b.curves.size(); ++i)
        scene.lines.push_back({b.curves[i], Rgb{20, 20, 20}, 1.5f, bool(b.closed[i]), false});
    RenderOptions ro;
    ro.views = {View::Front, View::Back, View::Left};
    ro.heightPx = 700;
    writePng(dir / (name + ".png"), renderScene(scene, ro));
  }
}

}  // namespace
}  // namespace s2p

int main(int argc, char** argv) {
  if (const char* dir = std::getenv("S2P_SYNTH_PREVIEW_DIR")) s2p::writePreviews(dir);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
