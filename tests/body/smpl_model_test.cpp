#include "body/smpl_model.h"

#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <numbers>
#include <random>

#include "body/npz.h"
#include "body/posing.h"
#include "core/error.h"
#include "test_support.h"

namespace s2p {
namespace {

using RowSparse = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// SMPL's 24 joints in a T-pose stick figure (metres, +Y up, facing +Z, left on +X).
const std::vector<Eigen::Vector3d> kJoints = {
    {0, 0.95, 0},      {0.09, 0.88, 0},    {-0.09, 0.88, 0},  {0, 1.05, 0},       {0.1, 0.5, 0},
    {-0.1, 0.5, 0},    {0, 1.18, 0},       {0.1, 0.1, -0.02}, {-0.1, 0.1, -0.02}, {0, 1.3, 0},
    {0.11, 0.03, 0.1}, {-0.11, 0.03, 0.1}, {0, 1.5, 0},       {0.07, 1.42, 0},    {-0.07, 1.42, 0},
    {0, 1.6, 0.02},    {0.18, 1.42, 0},    {-0.18, 1.42, 0},  {0.45, 1.42, 0},    {-0.45, 1.42, 0},
    {0.7, 1.42, 0},    {-0.7, 1.42, 0},    {0.78, 1.42, 0},   {-0.78, 1.42, 0}};
const std::vector<int> kParents = {-1, 0, 0, 0,  1,  2,  3,  4,  5,  6,  7,  8,
                                   9,  9, 9, 12, 13, 14, 16, 17, 18, 19, 20, 21};
constexpr int kNumShapes = 10;

struct Builder {
  std::vector<Eigen::Vector3d> V;
  std::vector<Eigen::Vector3i> F;
  std::vector<std::map<int, double>> W;    // per vertex: joint → weight
  std::vector<std::vector<int>> jointBox;  // per joint: the 8 vertices of its own cube

