#include "body_test_sources.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>

#include "body/mannequin.h"
#include "body/mpfb2_model.h"
#include "body/npz.h"
#include "body/smpl_model.h"
#include "test_support.h"

namespace s2p::test {
namespace {

// SMPL's 24 joints: parent and the mannequin joint playing its part ("" for spine2, which the
// mannequin has not: it gets the mean of spine and chest and no skin of its own).
struct SmplJoint {
  int parent;
  const char* mannequin;
};
constexpr SmplJoint kSmpl[24] = {
    {-1, "pelvis"},        {0, "left_hip"},        {0, "right_hip"},     {0, "spine"},
    {1, "left_knee"},      {2, "right_knee"},      {3, ""},              {4, "left_ankle"},
    {5, "right_ankle"},    {6, "chest"},           {7, "left_toe"},      {8, "right_toe"},
    {9, "neck"},           {9, "left_clavicle"},   {9, "right_clavicle"}, {12, "head"},
    {13, "left_shoulder"}, {14, "right_shoulder"}, {16, "left_elbow"},   {17, "right_elbow"},
    {18, "left_wrist"},    {19, "right_wrist"},    {20, "left_hand"},    {21, "right_hand"}};

NpyArray array(std::vector<size_t> shape) {
  NpyArray a;
  size_t n = 1;
  for (size_t s : shape) n *= s;
  a.shape = std::move(shape);
  a.data.assign(n, 0.0);
  return a;
}

BodyModel smplFromMannequin(const BodyModel& m) {
  const size_t nv = m.numVertices(), ns = m.numShapes();
  std::map<std::string, NpyArray> a;
  NpyArray vt = array({nv, 3}), sd = array({nv, 3, ns}), f = array({size_t(m.rest.numFaces()), 3});
  for (size_t v = 0; v < nv; ++v)
    for (size_t k = 0; k < 3; ++k) {
      vt.data[3 * v + k] = m.rest.V(v, k);
      for (size_t s = 0; s < ns; ++s) sd.data[(3 * v + k) * ns + s] = m.shapeDirs(3 * v + k, s);
    }
  for (int t = 0; t < m.rest.numFaces(); ++t)
    for (int k = 0; k < 3; ++k) f.data[3 * t + k] = m.rest.F(t, k);
  NpyArray jr = array({24, nv}), w = array({nv, 24}), kt = array({2, 24});
  const Eigen::SparseMatrix<double, Eigen::RowMajor> W = m.weights;
  for (int j = 0; j < 24; ++j) {
    kt.data[j] = kSmpl[j].parent < 0 ? 4294967295.0 : kSmpl[j].parent;
    kt.data[24 + j] = j;
    std::vector<int> sources;
    if (*kSmpl[j].mannequin) sources = {m.jointIndex(kSmpl[j].mannequin)};
    else sources = {m.jointIndex("spine"), m.jointIndex("chest")};
    for (int src : sources)
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(m.jointRegressor, src); it; ++it)
        jr.data[j * nv + it.col()] += it.value() / sources.size();
    if (*kSmpl[j].mannequin)
      for (size_t v = 0; v < nv; ++v) w.data[v * 24 + j] = W.coeff(v, m.jointIndex(kSmpl[j].mannequin));
  }
  a["v_template"] = vt;
  a["shapedirs"] = sd;
  a["posedirs"] = array({nv, 3, 9 * 23});
  a["J_regressor"] = jr;
  a["weights"] = w;
  a["kintree_table"] = kt;
  a["f"] = f;
  return smplModelFromArrays(a, "smpl:mannequin-as-smpl");
}

}  // namespace

const std::vector<BodySource>& bodySources() {
  static const std::vector<BodySource> cached = [] {
    std::vector<BodySource> s;
    MannequinOptions opt;
    opt.targetVertices = 8000;
    auto mannequin = std::make_shared<const BodyModel>(makeMannequin(opt));
    s.push_back({"mannequin", mannequin});
    s.push_back({"smpl", std::make_shared<const BodyModel>(smplFromMannequin(*mannequin))});
    std::filesystem::path dir;
    if (const char* env = std::getenv("S2P_MPFB2_DIR")) dir = env;
    else if (!sharedDir().empty()) dir = sharedDir() / "bodymodels" / "mpfb2";
    if (!dir.empty() && std::filesystem::exists(dir / "3dobjs" / "base.obj"))
      s.push_back({"mpfb2", std::make_shared<const BodyModel>(loadMpfb2(dir))});
    else
      std::printf("[ note ] MPFB2 body not found (../shared/bodymodels/mpfb2): skipping that source\n");
    return s;
  }();
  return cached;
}

}  // namespace s2p::test
