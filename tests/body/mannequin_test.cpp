// The built-in mannequin: closed template, height, symmetry, skinning weights, skeleton,
// and tape-measured girths that follow the shape parameters through the linear blend shapes.
#include "body/mannequin.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <unordered_map>

#include "core/error.h"

namespace s2p {
namespace {

// The default body, built once for the whole program (a few seconds).
const BodyModel& defaultMannequin() {
  static const BodyModel model = makeMannequin();
  return model;
}

// A coarse body for the quick structural tests (also run under sanitizers).
const BodyModel& coarseMannequin() {
  static const BodyModel model = makeMannequin({.targetVertices = 3000, .base = {}});
  return model;
}

// T(β) = rest + shapeDirs·β, #V×3.
Eigen::MatrixX3d shaped(const BodyModel& m, const Eigen::VectorXd& beta) {
  const Eigen::VectorXd flat = m.shapeDirs * beta;
  Eigen::MatrixX3d V = m.rest.V;
  for (int v = 0; v < m.numVertices(); ++v)
    for (int k = 0; k < 3; ++k) V(v, k) += flat[3 * v + k];
  return V;
}

Eigen::VectorXd unitStep(int param, double amount) {
  Eigen::VectorXd b = Eigen::VectorXd::Zero(kMannequinShapes);
  b[param] = amount;
  return b;
}

// === A tape measure written for the test: the plane section loop enclosing `p`, its convex
// hull perimeter (what a tape reads around a body part).
double cross2(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

double convexHullPerimeter(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  std::vector<Eigen::Vector2d> h;
  for (int pass = 0; pass < 2; ++pass) {
    const size_t start = h.size();
    for (const auto& q : p) {
      while (h.size() >= start + 2 && cross2(h[h.size() - 2], h.back(), q) <= 0) h.pop_back();
      h.push_back(q);
    }
    h.pop_back();
    std::reverse(p.begin(), p.end());
  }
  double len = 0;
  for (size_t i = 0; i < h.size(); ++i) len += (h[(i + 1) % h.size()] - h[i]).norm();
  return len;
}

double tapeGirth(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::Vector3d& p,
                 const Eigen::Vector3d& normal) {
  const Eigen::Vector3d n = normal.normalized();
  Eigen::Vector3d e1 = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  e1 = (e1 - e1.dot(n) * n).normalized();
  const Eigen::Vector3d e2 = n.cross(e1);
  auto side = [&](int v) { return (V.row(v).transpose() - p).dot(n); };
  std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> adj;
  auto key = [](int a, int b) { return std::make_pair(std::min(a, b), std::max(a, b)); };
  for (int f = 0; f < F.rows(); ++f) {
    std::vector<std::pair<int, int>> cut;
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      if ((side(a) >= 0) != (side(b) >= 0)) cut.push_back(key(a, b));
    }
    if (cut.size() == 2) {
      adj[cut[0]].push_back(cut[1]);
      adj[cut[1]].push_back(cut[0]);
    }
  }
  auto at = [&](const std::pair<int, int>& e) {
    const double sa = side(e.first), sb = side(e.second), l = sa / (sa - sb);
    const Eigen::Vector3d q = ((1 - l) * V.row(e.first) + l * V.row(e.second)).transpose() - p;
    return Eigen::Vector2d(q.dot(e1), q.dot(e2));
  };
  std::set<std::pair<int, int>> seen;
  double best = -1, bestArea = 1e9;
  for (const auto& [start, _] : adj) {
    if (seen.count(start)) continue;
    std::vector<Eigen::Vector2d> loop;
    std::pair<int, int> cur = start;
    while (!seen.count(cur)) {
      seen.insert(cur);
      loop.push_back(at(cur));
      for (const auto& nx : adj[cur])
        if (!seen.count(nx)) {
          cur = nx;
          break;
        }
    }
    bool inside = false;
    double area = 0;
    for (size_t i = 0; i < loop.size(); ++i) {
      const auto& a = loop[i];
      const auto& b = loop[(i + 1) % loop.size()];
      area += 0.5 * (a.x() * b.y() - a.y() * b.x());
      if ((a.y() > 0) != (b.y() > 0) && a.x() - a.y() * (b.x() - a.x()) / (b.y() - a.y()) > 0)
        inside = !inside;
    }
    if (inside && std::abs(area) < bestArea) {
      bestArea = std::abs(area);
      best = convexHullPerimeter(loop);
    }
  }
  return best;
}

struct Girths {
  double chest, waist, hip, thigh, neck, upperArm;
};

// Tape girths of vertices V (same faces as the model) at the places the measurements define.
Girths measure(const BodyModel& m, const Eigen::MatrixX3d& V, const MannequinMeasurements& mm) {
  const MannequinLevels lv = mannequinLevels(mm);
  const MannequinImplicit where(mm);  // only for the tape positions on the limbs
  const Eigen::Vector3d Y = Eigen::Vector3d::UnitY();
  Eigen::Vector3d nArm, nNeck;
  const Eigen::Vector3d cArm = where.upperArmTapeCentre(true, &nArm);
  const Eigen::Vector3d cNeck = where.neckTapeCentre(&nNeck);
  return {tapeGirth(V, m.rest.F, {0, lv.chest, 0}, Y),
          tapeGirth(V, m.rest.F, {0, lv.waist, 0}, Y),
          tapeGirth(V, m.rest.F, {0, lv.hip, 0}, Y),
          tapeGirth(V, m.rest.F, where.thighTapeCentre(true), Y),
          tapeGirth(V, m.rest.F, cNeck, nNeck),
          tapeGirth(V, m.rest.F, cArm, nArm)};
}

// === Topology: every undirected edge in exactly two faces with opposite orientations, one
// fan per vertex, one component, Euler characteristic 2.
void expectClosedSphere(const TriMesh& mesh) {
  std::map<std::pair<int, int>, int> directed;
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) ++directed[{mesh.F(f, k), mesh.F(f, (k + 1) % 3)}];
  int bad = 0;
  std::set<std::pair<int, int>> undirected;
  for (const auto& [e, c] : directed) {
    undirected.insert({std::min(e.first, e.second), std::max(e.first, e.second)});
    const auto it = directed.find({e.second, e.first});
    if (c != 1 || it == directed.end() || it->second != 1) ++bad;
  }
  EXPECT_EQ(bad, 0) << "edges not shared by exactly two oppositely oriented faces";
  const long long chi =
      mesh.numVertices() - static_cast<long long>(undirected.size()) + mesh.numFaces();
  EXPECT_EQ(chi, 2);
  // Fans: faces around each vertex form one cycle.
  std::vector<std::unordered_map<int, int>> next(mesh.numVertices());
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) next[mesh.F(f, k)][mesh.F(f, (k + 1) % 3)] = mesh.F(f, (k + 2) % 3);
  int badFans = 0;
  for (int v = 0; v < mesh.numVertices(); ++v) {
    ASSERT_FALSE(next[v].empty()) << "unreferenced vertex " << v;
    int w = next[v].begin()->first;
    size_t steps = 0;
    do {
      const auto it = next[v].find(w);
      if (it == next[v].end()) break;
      w = it->second;
      ++steps;
    } while (w != next[v].begin()->first && steps <= next[v].size());
    if (steps != next[v].size()) ++badFans;
  }
  EXPECT_EQ(badFans, 0);
  // One component (vertex flood fill along edges).
  std::vector<std::vector<int>> nb(mesh.numVertices());
  for (const auto& [a, b] : undirected) nb[a].push_back(b), nb[b].push_back(a);
  std::vector<char> seen(mesh.numVertices(), 0);
  std::vector<int> stack = {0};
  seen[0] = 1;
  int reached = 1;
  while (!stack.empty()) {
    const int v = stack.back();
    stack.pop_back();
    for (int w : nb[v])
      if (!seen[w]) seen[w] = 1, ++reached, stack.push_back(w);
  }
  EXPECT_EQ(reached, mesh.numVertices());
}

