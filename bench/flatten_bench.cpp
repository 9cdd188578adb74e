// Flattening (pattern/flatten.h: BFF with u = 0, then the warp/weft refinement) side by side
// with CGAL's Surface_mesh_parameterization LSCM and ARAP on the same panels (issue 15), timed
// and measured with the same metrics (pattern/flatten_metrics.h) after the same grain alignment.
// LSCM pins two vertices at an arbitrary scale: its map is scaled to the panel's 3D area first.
//
// BM_Cap/<method>/<faces>: a spherical cap of half-angle 40° on a sphere of radius 0.3 m (a
// doubly curved panel of a size between a sleeve cap and a bodice; its grain the cap's "up",
// across the axis) at about 10k, 100k and 1M faces. Peak memory is the process's, so run one
// benchmark per process for the memory column:
//   build/release/bench/flatten_bench --benchmark_filter='Cap/ours/100000'
//   --benchmark_counters_tabular=true
// BM_Panels/<method>: every panel of a pattern folder written by `run`/`panels` (S2P_FLATTEN_PANELS
// names the folder holding panels_3d.obj and flat.json, whose per-panel grain is used); counters:
// panels, panels whose warp and weft strain p95 are both ≤ 5 % and ≤ 10 %, the worst p95, the
// mean area distortion, inverted faces. Skipped when S2P_FLATTEN_PANELS is not set.
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/ARAP_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <vector>

#include "bench_obj.h"
#include "core/error.h"
#include "pattern/flatten.h"
#include "pattern/flatten_metrics.h"

namespace s2p {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexIndex = SurfaceMesh::Vertex_index;
namespace SMP = CGAL::Surface_mesh_parameterization;

enum class Method { Ours, CgalLscm, CgalArap };

// CGAL's parameterisation of a disk panel (#V×2, metres after scaling to the 3D area for LSCM).
Eigen::MatrixX2d cgalFlatten(const TriMesh& panel, Method method) {
  SurfaceMesh sm;
  std::vector<VertexIndex> vi(panel.V.rows());
  for (Eigen::Index v = 0; v < panel.V.rows(); ++v)
    vi[v] = sm.add_vertex(Kernel::Point_3(panel.V(v, 0), panel.V(v, 1), panel.V(v, 2)));
  for (Eigen::Index f = 0; f < panel.F.rows(); ++f)
    sm.add_face(vi[panel.F(f, 0)], vi[panel.F(f, 1)], vi[panel.F(f, 2)]);
  const auto border = CGAL::Polygon_mesh_processing::longest_border(sm).first;
  auto uvMap = sm.add_property_map<VertexIndex, Kernel::Point_2>("v:uv").first;
  const SMP::Error_code err =
      method == Method::CgalLscm
          ? SMP::parameterize(sm, SMP::LSCM_parameterizer_3<SurfaceMesh>(), border, uvMap)
          : SMP::parameterize(sm, SMP::ARAP_parameterizer_3<SurfaceMesh>(), border, uvMap);
  if (err != SMP::OK) throw SolverError(std::string("CGAL: ") + SMP::get_error_message(err));
  Eigen::MatrixX2d uv(panel.V.rows(), 2);
  for (Eigen::Index v = 0; v < panel.V.rows(); ++v) uv.row(v) << uvMap[vi[v]].x(), uvMap[vi[v]].y();
  if (method == Method::CgalLscm) {
    double a2 = 0, a3 = 0;
    for (Eigen::Index f = 0; f < panel.F.rows(); ++f) {
      const Eigen::Vector2d e1 = uv.row(panel.F(f, 1)) - uv.row(panel.F(f, 0));
      const Eigen::Vector2d e2 = uv.row(panel.F(f, 2)) - uv.row(panel.F(f, 0));
      a2 += 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
      const Eigen::Vector3d d1 = panel.V.row(panel.F(f, 1)) - panel.V.row(panel.F(f, 0));
      const Eigen::Vector3d d2 = panel.V.row(panel.F(f, 2)) - panel.V.row(panel.F(f, 0));
      a3 += 0.5 * d1.cross(d2).norm();
    }
    uv *= std::sqrt(a3 / std::abs(a2));
  }
  return uv;
}

// Flattens with the method; uv aligned to the grain (the metric's warp is +y).
Eigen::MatrixX2d flattenWith(const TriMesh& panel, const Eigen::Vector3d& grain, Method method,
                             const FlattenOptions& options) {
  if (method == Method::Ours) return flattenPanel(panel, grain, "bench", options).uv;
  return alignToGrain(panel, grain, cgalFlatten(panel, method));
}

// Options from the environment (S2P_MAX_SHEAR rad, S2P_REFINE_ITERATIONS), for experiments.
FlattenOptions envOptions() {
  FlattenOptions o;
  if (const char* v = std::getenv("S2P_MAX_SHEAR")) o.maxShear = std::atof(v);
  if (const char* v = std::getenv("S2P_REFINE_ITERATIONS")) o.refineIterations = std::atoi(v);
  return o;
}

double peakRssMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_maxrss / 1024.0;
}