  // A closed box around segment a→b, half-thickness r; `wa`, `wb` skin its two ends.
  std::vector<int> box(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r,
                       const std::map<int, double>& wa, const std::map<int, double>& wb) {
    const Eigen::Vector3d d = (b - a).normalized();
    const Eigen::Vector3d u = d.unitOrthogonal(), v = d.cross(u);  // (u, v, d) right-handed
    const int base = static_cast<int>(V.size());
    std::vector<int> ids;
    for (int k = 0; k < 2; ++k)
      for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 2; ++i) {
          V.push_back((k ? b : a) + r * (2 * i - 1) * u + r * (2 * j - 1) * v);
          W.push_back(k ? wb : wa);
          ids.push_back(static_cast<int>(V.size()) - 1);
        }
    const int faces[12][3] = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4},
                              {2, 6, 7}, {2, 7, 3}, {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
    for (const auto& f : faces) F.emplace_back(base + f[0], base + f[1], base + f[2]);
    return ids;
  }
};

// Arrays of a synthetic SMPL-like model: a cube per joint (the regressor averages it, so the
// joints are exact), a box per bone skinned to the parent near it and blended at the child
// end, and extensions for fingers, toes, heels, head top and nose.
std::map<std::string, NpyArray> syntheticSmpl(unsigned seed = 1) {
  Builder b;
  b.jointBox.resize(24);
  for (int j = 0; j < 24; ++j) {
    const Eigen::Vector3d half(0, 0, 0.015);
    b.jointBox[j] = b.box(kJoints[j] - half, kJoints[j] + half, 0.015, {{j, 1.0}}, {{j, 1.0}});
  }
  for (int j = 1; j < 24; ++j) {
    const int p = kParents[j];
    b.box(kJoints[p], kJoints[j], 0.02, {{p, 1.0}}, {{p, 0.6}, {j, 0.4}});
  }
  for (int s = 0; s < 2; ++s) {
    const double x = s ? -1 : 1;
    b.box(kJoints[22 + s], kJoints[22 + s] + Eigen::Vector3d(0.1 * x, 0, 0), 0.01, {{22 + s, 1.0}},
          {{22 + s, 1.0}});  // fingers
    b.box(kJoints[10 + s], kJoints[10 + s] + Eigen::Vector3d(0, -0.01, 0.1), 0.012, {{10 + s, 1.0}},
          {{10 + s, 1.0}});  // toes
    b.box(kJoints[7 + s], Eigen::Vector3d(0.1 * x, 0.01, -0.06), 0.012, {{7 + s, 1.0}},
          {{7 + s, 1.0}});  // heel
  }
  b.box(kJoints[15], kJoints[15] + Eigen::Vector3d(0, 0.2, 0), 0.08, {{15, 1.0}}, {{15, 1.0}});
  b.box(kJoints[15], kJoints[15] + Eigen::Vector3d(0, 0, 0.12), 0.015, {{15, 1.0}},
        {{15, 1.0}});  // nose
  const size_t nv = b.V.size(), nf = b.F.size();

  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  std::map<std::string, NpyArray> a;
  auto make = [](std::vector<size_t> shape) {
    NpyArray x;
    x.shape = std::move(shape);
    x.data.assign(x.size(), 0.0);
    return x;
  };
  NpyArray vt = make({nv, 3}), f = make({nf, 3}), w = make({nv, 24}), jr = make({24, nv});
  for (size_t v = 0; v < nv; ++v) {
    for (int k = 0; k < 3; ++k) vt.data[3 * v + k] = b.V[v](k);
    for (const auto& [j, x] : b.W[v]) w.data[v * 24 + j] = x;
  }
  for (size_t i = 0; i < nf; ++i)
    for (int k = 0; k < 3; ++k) f.data[3 * i + k] = b.F[i](k);
  for (int j = 0; j < 24; ++j)
    for (int v : b.jointBox[j]) jr.data[j * nv + v] = 1.0 / 8;
  NpyArray kt = make({2, 24});
  for (int j = 0; j < 24; ++j) {
    kt.data[j] = j == 0 ? 4294967295.0 : kParents[j];
    kt.data[24 + j] = j;
  }
  NpyArray sd = make({nv, 3, kNumShapes}), pd = make({nv, 3, 207});
  for (double& x : sd.data) x = 0.01 * U(rng);
  for (double& x : pd.data) x = 0.002 * U(rng);
  a["v_template"] = vt;
  a["f"] = f;
  a["weights"] = w;
  a["J_regressor"] = jr;
  a["kintree_table"] = kt;
  a["shapedirs"] = sd;
  a["posedirs"] = pd;
  return a;
}

void writeModel(const std::filesystem::path& path, const std::map<std::string, NpyArray>& a) {
  std::vector<NpzEntry> entries;
  for (const auto& [name, array] : a) {
    NpzEntry e{name, array, "<f8", false, name != "posedirs", {}};  // mixed STORED / DEFLATED
    if (name == "kintree_table" || name == "f") e.dtype = name == "f" ? "<u4" : "<i8";
    if (name == "weights" || name == "posedirs") e.dtype = "<f4";  // as real files often are
    if (name == "J_regressor") e.fortranOrder = true;
    entries.push_back(e);
  }
  writeNpz(path, entries);
}

struct Loaded {
  test::TempDir dir;
  BodyModel model;
  std::map<std::string, NpyArray> arrays;
};

std::unique_ptr<Loaded> load() {
  auto l = std::make_unique<Loaded>();
  l->arrays = syntheticSmpl();
  writeModel(l->dir / "smpl.npz", l->arrays);
  l->model = loadSmplNpz(l->dir / "smpl.npz");
  return l;
}

TEST(SmplModel, LoadsArraysNamesAndTree) {
  const auto l = load();
  const BodyModel& m = l->model;
  EXPECT_NO_THROW(m.validate());
  EXPECT_EQ(m.numJoints(), 24);
  EXPECT_EQ(m.numShapes(), kNumShapes);
  EXPECT_EQ(m.parents, kParents);
  EXPECT_EQ(m.jointNames[16], "left_shoulder");
  EXPECT_EQ(m.jointNames[23], "right_hand");
  EXPECT_EQ(m.source.rfind("smpl:", 0), 0u);
  EXPECT_EQ(m.canonical[static_cast<int>(Canonical::LeftWrist)].joint, 20);
  EXPECT_EQ(m.canonical[static_cast<int>(Canonical::Chest)].joint, 9);
  EXPECT_EQ(m.canonical[static_cast<int>(Canonical::RightClavicle)].joint, 14);
  // Layouts: row 3v+k of shapeDirs / poseDirs is [v, k, :] of the file.
  const NpyArray& sd = l->arrays.at("shapedirs");
  const NpyArray& pd = l->arrays.at("posedirs");
  EXPECT_EQ(m.shapeDirs(3 * 17 + 2, 6), sd.at({17, 2, 6}));
  EXPECT_NEAR(m.poseDirs(3 * 40 + 1, 100), pd.at({40, 1, 100}), 1e-9);  // stored as float32
  // Weights rows sum to one (renormalised from float32), regressed joints are exact.
  for (int v = 0; v < m.numVertices(); ++v) EXPECT_NEAR(m.weights.row(v).sum(), 1.0, 1e-12);
  const Eigen::MatrixX3d J = m.jointRegressor * m.rest.V;
  for (int j = 0; j < 24; ++j) EXPECT_LT((J.row(j).transpose() - kJoints[j]).norm(), 1e-12) << j;
  // Every box is a closed 2-manifold: each directed edge appears once, its reverse once.
  std::map<std::pair<int, int>, int> directed;
  for (int f = 0; f < m.rest.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) ++directed[{m.rest.F(f, k), m.rest.F(f, (k + 1) % 3)}];
  for (const auto& [e, count] : directed) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({e.second, e.first}), 1u);
  }
}