TEST(MannequinQuick, CoarseTemplateIsClosedSphereWithValidRig) {
  const BodyModel& m = coarseMannequin();
  expectClosedSphere(m.rest);
  EXPECT_EQ(m.numShapes(), kMannequinShapes);
  EXPECT_EQ(m.numJoints(), kMjCount);
  // Skinning rows: ≥ 0, ≤ 4 non-zeros, sum to one.
  for (int v = 0; v < m.numVertices(); ++v) {
    double sum = 0;
    int nnz = 0;
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(m.weights, v); it; ++it) {
      EXPECT_GE(it.value(), 0.0);
      sum += it.value();
      ++nnz;
    }
    EXPECT_LE(nnz, 4);
    EXPECT_NEAR(sum, 1.0, 1e-9);
  }
  // Regressor reproduces the implicit body's joints exactly at β = 0, rows sum to one.
  const Eigen::MatrixXd J = m.jointRegressor * m.rest.V;
  const MannequinImplicit body{MannequinMeasurements{}};
  for (int j = 0; j < m.numJoints(); ++j) {
    EXPECT_NEAR(m.jointRegressor.row(j).sum(), 1.0, 1e-9);
    EXPECT_LT((J.row(j) - body.joints().row(j)).norm(), 1e-9) << m.jointNames[j];
    EXPECT_LT(m.parents[j], j);
  }
}