// A spherical cap (radius R, half-angle theta) as rings × sectors of a polar grid: about
// `faces` triangles. Its axis is +z; the grain is +y (across the axis, like a bodice's vertical
// over the bust).
TriMesh sphericalCap(int faces, double R = 0.3, double theta = 40.0 * std::numbers::pi / 180) {
  const int rings = std::max(2, static_cast<int>(std::sqrt(faces / (2.0 * std::numbers::pi))));
  const int sectors = std::max(6, static_cast<int>(2 * std::numbers::pi * rings));
  TriMesh m;
  m.V.resize(1 + rings * sectors, 3);
  m.V.row(0) << 0, 0, R;
  for (int r = 1; r <= rings; ++r)
    for (int s = 0; s < sectors; ++s) {
      const double t = theta * r / rings, p = 2 * std::numbers::pi * s / sectors;
      m.V.row(1 + (r - 1) * sectors + s) << R * std::sin(t) * std::cos(p),
          R * std::sin(t) * std::sin(p), R * std::cos(t);
    }
  std::vector<Eigen::Vector3i> F;
  auto id = [&](int r, int s) { return 1 + (r - 1) * sectors + (s % sectors); };
  for (int s = 0; s < sectors; ++s) F.emplace_back(0, id(1, s), id(1, s + 1));
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < sectors; ++s) {
      F.emplace_back(id(r, s), id(r + 1, s), id(r + 1, s + 1));
      F.emplace_back(id(r, s), id(r + 1, s + 1), id(r, s + 1));
    }
  m.F.resize(static_cast<Eigen::Index>(F.size()), 3);
  for (size_t f = 0; f < F.size(); ++f) m.F.row(static_cast<Eigen::Index>(f)) = F[f].transpose();
  return m;
}

double worstP95(const FlatteningMetrics& m) {
  return std::max(std::abs(m.warp.p95), std::abs(m.weft.p95));
}

void BM_Cap(benchmark::State& state, Method method) {
  const TriMesh cap = sphericalCap(static_cast<int>(state.range(0)));
  const Eigen::Vector3d grain = Eigen::Vector3d::UnitY();
  const FlattenOptions options = envOptions();
  Eigen::MatrixX2d uv;
  for (auto _ : state) uv = flattenWith(cap, grain, method, options);
  const FlatteningMetrics m = flatteningMetrics(cap, uv, grain);
  state.counters["faces"] = static_cast<double>(cap.F.rows());
  state.counters["strain_p95_pct"] = 100 * worstP95(m);
  state.counters["area_dist"] = m.areaDistortionMean;
  state.counters["boundary_err_pct"] = 100 * m.boundaryLengthError;
  state.counters["inverted"] = m.invertedFaces;
  state.counters["peak_MB"] = peakRssMb();
}

void capArgs(benchmark::internal::Benchmark* b) {
  b->Arg(10000)->Arg(100000)->Arg(1000000)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
}
BENCHMARK_CAPTURE(BM_Cap, ours, Method::Ours)->Apply(capArgs);
BENCHMARK_CAPTURE(BM_Cap, cgal_lscm, Method::CgalLscm)->Apply(capArgs);
BENCHMARK_CAPTURE(BM_Cap, cgal_arap, Method::CgalArap)->Apply(capArgs);

struct NamedPanel {
  std::string name;
  TriMesh mesh;
  Eigen::Vector3d grain;
};