TEST(SmplModel, LandmarksFollowGeometricRules) {
  const auto l = load();
  const BodyModel& m = l->model;
  auto at = [&](Canonical c) {
    const CanonicalDef& d = m.canonical[static_cast<int>(c)];
    EXPECT_EQ(d.joint, -1);
    EXPECT_EQ(d.vertices.size(), 1u);
    return Eigen::Vector3d(m.rest.V.row(d.vertices.at(0).first).transpose());
  };
  EXPECT_NEAR(at(Canonical::LeftHandTip).x(), 0.88, 1e-12);  // end of the finger box
  EXPECT_NEAR(at(Canonical::RightHandTip).x(), -0.88, 1e-12);
  EXPECT_NEAR(at(Canonical::LeftToeTip).z(), 0.2, 2.5e-3);  // end of the toe box
  EXPECT_GT(at(Canonical::LeftToeTip).x(), 0.0);
  EXPECT_LT(at(Canonical::RightToeTip).x(), 0.0);
  EXPECT_LT(at(Canonical::LeftHeel).z(), -0.06);
  EXPECT_LT(at(Canonical::LeftHeel).y(), 0.05);
  EXPECT_LT(at(Canonical::RightHeel).x(), 0.0);
  EXPECT_NEAR(at(Canonical::HeadTop).y(), 1.8, 1e-12);
  EXPECT_NEAR(at(Canonical::Nose).z(), 0.14, 1e-12);
}

TEST(SmplModel, ZeroPoseAndShapeReproduceTemplateExactly) {
  const auto l = load();
  const BodyModel& m = l->model;
  BodyParams p;
  p.shape = Eigen::VectorXd::Zero(m.numShapes());
  p.pose = BodyPose::zero(m.numJoints());
  const PosedBody b = poseBody(m, p);
  EXPECT_EQ((b.mesh.V - m.rest.V).cwiseAbs().maxCoeff(), 0.0);
}