TEST(MannequinQuick, BadInputThrowsInputError) {
  EXPECT_THROW(makeMannequin({.targetVertices = 10, .base = {}}), InputError);
  MannequinOptions o;
  o.base.height = -1;
  EXPECT_THROW(makeMannequin(o), InputError);
  o.base.height = std::nan("");
  EXPECT_THROW(makeMannequin(o), InputError);
  o.base = {};
  o.base.waist = 5.0;  // not a person
  EXPECT_THROW(makeMannequin(o), InputError);
  EXPECT_THROW(mannequinMeasurements({}, Eigen::VectorXd::Zero(3)), InputError);
}

TEST(MannequinQuick, MeasurementsAndShapeVectorAreInverse) {
  MannequinMeasurements target;
  target.chest = 1.02;
  target.inseam = 0.78;
  const Eigen::VectorXd beta = mannequinShapeFor({}, target);
  EXPECT_NEAR(beta[1], 6.0, 1e-9);
  EXPECT_NEAR(beta[6], -2.0, 1e-9);
  const MannequinMeasurements back = mannequinMeasurements({}, beta);
  EXPECT_NEAR(back.chest, 1.02, 1e-12);
  EXPECT_NEAR(back.inseam, 0.78, 1e-12);
}

// The implicit body reads back its own measurements (the calibration's job).
TEST(MannequinQuick, ImplicitTapesReadTheRequestedMeasurements) {
  MannequinMeasurements m;
  m.height = 1.68;
  m.chest = 1.05;
  m.hip = 1.08;
  m.neck = 0.36;
  const MannequinImplicit body(m);
  const MannequinLevels lv = mannequinLevels(m);
  EXPECT_NEAR(body.headTop(), 1.68, 1e-5);
  EXPECT_NEAR(body.crotch(), m.inseam, 1e-5);
  EXPECT_NEAR(body.sectionGirth({0, lv.chest, 0}, Eigen::Vector3d::UnitY()), 1.05, 1e-5);
  EXPECT_NEAR(body.sectionGirth({0, lv.hip, 0}, Eigen::Vector3d::UnitY()), 1.08, 1e-5);
  Eigen::Vector3d n;
  const Eigen::Vector3d c = body.neckTapeCentre(&n);
  EXPECT_NEAR(body.sectionGirth(c, n), 0.36, 1e-5);
  EXPECT_NEAR((body.joints().row(kMjLeftShoulder) - body.joints().row(kMjRightShoulder)).norm(),
              m.shoulder, 1e-12);
  const double arm = (body.joints().row(kMjLeftShoulder) - body.joints().row(kMjLeftElbow)).norm() +
                     (body.joints().row(kMjLeftElbow) - body.joints().row(kMjLeftWrist)).norm();
  EXPECT_NEAR(arm, m.armLength, 1e-12);
}

