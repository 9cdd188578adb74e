// Posing and Jacobian speed on a synthetic SMPL-sized model (~15k vertices, 24 joints, 10
// shapes, 207 pose correctives): what the body fitter pays per iteration.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <random>

#include "body/posing.h"
#include "core/shapes.h"

namespace s2p {
namespace {

// A UV sphere stretched to body height around SMPL's 24-joint tree; 4-joint inverse-distance
// skinning, each joint regressed from its 4 nearest vertices, random blend shapes.
BodyModel makeBenchModel(bool correctives) {
  BodyModel m;
  m.source = "bench";
  m.rest = makeUvSphere(100, 150, 1.0);  // 14,852 vertices
  m.rest.V.col(0) *= 0.4;
  m.rest.V.col(1) = m.rest.V.col(1) * 0.85 + Eigen::VectorXd::Constant(m.rest.V.rows(), 0.9);
  m.rest.V.col(2) *= 0.15;
  const std::vector<Eigen::Vector3d> J = {
      {0, 0.95, 0},    {0.09, 0.88, 0},  {-0.09, 0.88, 0}, {0, 1.05, 0},    {0.1, 0.5, 0},
      {-0.1, 0.5, 0},  {0, 1.18, 0},     {0.1, 0.1, 0},    {-0.1, 0.1, 0},  {0, 1.3, 0},
      {0.11, 0.05, 0}, {-0.11, 0.05, 0}, {0, 1.5, 0},      {0.07, 1.42, 0}, {-0.07, 1.42, 0},
      {0, 1.6, 0},     {0.18, 1.42, 0},  {-0.18, 1.42, 0}, {0.3, 1.2, 0},   {-0.3, 1.2, 0},
      {0.35, 1.0, 0},  {-0.35, 1.0, 0},  {0.37, 0.92, 0},  {-0.37, 0.92, 0}};
  m.parents = {-1, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 9, 12, 13, 14, 16, 17, 18, 19, 20, 21};
  for (int j = 0; j < 24; ++j) m.jointNames.push_back("j" + std::to_string(j));
  const int nv = m.numVertices(), nj = 24;
  std::vector<Eigen::Triplet<double>> tw, tr;
  std::vector<std::pair<double, int>> d;
  for (int v = 0; v < nv; ++v) {
    d.clear();
    for (int j = 0; j < nj; ++j) d.push_back({(m.rest.V.row(v).transpose() - J[j]).norm(), j});
    std::partial_sort(d.begin(), d.begin() + 4, d.end());
    double sum = 0;
    for (int k = 0; k < 4; ++k) sum += 1 / (d[k].first + 1e-3);
    for (int k = 0; k < 4; ++k) tw.emplace_back(v, d[k].second, 1 / (d[k].first + 1e-3) / sum);
  }
  for (int j = 0; j < nj; ++j) {
    d.clear();
    for (int v = 0; v < nv; ++v) d.push_back({(m.rest.V.row(v).transpose() - J[j]).norm(), v});
    std::partial_sort(d.begin(), d.begin() + 4, d.end());
    for (int k = 0; k < 4; ++k) tr.emplace_back(j, d[k].second, 0.25);
  }
  m.weights.resize(nv, nj);
  m.weights.setFromTriplets(tw.begin(), tw.end());
  m.jointRegressor.resize(nj, nv);
  m.jointRegressor.setFromTriplets(tr.begin(), tr.end());
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(-0.01, 0.01);
  m.shapeDirs.resize(3 * nv, 10);
  for (int i = 0; i < m.shapeDirs.size(); ++i) m.shapeDirs.data()[i] = U(rng);
  for (int s = 0; s < 10; ++s) m.shapeParams.push_back({"b" + std::to_string(s), "", -5, 5});
  if (correctives) {
    m.poseDirs.resize(3 * nv, 9 * (nj - 1));
    for (int i = 0; i < m.poseDirs.size(); ++i) m.poseDirs.data()[i] = 0.1 * U(rng);
  }
  for (int c = 0; c < kNumCanonical; ++c) m.canonical[c].joint = c % nj;
  return m;
}

BodyParams benchParams(const BodyModel& m) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> U(-0.5, 0.5);
  BodyParams p;
  p.shape = Eigen::VectorXd::Constant(m.numShapes(), 0.3);
  p.pose = BodyPose::zero(m.numJoints());
  for (int i = 0; i < p.pose.axisAngle.size(); ++i) p.pose.axisAngle.data()[i] = U(rng);
  return p;
}

const BodyModel& model(bool correctives) {
  static const BodyModel with = makeBenchModel(true), without = makeBenchModel(false);
  return correctives ? with : without;
}

void BM_PoseBody(benchmark::State& state) {
  const BodyModel& m = model(state.range(0));
  const Poser poser(m);
  const BodyParams p = benchParams(m);
  for (auto _ : state) benchmark::DoNotOptimize(poser.pose(p));
  state.counters["vertices"] = m.numVertices();
}
BENCHMARK(BM_PoseBody)->Arg(0)->Arg(1)->ArgName("correctives")->Unit(benchmark::kMillisecond);

void BM_PoseBodyFreeFunction(benchmark::State& state) {  // includes the Poser precomputation
  const BodyModel& m = model(true);
  const BodyParams p = benchParams(m);
  for (auto _ : state) benchmark::DoNotOptimize(poseBody(m, p));
}
BENCHMARK(BM_PoseBodyFreeFunction)->Unit(benchmark::kMillisecond);

void BM_VertexJacobian(benchmark::State& state) {
  const BodyModel& m = model(state.range(0));
  const Poser poser(m);
  const BodyParams p = benchParams(m);
  const int n = std::min<int>(static_cast<int>(state.range(1)), m.numVertices());
  std::vector<int> verts(n);
  for (int i = 0; i < n; ++i)
    verts[i] = static_cast<int>(static_cast<long>(i) * m.numVertices() / n);
  for (auto _ : state) benchmark::DoNotOptimize(poser.vertexJacobian(p, verts));
  state.counters["rows"] = 3 * n;
}
BENCHMARK(BM_VertexJacobian)
    ->ArgsProduct({{0, 1}, {1000, 10000, 1 << 20}})
    ->ArgNames({"correctives", "vertices"})
    ->Unit(benchmark::kMillisecond);

void BM_JointJacobian(benchmark::State& state) {
  const BodyModel& m = model(true);
  const Poser poser(m);
  const BodyParams p = benchParams(m);
  for (auto _ : state) benchmark::DoNotOptimize(poser.jointJacobian(p));
}
BENCHMARK(BM_JointJacobian)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace s2p

BENCHMARK_MAIN();