TEST(SmplModel, LeftShoulderQuarterTurnLiftsWrist) {
  const auto l = load();
  const BodyModel& m = l->model;
  BodyParams p;
  p.pose = BodyPose::zero(m.numJoints());
  p.pose.axisAngle.row(16) = Eigen::RowVector3d(0, 0, std::numbers::pi / 2);
  const PosedBody b = poseBody(m, p);
  // The arm pointed to +X; 90° about +Z points it up: wrist 0.52 m above the shoulder.
  EXPECT_LT((b.joints.row(20) - Eigen::RowVector3d(0.18, 1.42 + 0.52, 0)).norm(), 1e-12);
  EXPECT_LT((b.joints.row(21) - Eigen::RowVector3d(-0.7, 1.42, 0)).norm(), 1e-12);
  // The left hand's own cube moved rigidly with it (weights 1 on joint 22).
  EXPECT_GT(b.canonical(static_cast<int>(Canonical::LeftHandTip), 1), 1.42 + 0.6);
}

TEST(SmplModel, PoseCorrectivesAreApplied) {
  const auto l = load();
  const BodyModel& m = l->model;
  BodyModel plain = m;
  plain.poseDirs.resize(0, 0);
  BodyParams p;
  p.pose = BodyPose::zero(m.numJoints());
  p.pose.axisAngle.row(18) = Eigen::RowVector3d(0, 0.7, 0);  // left elbow
  const PosedBody a = poseBody(m, p), c = poseBody(plain, p);
  Eigen::VectorXd feat = Eigen::VectorXd::Zero(207);
  const Eigen::Matrix3d R = axisAngleToMatrix(Eigen::Vector3d(0, 0.7, 0));
  for (int r = 0; r < 3; ++r)
    for (int s = 0; s < 3; ++s) feat(9 * 17 + 3 * r + s) = R(r, s) - (r == s);
  // Vertex of the pelvis cube: skinned rigidly by the unrotated root, so the corrective shows
  // up unrotated.
  const int v = 0;
  const Eigen::Vector3d expect = m.poseDirs.middleRows(3 * v, 3) * feat;
  EXPECT_LT((a.mesh.V.row(v) - c.mesh.V.row(v) - expect.transpose()).norm(), 1e-14);
  EXPECT_GT(expect.norm(), 1e-4);
}

TEST(SmplModel, JacobiansMatchFiniteDifferences) {
  const auto l = load();
  const BodyModel& m = l->model;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  BodyParams p;
  p.shape = Eigen::VectorXd(m.numShapes());
  for (int s = 0; s < m.numShapes(); ++s) p.shape(s) = 2 * U(rng);
  p.pose = BodyPose::zero(m.numJoints());
  for (int i = 0; i < p.pose.axisAngle.size(); ++i) p.pose.axisAngle.data()[i] = 0.5 * U(rng);
  p.pose.axisAngle.row(4).setZero();  // one joint exactly at θ = 0
  p.pose.translation = Eigen::Vector3d(0.2, -0.1, 0.4);
  std::vector<int> verts;
  for (int v = 0; v < m.numVertices(); v += 11) verts.push_back(v);
  const Eigen::MatrixXd jv = posedVertexJacobian(m, p, verts);
  const Eigen::MatrixXd jj = posedJointJacobian(m, p);
  const Eigen::MatrixXd jc = posedCanonicalJacobian(m, p);
  const int P = numPoseParams(m);
  ASSERT_EQ(P, kNumShapes + 72 + 3);
  Eigen::MatrixXd fv(jv.rows(), P), fj(jj.rows(), P), fc(jc.rows(), P);
  const double h = 1e-6;
  for (int i = 0; i < P; ++i) {
    BodyParams lo = p, hi = p;
    if (i < kNumShapes) {
      lo.shape(i) -= h, hi.shape(i) += h;
    } else if (i < kNumShapes + 72) {
      lo.pose.axisAngle((i - kNumShapes) / 3, (i - kNumShapes) % 3) -= h;
      hi.pose.axisAngle((i - kNumShapes) / 3, (i - kNumShapes) % 3) += h;
    } else {
      lo.pose.translation(i - kNumShapes - 72) -= h;
      hi.pose.translation(i - kNumShapes - 72) += h;
    }
    const PosedBody a = poseBody(m, hi), b = poseBody(m, lo);
    for (size_t r = 0; r < verts.size(); ++r)
      fv.block(3 * r, i, 3, 1) =
          (a.mesh.V.row(verts[r]) - b.mesh.V.row(verts[r])).transpose() / (2 * h);
    for (int j = 0; j < 24; ++j)
      fj.block(3 * j, i, 3, 1) = (a.joints.row(j) - b.joints.row(j)).transpose() / (2 * h);
    for (int c = 0; c < kNumCanonical; ++c)
      fc.block(3 * c, i, 3, 1) = (a.canonical.row(c) - b.canonical.row(c)).transpose() / (2 * h);
  }
  EXPECT_LT((jv - fv).norm() / fv.norm(), 1e-5);
  EXPECT_LT((jj - fj).norm() / fj.norm(), 1e-5);
  EXPECT_LT((jc - fc).norm() / fc.norm(), 1e-5);
}