// The panels of panels_3d.obj (one group each, named garment_panel) with flat.json's grains.
std::vector<NamedPanel> readPanels(const std::string& dir) {
  const ObjFile obj = readObjFile(dir + "/panels_3d.obj");
  std::ifstream in(dir + "/flat.json");
  const nlohmann::json flat = nlohmann::json::parse(in);
  std::map<std::string, Eigen::Vector3d> grains;
  for (const auto& p : flat.at("panels")) {
    const auto& g = p.at("grain");
    grains[p.at("garment").get<std::string>() + "_" + p.at("name").get<std::string>()] =
        Eigen::Vector3d(g[0], g[1], g[2]);
  }
  std::vector<NamedPanel> panels;
  for (int g = 0; g < static_cast<int>(obj.names.size()); ++g) {
    std::vector<int> local(obj.V.size(), -1);
    std::vector<Eigen::Vector3d> V;
    std::vector<Eigen::Vector3i> F;
    for (size_t f = 0; f < obj.F.size(); ++f) {
      if (obj.group[f] != g) continue;
      Eigen::Vector3i t;
      for (int k = 0; k < 3; ++k) {
        int& l = local[obj.F[f][k]];
        if (l < 0) l = static_cast<int>(V.size()), V.push_back(obj.V[obj.F[f][k]]);
        t[k] = l;
      }
      F.push_back(t);
    }
    NamedPanel p{obj.names[g],
                 {},
                 grains.count(obj.names[g]) ? grains[obj.names[g]] : Eigen::Vector3d::UnitY()};
    p.mesh.V.resize(static_cast<Eigen::Index>(V.size()), 3);
    for (size_t v = 0; v < V.size(); ++v) p.mesh.V.row(static_cast<Eigen::Index>(v)) = V[v];
    p.mesh.F.resize(static_cast<Eigen::Index>(F.size()), 3);
    for (size_t f = 0; f < F.size(); ++f) p.mesh.F.row(static_cast<Eigen::Index>(f)) = F[f];
    panels.push_back(std::move(p));
  }
  return panels;
}

void BM_Panels(benchmark::State& state, Method method) {
  const char* dir = std::getenv("S2P_FLATTEN_PANELS");
  if (!dir) {
    state.SkipWithError("set S2P_FLATTEN_PANELS to a pattern folder (panels_3d.obj, flat.json)");
    return;
  }
  const std::vector<NamedPanel> panels = readPanels(dir);
  const FlattenOptions options = envOptions();
  std::vector<FlatteningMetrics> metrics(panels.size());
  int failed = 0;
  for (auto _ : state) {
    failed = 0;
    for (size_t p = 0; p < panels.size(); ++p) {
      try {
        metrics[p] = flatteningMetrics(
            panels[p].mesh, flattenWith(panels[p].mesh, panels[p].grain, method, options),
            panels[p].grain);
      } catch (const std::exception&) {
        ++failed;
        metrics[p] = FlatteningMetrics{};
        metrics[p].warp.p95 = 1.0;
      }
    }
  }
  int le5 = 0, le10 = 0, inverted = 0;
  double worst = 0, areaDist = 0;
  for (size_t p = 0; p < panels.size(); ++p) {
    const double w = worstP95(metrics[p]);
    le5 += w <= 0.05, le10 += w <= 0.10, worst = std::max(worst, w);
    areaDist += metrics[p].areaDistortionMean / static_cast<double>(panels.size());
    inverted += metrics[p].invertedFaces;
    if (std::getenv("S2P_FLATTEN_VERBOSE"))
      std::fprintf(stderr, "%-24s warp p95 %5.2f %%  weft p95 %5.2f %%\n", panels[p].name.c_str(),
                   100 * metrics[p].warp.p95, 100 * metrics[p].weft.p95);
  }
  state.counters["panels"] = static_cast<double>(panels.size());
  state.counters["p95_le5"] = le5;
  state.counters["p95_le10"] = le10;
  state.counters["worst_p95_pct"] = 100 * worst;
  state.counters["area_dist"] = areaDist;
  state.counters["inverted"] = inverted;
  state.counters["failed"] = failed;
}
BENCHMARK_CAPTURE(BM_Panels, ours, Method::Ours)
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Panels, cgal_lscm, Method::CgalLscm)
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_Panels, cgal_arap, Method::CgalArap)
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

}  // namespace
}  // namespace s2p

BENCHMARK_MAIN();
