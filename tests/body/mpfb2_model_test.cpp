#include "body/mpfb2_model.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <numeric>
#include <set>
#include <tuple>

#include "body/mpfb2_files.h"
#include "body/posing.h"
#include "core/error.h"
#include "core/shapes.h"
#include "test_support.h"

namespace s2p {
namespace {

namespace fs = std::filesystem;

// ../shared/bodymodels/mpfb2, or $S2P_MPFB2_DIR (e.g. when building in a git worktree).
fs::path mpfb2Dir() {
  fs::path d;
  if (const char* env = std::getenv("S2P_MPFB2_DIR")) {
    d = env;
  } else {
    const fs::path shared = test::sharedDir();
    if (shared.empty()) return {};
    d = shared / "bodymodels" / "mpfb2";
  }
  return fs::exists(d / "3dobjs" / "base.obj") ? d : fs::path{};
}

#define SKIP_WITHOUT_MPFB2() \
  if (mpfb2Dir().empty())    \
  GTEST_SKIP() << "MPFB2 data not found at ../shared/bodymodels/mpfb2: skipping"

// The default model, loaded once for the whole test program.
struct Loaded {
  BodyModel model;
  Mpfb2Report report;
};
const Loaded& defaultModel() {
  static const Loaded loaded = [] {
    Loaded l;
    l.model = loadMpfb2(mpfb2Dir(), {}, &l.report);
    return l;
  }();
  return loaded;
}

Eigen::MatrixX3d shaped(const BodyModel& m, const Eigen::VectorXd& beta) {
  Eigen::VectorXd flat = m.shapeDirs * beta;
  Eigen::MatrixX3d V = m.rest.V;
  for (int v = 0; v < V.rows(); ++v) V.row(v) += flat.segment<3>(3 * v).transpose();
  return V;
}

int shapeIndex(const BodyModel& m, const std::string& name) {
  for (int s = 0; s < m.numShapes(); ++s)
    if (m.shapeParams[s].name == name) return s;
  return -1;
}

int joint(const BodyModel& m, const std::string& name) {
  for (int j = 0; j < m.numJoints(); ++j)
    if (m.jointNames[j] == name) return j;
  return -1;
}

// Per vertex, the skinning weight of the joints named (torso selection).
Eigen::VectorXd weightOn(const BodyModel& m, const std::vector<std::string>& names) {
  Eigen::VectorXd r = Eigen::VectorXd::Zero(m.numVertices());
  for (const auto& n : names) r += Eigen::MatrixXd(m.weights).col(joint(m, n));
  return r;
}

// x and z extents of the torso slice |y − y0| < 1 cm.
Eigen::Vector2d sliceExtent(const BodyModel& m, const Eigen::MatrixX3d& V, double y0) {
  const Eigen::VectorXd torso = weightOn(m, {"pelvis", "spine_01", "spine_02", "spine_03"});
  double xmin = 1e9, xmax = -1e9, zmin = 1e9, zmax = -1e9;
  for (int v = 0; v < V.rows(); ++v) {
    if (torso[v] < 0.5 || std::abs(V(v, 1) - y0) > 0.01) continue;
    xmin = std::min(xmin, V(v, 0)), xmax = std::max(xmax, V(v, 0));
    zmin = std::min(zmin, V(v, 2)), zmax = std::max(zmax, V(v, 2));
  }
  return {xmax - xmin, zmax - zmin};
}

// === Readers (no data folder needed)

TEST(Mpfb2Files, ObjReaderKeepsIndicesGroupsAndPolygons) {
  test::TempDir dir;
  test::writeFile(dir / "m.obj",
                  "# comment\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nvt 0 0\n"
                  "g body\nusemtl skin\nf 1/1 2/1 3/1 4/1\ng joint-a\nf 1//1 2//1 5//1\n");
  const Mpfb2Obj obj = readMpfb2Obj(dir / "m.obj");
  ASSERT_EQ(obj.V.rows(), 5);
  EXPECT_DOUBLE_EQ(obj.V(2, 1), 1.0);
  ASSERT_EQ(obj.faces.size(), 2u);
  EXPECT_EQ(obj.faces[0], (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(obj.groups[obj.faceGroup[1]], "joint-a");
  EXPECT_EQ(obj.groupVertices.at("joint-a"), (std::vector<int>{0, 1, 4}));
}

TEST(Mpfb2Files, ObjReaderRejectsBadIndexNamingTheFile) {
  test::TempDir dir;
  test::writeFile(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nf 1 2 7\n");
  try {
    readMpfb2Obj(dir / "bad.obj");
    FAIL() << "no exception";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.obj line 3"), std::string::npos) << e.what();
  }
}

TEST(Mpfb2Files, TargetReaderParsesMakeHumanNumbers) {
  test::TempDir dir;
  test::writeFile(dir / "t.target", "# offsets\n4243 -.003 0 -.5\n\n7 1.25 2 3\n");
  const Mpfb2Target t = readMpfb2Target(dir / "t.target", 5000);
  ASSERT_EQ(t.index, (std::vector<int>{4243, 7}));
  EXPECT_DOUBLE_EQ(t.delta[0].x(), -0.003);
  EXPECT_DOUBLE_EQ(t.delta[0].z(), -0.5);
  EXPECT_DOUBLE_EQ(t.delta[1].x(), 1.25);
  EXPECT_THROW(readMpfb2Target(dir / "t.target", 100), FormatError);  // 4243 out of range
  test::writeFile(dir / "u.target", "3 0.1 zz 0\n");
  EXPECT_THROW(readMpfb2Target(dir / "u.target", 100), FormatError);
  EXPECT_THROW(readMpfb2Target(dir / "none.target.gz", 100), IoError);
}

// === Closing the body mesh

std::vector<Eigen::Vector3i> trianglesOf(const TriMesh& m) {
  std::vector<Eigen::Vector3i> t;
  for (int f = 0; f < m.numFaces(); ++f) t.emplace_back(m.F.row(f).transpose());
  return t;
}

TEST(Mpfb2Mesh, OpenCylinderGetsBothEndsClosed) {
  const TriMesh cyl = makeCylinder(4, 12, 0.5, 2.0);  // two boundary loops of 12
  std::vector<Eigen::Vector3i> tris = trianglesOf(cyl);
  const MeshClosure c = closeTriangleMesh(tris, cyl.numVertices(), "cylinder");
  EXPECT_EQ(c.holes, 2);
  EXPECT_EQ(c.holeVertices, 24);
  EXPECT_EQ(c.splitVertices, 0);
  ASSERT_EQ(c.extra.size(), 2u);
  EXPECT_EQ(c.extra[0].size(), 12u);
  EXPECT_EQ(tris.size(), static_cast<size_t>(cyl.numFaces() + 24));
  // Closed and consistently oriented: every directed edge once, with its twin.
  std::set<std::pair<int, int>> directed;
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(directed.insert({t[k], t[(k + 1) % 3]}).second);
  for (const auto& [a, b] : directed) EXPECT_TRUE(directed.count({b, a})) << a << "-" << b;
  // Euler characteristic 2 with the two centroids added.
  EXPECT_EQ(
      cyl.numVertices() + 2 - static_cast<int>(directed.size()) / 2 + static_cast<int>(tris.size()),
      2);
}

TEST(Mpfb2Mesh, ClosedMeshIsLeftUntouched) {
  const TriMesh ico = makeIcosphere(1);
  std::vector<Eigen::Vector3i> tris = trianglesOf(ico);
  const MeshClosure c = closeTriangleMesh(tris, ico.numVertices(), "icosphere");
  EXPECT_EQ(c.holes + c.splitVertices, 0);
  EXPECT_EQ(tris, trianglesOf(ico));
}

TEST(Mpfb2Mesh, PinchedVertexIsSplitAndNonManifoldEdgeRejected) {
  // Two tetrahedra sharing vertex 0, joined elsewhere by nothing: the split leaves two
  // components, which is an error; sharing an edge (three faces on it) is an error too.
  const std::vector<Eigen::Vector3i> tet = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  std::vector<Eigen::Vector3i> two = tet;
  for (auto t : tet) {
    for (int k = 0; k < 3; ++k) t[k] = t[k] == 0 ? 0 : t[k] + 3;
    two.push_back(t);
  }
  try {
    closeTriangleMesh(two, 7, "bow-tie");
    ADD_FAILURE() << "no exception";
  } catch (const TopologyError& e) {  // without the split, vertex 0 would join them into one
    EXPECT_NE(std::string(e.what()).find("2 connected components"), std::string::npos) << e.what();
  }
  std::vector<Eigen::Vector3i> fin = tet;
  fin.emplace_back(0, 1, 4);  // a third face on edge 0-1
  EXPECT_THROW(closeTriangleMesh(fin, 5, "fin"), TopologyError);
}

// === MakeHuman macro weights (analytic values of human.py's slider mapping)

double familySum(const std::map<std::string, double>& w, const std::string& prefix,
                 bool excludeSub = false) {
  double s = 0;
  for (const auto& [n, x] : w)
    if (n.rfind(prefix, 0) == 0 && !(excludeSub && n.find('/', prefix.size()) != std::string::npos))
      s += x;
  return s;
}

TEST(Mpfb2Macro, DefaultSettingWeights) {
  const auto w = mpfb2MacroTargetWeights({});
  EXPECT_DOUBLE_EQ(w.at("macrodetails/universal-female-young-averagemuscle-averageweight"), 0.5);
  EXPECT_DOUBLE_EQ(w.at("macrodetails/universal-male-young-averagemuscle-averageweight"), 0.5);
  EXPECT_NEAR(w.at("macrodetails/caucasian-male-young"), 1.0 / 6, 1e-15);
  EXPECT_NEAR(w.at("macrodetails/asian-female-young"), 1.0 / 6, 1e-15);
  EXPECT_EQ(familySum(w, "macrodetails/height/"), 0.0);       // height 0.5: no target
  EXPECT_EQ(familySum(w, "macrodetails/proportions/"), 0.0);  // proportions 0.5: none
  EXPECT_EQ(w.size(), 8u);
}

TEST(Mpfb2Macro, SliderMappingsMatchMakeHuman) {
  Mpfb2Options o;
  o.age = 0.3;  // between child (0.1875) and young (0.5): young = 0.1125/0.3125 = 0.36
  o.gender = 0.2;
  o.weight = 0.8;   // average 0.4, max 0.6
  o.height = 0.75;  // maxheight 0.5
  o.ethnicity = "caucasian";
  const auto w = mpfb2MacroTargetWeights(o);
  EXPECT_NEAR(w.at("macrodetails/caucasian-female-young"), 0.8 * 0.36, 1e-12);
  EXPECT_NEAR(w.at("macrodetails/caucasian-male-child"), 0.2 * 0.64, 1e-12);
  EXPECT_NEAR(w.at("macrodetails/universal-female-child-averagemuscle-maxweight"), 0.8 * 0.64 * 0.6,
              1e-12);
  EXPECT_NEAR(familySum(w, "macrodetails/universal-"), 1.0, 1e-12);
  EXPECT_NEAR(familySum(w, "macrodetails/height/"), 0.5, 1e-12);
  EXPECT_NEAR(w.at("macrodetails/height/male-young-averagemuscle-averageweight-maxheight"),
              0.2 * 0.36 * 0.4 * 0.5, 1e-12);
  EXPECT_EQ(w.count("macrodetails/asian-female-young"), 0u);
  o.age = 0.75;  // young 0.5, old 0.5
  EXPECT_NEAR(mpfb2MacroTargetWeights(o).at("macrodetails/caucasian-female-old"), 0.8 * 0.5, 1e-12);
  o.age = 0.0;  // baby only
  EXPECT_NEAR(mpfb2MacroTargetWeights(o).at("macrodetails/caucasian-female-baby"), 0.8, 1e-12);
}

TEST(Mpfb2Macro, BadOptionsAreInputErrors) {
  Mpfb2Options o;
  o.weight = 1.5;
  EXPECT_THROW(loadMpfb2("/nonexistent", o), InputError);
  o = {};
  o.ethnicity = "martian";
  EXPECT_THROW(loadMpfb2("/nonexistent", o), InputError);
}

// === The shared MakeHuman data

TEST(Mpfb2Model, MeshIsClosedManifoldOneComponent) {
  SKIP_WITHOUT_MPFB2();
  const auto& [m, rep] = defaultModel();
  EXPECT_EQ(rep.bodyVertices, 13380);
  std::cout << "[ MPFB2 ] holes closed " << rep.holesClosed << " (" << rep.holeVertices
            << " vertices), split vertices " << rep.splitVertices << ", regressed joints "
            << rep.regressedJoints << "\n";
  EXPECT_EQ(rep.splitVertices, 0);
  EXPECT_EQ(m.numVertices(), rep.bodyVertices + rep.holesClosed);
  EXPECT_EQ(m.rest.numFaces(), 2 * 13378 + rep.holeVertices);  // quads → 2 triangles, fans
  std::map<std::pair<int, int>, int> directed;
  for (int f = 0; f < m.rest.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) ++directed[{m.rest.F(f, k), m.rest.F(f, (k + 1) % 3)}];
  for (const auto& [e, c] : directed) {
    ASSERT_EQ(c, 1) << "edge " << e.first << "-" << e.second << " repeated";
    ASSERT_EQ(directed.count({e.second, e.first}), 1u) << "boundary edge " << e.first;
  }
  // Euler characteristic of a closed genus-0 surface, and one component.
  const int E = static_cast<int>(directed.size()) / 2;
  EXPECT_EQ(m.numVertices() - E + m.rest.numFaces(), 2);
  std::vector<int> parent(m.numVertices());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& [e, c] : directed) parent[find(e.first)] = find(e.second);
  int roots = 0;
  for (int v = 0; v < m.numVertices(); ++v) roots += find(v) == v;
  EXPECT_EQ(roots, 1);
  // Outward orientation: positive signed volume.
  double vol = 0;
  for (int f = 0; f < m.rest.numFaces(); ++f)
    vol += m.rest.V.row(m.rest.F(f, 0))
               .dot(m.rest.V.row(m.rest.F(f, 1)).cross(m.rest.V.row(m.rest.F(f, 2)))) /
           6;
  EXPECT_GT(vol, 0.03);  // an adult body is ~0.06 m³
  EXPECT_LT(vol, 0.12);
}

TEST(Mpfb2Model, DefaultHeightAndFrame) {
  SKIP_WITHOUT_MPFB2();
  const auto& [m, rep] = defaultModel();
  const BoundingBox box = boundingBox(m.rest.V);
  const double height = box.extent().y();
  std::cout << "[ MPFB2 ] default height " << height << " m, " << rep.targetsRead
            << " targets read, " << m.numShapes() << " shape parameters\n";
  EXPECT_NEAR(box.min.y(), 0.0, 1e-12);  // feet on the floor
  EXPECT_GT(height, 1.55);
  EXPECT_LT(height, 1.85);
  EXPECT_NEAR(box.centre().x(), 0.0, 0.01);  // symmetric about x = 0
  EXPECT_EQ(rep.unweightedVertices, 0);
}

TEST(Mpfb2Model, WeightsAndRegressorRowsSumToOne) {
  SKIP_WITHOUT_MPFB2();
  const auto& m = defaultModel().model;
  ASSERT_EQ(m.weights.rows(), m.numVertices());
  ASSERT_EQ(m.weights.cols(), m.numJoints());
  const Eigen::VectorXd ws = m.weights * Eigen::VectorXd::Ones(m.numJoints());
  EXPECT_LT((ws.array() - 1).abs().maxCoeff(), 1e-9);
  EXPECT_GE(Eigen::MatrixXd(m.weights).minCoeff(), 0.0);
  ASSERT_EQ(m.jointRegressor.rows(), m.numJoints());
  ASSERT_EQ(m.jointRegressor.cols(), m.numVertices());
  const Eigen::VectorXd rs = m.jointRegressor * Eigen::VectorXd::Ones(m.numVertices());
  EXPECT_LT((rs.array() - 1).abs().maxCoeff(), 1e-9);
}

TEST(Mpfb2Model, SkeletonOrderSidesAndPlacement) {
  SKIP_WITHOUT_MPFB2();
  const auto& [m, rep] = defaultModel();
  ASSERT_EQ(m.numJoints(), 53);
  EXPECT_EQ(m.jointNames[0], "Root");
  EXPECT_EQ(m.parents[0], -1);
  for (int j = 1; j < m.numJoints(); ++j) EXPECT_LT(m.parents[j], j);
  EXPECT_EQ(m.jointNames[m.parents[joint(m, "calf_l")]], "thigh_l");
  const Eigen::MatrixX3d J = m.jointRegressor * m.rest.V;
  const BoundingBox box = boundingBox(m.rest.V);
  for (int j = 0; j < m.numJoints(); ++j) {
    const std::string& n = m.jointNames[j];
    for (int k = 0; k < 3; ++k) {  // 1 mm: Root is the ground cube, 0.5 mm under the soles
      EXPECT_GE(J(j, k), box.min[k] - 0.001) << n;
      EXPECT_LE(J(j, k), box.max[k] + 0.001) << n;
    }
    if (n.size() > 2 && n.substr(n.size() - 2) == "_l") {
      EXPECT_GT(J(j, 0), 0.0) << n;
    }
    if (n.size() > 2 && n.substr(n.size() - 2) == "_r") {
      EXPECT_LT(J(j, 0), 0.0) << n;
    }
  }
  // Anatomical order along y.
  EXPECT_GT(J(joint(m, "head"), 1), J(joint(m, "neck_01"), 1));
  EXPECT_GT(J(joint(m, "neck_01"), 1), J(joint(m, "spine_03"), 1));
  EXPECT_GT(J(joint(m, "pelvis"), 1), J(joint(m, "calf_l"), 1));
  EXPECT_GT(J(joint(m, "calf_l"), 1), J(joint(m, "foot_l"), 1));
  // The regressor reproduces the rig's own joint definition at rest.
  EXPECT_LT((J - rep.trueJoints).rowwise().norm().maxCoeff(), 1e-9);
}

TEST(Mpfb2Model, RegressedJointsTrackTheJointCubes) {
  SKIP_WITHOUT_MPFB2();
  const auto& [m, rep] = defaultModel();
  EXPECT_GT(rep.regressedJoints, 40);  // nearly all heads are joint cubes
  Eigen::VectorXd beta = Eigen::VectorXd::Zero(m.numShapes());
  beta[shapeIndex(m, "macro-weight")] = 3;
  beta[shapeIndex(m, "macro-height")] = -2;
  beta[shapeIndex(m, "macro-gender")] = 2;
  beta[shapeIndex(m, "measure-waist-circ")] = 1;
  const Eigen::MatrixX3d J = m.jointRegressor * shaped(m, beta);
  Eigen::MatrixX3d truth = rep.trueJoints;
  const Eigen::VectorXd flat = rep.trueJointDirs * beta;
  for (int j = 0; j < m.numJoints(); ++j) truth.row(j) += flat.segment<3>(3 * j).transpose();
  const double err = (J - truth).rowwise().norm().maxCoeff();
  std::cout << "[ MPFB2 ] in-shape-space joint regression error max " << err * 1000 << " mm\n";
  EXPECT_LT(err, 0.01);
}

TEST(Mpfb2Model, RegressorGeneralisesToAnotherMacroSetting) {
  SKIP_WITHOUT_MPFB2();
  const auto& m = defaultModel().model;
  Mpfb2Options o;
  o.weight = 0.9;
  o.muscle = 0.2;
  o.gender = 1.0;
  o.age = 0.8;
  Mpfb2Report rep2;
  const BodyModel other = loadMpfb2(mpfb2Dir(), o, &rep2);
  ASSERT_EQ(other.numVertices(), m.numVertices());
  const Eigen::MatrixX3d J = m.jointRegressor * other.rest.V;
  const Eigen::VectorXd err = (J - rep2.trueJoints).rowwise().norm();
  std::cout << "[ MPFB2 ] regressor at another macro setting: mean " << err.mean() * 1000
            << " mm, max " << err.maxCoeff() * 1000 << " mm\n";
  EXPECT_LT(err.mean(), 0.01);
  EXPECT_LT(err.maxCoeff(), 0.04);
}

TEST(Mpfb2Model, MacroHeightMakesTaller) {
  SKIP_WITHOUT_MPFB2();
  const auto& m = defaultModel().model;
  const int s = shapeIndex(m, "macro-height");
  ASSERT_GE(s, 0);
  Eigen::VectorXd beta = Eigen::VectorXd::Zero(m.numShapes());
  const double h0 = boundingBox(m.rest.V).extent().y();
  beta[s] = 1;
  const double h1 = boundingBox(shaped(m, beta)).extent().y();
  beta[s] = -1;
  const double hm = boundingBox(shaped(m, beta)).extent().y();
  std::cout << "[ MPFB2 ] macro-height ±1: " << hm << " / " << h0 << " / " << h1 << " m\n";
  EXPECT_GT(h1, h0 + 0.02);
  EXPECT_LT(hm, h0 - 0.02);
  EXPECT_DOUBLE_EQ(m.shapeParams[s].min, -5.0);  // slider 0.5 − 5·0.1 = 0
  EXPECT_DOUBLE_EQ(m.shapeParams[s].max, 5.0);
}

TEST(Mpfb2Model, MacroWeightWidensTheWaist) {
  SKIP_WITHOUT_MPFB2();
  const auto& m = defaultModel().model;
  const Eigen::MatrixX3d J = m.jointRegressor * m.rest.V;
  const double yWaist = J(joint(m, "spine_01"), 1);
  Eigen::VectorXd beta = Eigen::VectorXd::Zero(m.numShapes());
  beta[shapeIndex(m, "macro-weight")] = 3;
  const Eigen::Vector2d e0 = sliceExtent(m, m.rest.V, yWaist);
  const Eigen::Vector2d e1 = sliceExtent(m, shaped(m, beta), yWaist);
  std::cout << "[ MPFB2 ] waist width/depth " << e0.transpose() << " → " << e1.transpose()
            << " m at macro-weight +3\n";
  EXPECT_GT(e0.x(), 0.2);  // a waist, not an empty slice
  EXPECT_LT(e0.x(), 0.45);
  EXPECT_GT(e1.x(), e0.x() + 0.005);
  EXPECT_GT(e1.y(), e0.y() + 0.005);
  EXPECT_GT(e1.sum(), e0.sum() + 0.015);
}

TEST(Mpfb2Model, MeasureTargetsChangeTheirRegion) {
  SKIP_WITHOUT_MPFB2();
  const auto& m = defaultModel().model;
  const Eigen::MatrixX3d J = m.jointRegressor * m.rest.V;
  // Displacement-weighted mean height of each measure target vs the joint it belongs to.
  auto centroidY = [&](const std::string& name) {
    const int s = shapeIndex(m, name);
    EXPECT_GE(s, 0) << name;
    double sw = 0, sy = 0;
    for (int v = 0; v < m.numVertices(); ++v) {
      const double d = m.shapeDirs.block<3, 1>(3 * v, s).norm();
      sw += d, sy += d * m.rest.V(v, 1);
    }
    return sy / sw;
  };
  EXPECT_NEAR(centroidY("measure-waist-circ"), J(joint(m, "spine_01"), 1), 0.12);
  EXPECT_NEAR(centroidY("measure-neck-circ"), J(joint(m, "neck_01"), 1), 0.08);
  EXPECT_NEAR(centroidY("measure-calf-circ"),
              0.5 * (J(joint(m, "calf_l"), 1) + J(joint(m, "foot_l"), 1)), 0.15);
  Eigen::VectorXd beta = Eigen::VectorXd::Zero(m.numShapes());
  beta[shapeIndex(m, "measure-waist-circ")] = 1;
  const double yWaist = J(joint(m, "spine_01"), 1);
  const Eigen::Vector2d e0 = sliceExtent(m, m.rest.V, yWaist);
  const Eigen::Vector2d e1 = sliceExtent(m, shaped(m, beta), yWaist);
  EXPECT_GT(e1.x() + e1.y(), e0.x() + e0.y() + 0.005);
  // Only the measure pairs present in the data: 18 of them, plus 6 macro sliders.
  EXPECT_EQ(m.numShapes(), 24);
  Mpfb2Options noMeasure;
  noMeasure.includeMeasureTargets = false;
  EXPECT_EQ(loadMpfb2(mpfb2Dir(), noMeasure).numShapes(), 6);
}

TEST(Mpfb2Model, CanonicalPointsFollowTheRules) {
  SKIP_WITHOUT_MPFB2();
  const auto& m = defaultModel().model;
  const Eigen::MatrixX3d J = m.jointRegressor * m.rest.V;
  auto point = [&](Canonical c) {
    const CanonicalDef& d = m.canonical[static_cast<int>(c)];
    if (d.joint >= 0) return Eigen::Vector3d(J.row(d.joint).transpose());
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    double s = 0;
    for (const auto& [v, w] : d.vertices) p += w * m.rest.V.row(v).transpose(), s += w;
    EXPECT_NEAR(s, 1.0, 1e-12);
    return p;
  };
  for (int c = 0; c < kNumCanonical; ++c) {
    const CanonicalDef& d = m.canonical[c];
    EXPECT_TRUE(d.joint >= 0 || !d.vertices.empty()) << c;
  }
  const BoundingBox box = boundingBox(m.rest.V);
  EXPECT_NEAR(point(Canonical::HeadTop).y(), box.max.y(), 0.004);
  EXPECT_GT(point(Canonical::Nose).z(), point(Canonical::Head).z() + 0.05);  // faces +Z
  EXPECT_NEAR(point(Canonical::Nose).x(), 0.0, 0.01);
  EXPECT_GT(point(Canonical::Nose).y(), point(Canonical::Neck).y());
  for (int side = 0; side < 2; ++side) {
    const double sgn = side == 0 ? 1 : -1;
    const auto tip = point(side == 0 ? Canonical::LeftHandTip : Canonical::RightHandTip);
    const auto wrist = point(side == 0 ? Canonical::LeftWrist : Canonical::RightWrist);
    const auto toe = point(side == 0 ? Canonical::LeftToeTip : Canonical::RightToeTip);
    const auto heel = point(side == 0 ? Canonical::LeftHeel : Canonical::RightHeel);
    const auto ankle = point(side == 0 ? Canonical::LeftAnkle : Canonical::RightAnkle);
    EXPECT_GT(sgn * tip.x(), 0);
    EXPECT_LT(tip.y(), wrist.y() - 0.1);  // A-pose: fingers hang below the wrist
    EXPECT_GT(toe.z(), ankle.z() + 0.08);
    EXPECT_LT(heel.z(), ankle.z());
    EXPECT_LT(heel.y(), 0.02);
    EXPECT_NEAR(toe.y(), 0.02, 0.03);
    EXPECT_GT(sgn * point(side == 0 ? Canonical::LeftShoulder : Canonical::RightShoulder).x(), 0.1);
  }
}

TEST(Mpfb2Model, ValidatesAndPosesIntoATPose) {
  SKIP_WITHOUT_MPFB2();
  const auto& m = defaultModel().model;
  EXPECT_NO_THROW(m.validate());
  BodyParams params;
  params.shape = Eigen::VectorXd::Zero(m.numShapes());
  params.pose = BodyPose::zero(m.numJoints());
  const PosedBody rest = poseBody(m, params);
  EXPECT_LT((rest.mesh.V - m.rest.V).cwiseAbs().maxCoeff(), 1e-9);  // zero pose = template
  params.pose = standardPose(m, params.shape, StandardPose::TPose);
  const PosedBody t = poseBody(m, params);
  const auto c = [&](Canonical k) { return Eigen::Vector3d(t.canonical.row(static_cast<int>(k))); };
  // Arms horizontal: wrist and hand tip at shoulder height, far out along ±x.
  for (const auto& [sh, wr, tip, sgn] :
       {std::tuple{Canonical::LeftShoulder, Canonical::LeftWrist, Canonical::LeftHandTip, 1.0},
        std::tuple{Canonical::RightShoulder, Canonical::RightWrist, Canonical::RightHandTip,
                   -1.0}}) {
    EXPECT_NEAR(c(wr).y(), c(sh).y(), 0.03);
    EXPECT_NEAR(c(tip).y(), c(sh).y(), 0.06);
    EXPECT_GT(sgn * (c(tip).x() - c(sh).x()), 0.55);  // shoulder → fingertip of an adult
  }
  const double span = c(Canonical::LeftHandTip).x() - c(Canonical::RightHandTip).x();
  std::cout << "[ MPFB2 ] T-pose arm span " << span << " m\n";
  EXPECT_NEAR(span, boundingBox(m.rest.V).extent().y(), 0.12);  // span ≈ height (Vitruvian)
}

// === Errors naming the file

// A copy of the data folder made of symlinks, with `replace` (relative path) written anew.
void mirror(const fs::path& from, const fs::path& to, const fs::path& replace,
            const std::string* bytes) {
  fs::create_directories(to);
  for (const auto& e : fs::directory_iterator(from)) {
    const fs::path rel = e.path().filename();
    const auto r = replace.begin();
    if (!replace.empty() && rel == *r) {
      fs::path rest;
      for (auto it = std::next(r); it != replace.end(); ++it) rest /= *it;
      if (rest.empty()) {
        if (bytes) test::writeFile(to / rel, *bytes);
      } else {
        mirror(e.path(), to / rel, rest, bytes);
      }
    } else {
      fs::create_symlink(e.path(), to / rel);
    }
  }
}

template <class E>
std::string errorOf(const fs::path& dir) {
  try {
    loadMpfb2(dir);
  } catch (const E& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "wrong exception type: " << e.what();
    return "";
  }
  ADD_FAILURE() << "no exception for " << dir;
  return "";
}

TEST(Mpfb2Errors, MissingFolderIsIoError) {
  const std::string msg = errorOf<IoError>("/nonexistent/mpfb2_folder");
  EXPECT_NE(msg.find("/nonexistent/mpfb2_folder"), std::string::npos) << msg;
}

TEST(Mpfb2Errors, MissingFilesAreIoErrorsNamingThem) {
  SKIP_WITHOUT_MPFB2();
  for (const char* rel : {"3dobjs/base.obj", "rigs/standard/weights.game_engine.json",
                          "targets/macrodetails/caucasian-male-young.target.gz"}) {
    test::TempDir tmp;
    mirror(mpfb2Dir(), tmp.path() / "m", rel, nullptr);
    const std::string msg = errorOf<IoError>(tmp.path() / "m");
    EXPECT_NE(msg.find(fs::path(rel).filename().string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("missing"), std::string::npos) << msg;
  }
}

TEST(Mpfb2Errors, MalformedFilesAreFormatErrorsNamingThem) {
  SKIP_WITHOUT_MPFB2();
  const std::pair<const char*, std::string> cases[] = {
      {"rigs/standard/rig.game_engine.json", "{ \"Root\": { \"head\": "},
      {"rigs/standard/weights.game_engine.json", "{\"weights\": {\"pelvis\": [[1, \"x\"]]}}"},
      {"targets/macrodetails/macro.json", "{\"macrotargets\": {}}"},
      {"targets/macrodetails/caucasian-female-young.target.gz", "12 0.1 0.2\n"},
      {"3dobjs/base.obj", "v 0 0 0\nf 1 2 3\n"}};
  for (const auto& [rel, bytes] : cases) {
    test::TempDir tmp;
    mirror(mpfb2Dir(), tmp.path() / "m", rel, &bytes);
    const std::string msg = errorOf<FormatError>(tmp.path() / "m");
    EXPECT_NE(msg.find(fs::path(rel).filename().string()), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace s2p