TEST(SmplModel, UnposingInvertsPosing) {
  const auto l = load();
  BodyModel m = l->model;
  m.poseDirs.resize(0, 0);  // without correctives, unposing returns the shaped template
  BodyParams p;
  p.shape = Eigen::VectorXd::LinSpaced(m.numShapes(), -1, 1);
  p.pose = BodyPose::zero(m.numJoints());
  p.pose.axisAngle.row(0) = Eigen::RowVector3d(0.1, 0.3, -0.2);
  p.pose.axisAngle.row(18) = Eigen::RowVector3d(0, 1.2, 0);
  p.pose.axisAngle.row(4) = Eigen::RowVector3d(0.8, 0, 0);
  p.pose.translation = Eigen::Vector3d(1, 2, 3);
  const PosedBody b = poseBody(m, p);
  const Eigen::MatrixX3d back = unposeSkinned(b, m.weights, b.mesh.V);
  EXPECT_LT((back - shapedTemplate(m, p.shape)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(SmplModel, MissingKeysAndBadArraysAreFormatErrors) {
  test::TempDir dir;
  const auto good = syntheticSmpl();
  for (const char* key : {"weights", "posedirs", "kintree_table", "f", "J_regressor"}) {
    auto a = good;
    a.erase(key);
    writeModel(dir / "m.npz", a);
    try {
      loadSmplNpz(dir / "m.npz");
      FAIL() << "accepted a model without " << key;
    } catch (const FormatError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
  auto a = good;
  a["kintree_table"].data[5] = 9;  // joint 5's parent after it
  writeModel(dir / "tree.npz", a);
  EXPECT_THROW(loadSmplNpz(dir / "tree.npz"), FormatError);
  a = good;
  a["posedirs"].shape = {a["posedirs"].shape[0], 9, 69};
  writeModel(dir / "posedirs.npz", a);
  EXPECT_THROW(loadSmplNpz(dir / "posedirs.npz"), FormatError);
  a = good;
  a["f"].data[7] = 1e6;
  writeModel(dir / "faces.npz", a);
  EXPECT_THROW(loadSmplNpz(dir / "faces.npz"), FormatError);
  EXPECT_THROW(loadSmplNpz(dir / "absent.npz"), IoError);
}

TEST(SmplModel, JointNamesOfTheFamily) {
  const auto smplh = smplJointNames(52), smplx = smplJointNames(55);
  EXPECT_EQ(smplh[21], "right_wrist");
  EXPECT_EQ(smplh[22], "left_index1");
  EXPECT_EQ(smplh[51], "right_thumb3");
  EXPECT_EQ(smplx[22], "jaw");
  EXPECT_EQ(smplx[25], "left_index1");
  EXPECT_EQ(smplx[40], "right_index1");
  EXPECT_EQ(smplx[54], "right_thumb3");
  EXPECT_THROW(smplJointNames(30), FormatError);
}

}  // namespace
}  // namespace s2p