// === Full-resolution default body

TEST(Mannequin, DefaultTemplateIsClosedSphereOf10kTo20kVertices_Slow) {
  const BodyModel& m = defaultMannequin();
  EXPECT_GE(m.numVertices(), 10000);
  EXPECT_LE(m.numVertices(), 20000);
  expectClosedSphere(m.rest);
  EXPECT_EQ(m.source, "mannequin");
}

TEST(Mannequin, HeightFeetAndHeightBlendShape_Slow) {
  const BodyModel& m = defaultMannequin();
  EXPECT_NEAR(m.rest.V.col(1).maxCoeff(), 1.75, 0.005);
  EXPECT_NEAR(m.rest.V.col(1).minCoeff(), 0.0, 0.003);
  const Eigen::MatrixX3d T = shaped(m, unitStep(0, 5.0));  // +5 cm height
  EXPECT_NEAR(T.col(1).maxCoeff() - T.col(1).minCoeff(), 1.80, 0.005);
  // Faces +Z: the nose is in front of the head's centre, toes in front of heels.
  const auto& nose = m.canonical[static_cast<int>(Canonical::Nose)].vertices;
  ASSERT_FALSE(nose.empty());
  EXPECT_GT(m.rest.V(nose[0].first, 2), 0.08);
}

TEST(Mannequin, MirrorSymmetric_Slow) {
  const BodyModel& m = defaultMannequin();
  // Hash the vertices in 1 cm cells; each mirrored vertex must land on a vertex.
  const double cell = 0.01;
  auto cellOf = [&](const Eigen::Vector3d& p) {
    return std::make_tuple(static_cast<int>(std::floor(p.x() / cell)),
                           static_cast<int>(std::floor(p.y() / cell)),
                           static_cast<int>(std::floor(p.z() / cell)));
  };
  std::map<std::tuple<int, int, int>, std::vector<int>> grid;
  for (int v = 0; v < m.numVertices(); ++v) grid[cellOf(m.rest.V.row(v))].push_back(v);
  double worst = 0;
  for (int v = 0; v < m.numVertices(); ++v) {
    Eigen::Vector3d q = m.rest.V.row(v);
    q.x() = -q.x();
    const auto [cx, cy, cz] = cellOf(q);
    double best = 1e9;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find({cx + dx, cy + dy, cz + dz});
          if (it == grid.end()) continue;
          for (int w : it->second) best = std::min(best, (m.rest.V.row(w).transpose() - q).norm());
        }
    worst = std::max(worst, best);
  }
  EXPECT_LT(worst, 0.008);  // vertex positions mirror within a fraction of an edge
  // and the mirrored vertices lie on the surface itself.
  const MannequinImplicit body{MannequinMeasurements{}};
  double off = 0;
  for (int v = 0; v < m.numVertices(); ++v) {
    Eigen::Vector3d q = m.rest.V.row(v);
    q.x() = -q.x();
    off = std::max(off, std::abs(body.value(q)));
  }
  EXPECT_LT(off, 0.0005);
}

