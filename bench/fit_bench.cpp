// Body fit timings (issue 6): a 50k-vertex "clothed" scan (the default mannequin posed in a
// walking pose, offset 2 cm outwards and subdivided) fitted from the geometric pose
// initialisation; counters give the stage split in seconds.
#include <benchmark/benchmark.h>

#include <chrono>
#include <ctime>
#include <map>

#include "body/mannequin.h"
#include "body/posing.h"
#include "fit/body_fit.h"
#include "fit/orientation.h"
#include "fit/pose_init.h"

namespace s2p {
namespace {

const BodyModel& mannequin() {
  static const BodyModel m = makeMannequin();
  return m;
}

// Midpoint subdivision (each triangle into four) until the mesh has at least `target` vertices.
TriMesh subdivideTo(TriMesh m, int target) {
  while (m.numVertices() < target) {
    std::map<std::pair<int, int>, int> mid;
    std::vector<Eigen::RowVector3d> V;
    for (int v = 0; v < m.numVertices(); ++v) V.push_back(m.V.row(v));
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      V.push_back(0.5 * (m.V.row(a) + m.V.row(b)));
      return mid[key] = static_cast<int>(V.size()) - 1;
    };
    Eigen::MatrixX3i F(4 * m.numFaces(), 3);
    for (int f = 0; f < m.numFaces(); ++f) {
      const int a = m.F(f, 0), b = m.F(f, 1), c = m.F(f, 2);
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      F.row(4 * f) << a, ab, ca;
      F.row(4 * f + 1) << ab, b, bc;
      F.row(4 * f + 2) << ca, bc, c;
      F.row(4 * f + 3) << ab, bc, ca;
    }
    m.V.resize(static_cast<int>(V.size()), 3);
    for (int v = 0; v < m.V.rows(); ++v) m.V.row(v) = V[v];
    m.F = F;
  }
  return m;
}

struct Clothed {
  TriMesh scan;
  Eigen::MatrixX3d canonical;  // true canonical points of the body under the "clothing"
};

const Clothed& clothed() {
  static const Clothed scan = [] {
    const BodyModel& m = mannequin();
    BodyParams p;
    p.shape = Eigen::VectorXd::Zero(m.numShapes());
    p.shape[1] = 5;
    p.pose = BodyPose::zero(m.numJoints());
    p.pose.axisAngle(m.jointIndex("left_hip"), 0) = -0.35;
    p.pose.axisAngle(m.jointIndex("right_hip"), 0) = 0.25;
    p.pose.axisAngle(m.jointIndex("right_knee"), 0) = 0.4;
    p.pose.axisAngle(m.jointIndex("left_elbow"), 0) = -0.8;
    const PosedBody posed = poseBody(m, p);
    TriMesh body = posed.mesh;
    body.V += 0.02 * vertexNormals(body);
    return Clothed{subdivideTo(body, 50000), posed.canonical};
  }();
  return scan;
}

void BM_FitClothed50k(benchmark::State& state) {
  const TriMesh& scan = clothed().scan;
  const BodyModel& m = mannequin();
  BodyFitResult r;
  double init = 0, orient = 0;
  double cpu = 0;
  for (auto _ : state) {
    const std::clock_t c0 = std::clock();
    const auto t0 = std::chrono::steady_clock::now();
    const Orientation o = estimateOrientation(scan);
    const auto t1 = std::chrono::steady_clock::now();
    const BodyParams start = initialisePose(scan, m);
    const auto t2 = std::chrono::steady_clock::now();
    r = runBodyFit({.scan = scan, .model = &m, .initial = start}, {});
    orient = std::chrono::duration<double>(t1 - t0).count();
    init = std::chrono::duration<double>(t2 - t1).count();
    benchmark::DoNotOptimize(o);
    cpu = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  }
  state.counters["process_cpu_s"] =
      cpu;  // both threads: ≈ 2× the wall time of a quiet 2-core machine
  state.counters["scan_vertices"] = scan.numVertices();
  state.counters["body_vertices"] = m.numVertices();
  state.counters["orientation_s"] = orient;
  state.counters["pose_init_s"] = init;
  state.counters["translation_s"] = r.secondsByStage("translation");
  state.counters["shape_s"] = r.secondsByStage("shape");
  state.counters["pose_s"] = r.secondsByStage("pose");
  state.counters["fit_total_s"] = r.seconds;
  state.counters["inside_or_near"] = r.insideOrNear;
  double mean = 0, worst = 0;
  for (int c = 0; c < static_cast<int>(Canonical::LeftHandTip); ++c) {
    const double d = (r.body.canonical.row(c) - clothed().canonical.row(c)).norm();
    mean += d / static_cast<int>(Canonical::LeftHandTip);
    worst = std::max(worst, d);
  }
  state.counters["joint_mean_mm"] = 1000 * mean;
  state.counters["joint_max_mm"] = 1000 * worst;
}
BENCHMARK(BM_FitClothed50k)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace
}  // namespace s2p

BENCHMARK_MAIN();