TEST(Mannequin, GirthsEqualParametersAtDefaultAndAfterSteps_Slow) {
  const BodyModel& m = defaultMannequin();
  const MannequinMeasurements base;
  const Girths g = measure(m, m.rest.V, base);
  EXPECT_NEAR(g.chest, base.chest, 0.01);
  EXPECT_NEAR(g.waist, base.waist, 0.01);
  EXPECT_NEAR(g.hip, base.hip, 0.01);
  EXPECT_NEAR(g.thigh, base.thigh, 0.01);
  EXPECT_NEAR(g.neck, base.neck, 0.01);
  EXPECT_NEAR(g.upperArm, base.upperArm, 0.01);
  // +5 cm of each girth through the linear blend shape.
  const int params[] = {1, 2, 3, 7, 8, 9};
  for (int p : params) {
    const Eigen::VectorXd beta = unitStep(p, 5.0);
    const MannequinMeasurements want = mannequinMeasurements(base, beta);
    const Girths s = measure(m, shaped(m, beta), want);
    EXPECT_NEAR(s.chest, want.chest, 0.01) << m.shapeParams[p].name;
    EXPECT_NEAR(s.waist, want.waist, 0.01) << m.shapeParams[p].name;
    EXPECT_NEAR(s.hip, want.hip, 0.01) << m.shapeParams[p].name;
    EXPECT_NEAR(s.thigh, want.thigh, 0.01) << m.shapeParams[p].name;
    EXPECT_NEAR(s.neck, want.neck, 0.01) << m.shapeParams[p].name;
    EXPECT_NEAR(s.upperArm, want.upperArm, 0.01) << m.shapeParams[p].name;
  }
}

// How linear the blend shapes are: girths of the linear model at −6, −2, +2, +6 cm steps
// against the requested values (printed; all within 1 cm).
TEST(Mannequin, BlendShapesStayLinearToSixCentimetres_Slow) {
  const BodyModel& m = defaultMannequin();
  const int params[] = {1, 2, 3, 7, 8, 9};
  for (int p : params)
    for (double step : {-6.0, -2.0, 2.0, 6.0}) {
      const Eigen::VectorXd beta = unitStep(p, step);
      const MannequinMeasurements want = mannequinMeasurements({}, beta);
      const Girths g = measure(m, shaped(m, beta), want);
      const double got[] = {g.chest, g.waist, g.hip, g.neck, g.thigh, g.upperArm};
      const double req[] = {want.chest, want.waist, want.hip, want.neck, want.thigh, want.upperArm};
      const int idx = p == 1 ? 0 : p == 2 ? 1 : p == 3 ? 2 : p == 7 ? 3 : p == 8 ? 4 : 5;
      std::printf("  %-9s %+4.0f cm: tape %.4f m, requested %.4f m, error %+.1f mm\n",
                  m.shapeParams[p].name.c_str(), step, got[idx], req[idx],
                  1000 * (got[idx] - req[idx]));
      EXPECT_NEAR(got[idx], req[idx], 0.01) << m.shapeParams[p].name << " " << step;
    }
}

// Fit to a requested set of measurements: β from the measurements, read them back.
TEST(Mannequin, FitToRequestedMeasurementsReadsThemBack_Slow) {
  const BodyModel& m = defaultMannequin();
  MannequinMeasurements want;
  want.height = 1.80;
  want.chest = 1.02;
  want.waist = 0.90;
  want.hip = 1.03;
  want.inseam = 0.83;
  want.thigh = 0.59;
  const Eigen::MatrixX3d T = shaped(m, mannequinShapeFor({}, want));
  const Girths g = measure(m, T, want);
  EXPECT_NEAR(T.col(1).maxCoeff() - T.col(1).minCoeff(), want.height, 0.01);
  EXPECT_NEAR(g.chest, want.chest, 0.01);
  EXPECT_NEAR(g.waist, want.waist, 0.01);
  EXPECT_NEAR(g.hip, want.hip, 0.01);
  EXPECT_NEAR(g.thigh, want.thigh, 0.01);
}

TEST(Mannequin, RegressedJointsTrackTheImplicitJoints_Slow) {
  const BodyModel& m = defaultMannequin();
  double worst = 0;
  for (int p = 0; p < kMannequinShapes; ++p) {
    const Eigen::VectorXd beta = unitStep(p, 5.0);
    const Eigen::MatrixXd J = m.jointRegressor * shaped(m, beta);
    const MannequinImplicit body(mannequinMeasurements({}, beta));
    for (int j = 0; j < m.numJoints(); ++j) {
      const double e = (J.row(j) - body.joints().row(j)).norm();
      worst = std::max(worst, e);
      EXPECT_LT(e, 0.006) << m.shapeParams[p].name << " " << m.jointNames[j];
    }
  }
  std::printf("  worst regressed-joint error over +5 cm steps: %.1f mm\n", 1000 * worst);
}

TEST(Mannequin, SkinningWeightsFollowTheLimbs_Slow) {
  const BodyModel& m = defaultMannequin();
  const MannequinImplicit body{MannequinMeasurements{}};
  auto nearest = [&](const Eigen::Vector3d& p) {
    int best = 0;
    for (int v = 1; v < m.numVertices(); ++v)
      if ((m.rest.V.row(v).transpose() - p).norm() < (m.rest.V.row(best).transpose() - p).norm())
        best = v;
    return best;
  };
  const auto& J = body.joints();
  // Surface above the mid forearm / mid thigh / mid upper arm: mostly that bone's joint.
  const Eigen::Vector3d forearm = 0.5 * (J.row(kMjLeftElbow) + J.row(kMjLeftWrist)).transpose();
  EXPECT_GT(m.weights.coeff(nearest(forearm + Eigen::Vector3d(0, 0, 0.05)), kMjLeftElbow), 0.8);
  const Eigen::Vector3d thigh = 0.5 * (J.row(kMjRightHip) + J.row(kMjRightKnee)).transpose();
  EXPECT_GT(m.weights.coeff(nearest(thigh + Eigen::Vector3d(0, 0, 0.1)), kMjRightHip), 0.8);
  const int top = nearest({0, 1.8, 0});
  EXPECT_NEAR(m.weights.coeff(top, kMjHead), 1.0, 1e-6);
  // The wrist blends forearm (elbow joint) and hand (wrist joint).
  const int wrist = nearest(J.row(kMjLeftWrist).transpose() + Eigen::Vector3d(0, 0, 0.05));
  EXPECT_GT(m.weights.coeff(wrist, kMjLeftElbow), 0.1);
  EXPECT_GT(m.weights.coeff(wrist, kMjLeftWrist), 0.1);
}

TEST(Mannequin, CanonicalPointsByRule_Slow) {
  const BodyModel& m = defaultMannequin();
  auto point = [&](Canonical c) {
    const CanonicalDef& d = m.canonical[static_cast<int>(c)];
    if (d.joint >= 0)
      return Eigen::Vector3d((m.jointRegressor * m.rest.V).row(d.joint).transpose());
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    double sum = 0;
    for (const auto& [v, w] : d.vertices) p += w * m.rest.V.row(v).transpose(), sum += w;
    EXPECT_NEAR(sum, 1.0, 1e-9);
    return p;
  };
  for (int c = 0; c < kNumCanonical; ++c) {
    const CanonicalDef& d = m.canonical[c];
    EXPECT_TRUE(d.joint >= 0 || !d.vertices.empty()) << c;
  }
  EXPECT_NEAR(point(Canonical::HeadTop).y(), 1.75, 0.003);
  EXPECT_GT(point(Canonical::LeftHandTip).x(), 0.6);
  EXPECT_LT(point(Canonical::RightHandTip).x(), -0.6);
  EXPECT_GT(point(Canonical::LeftToeTip).z(), point(Canonical::LeftHeel).z() + 0.2);
  EXPECT_LT(point(Canonical::LeftHeel).y(), 0.04);
  EXPECT_GT(point(Canonical::Nose).z(), point(Canonical::Head).z() + 0.08);
  EXPECT_NEAR(point(Canonical::LeftHandTip).x(), -point(Canonical::RightHandTip).x(), 0.003);
}

}  // namespace
}  // namespace s2p
