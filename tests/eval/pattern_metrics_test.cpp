// The pattern score's figures of where seams land, on hand-made panels with known answers: the
// side seam's angle against the body's and the limb's coronal plane, and mirrored panels' areas
// with and without the scanner's noise.
#include "eval/pattern_metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "core/shapes.h"

namespace s2p {
namespace {

using Vec3 = Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;

// A standing skeleton (+y up, facing +z, left = +x) whose left leg is swung forward by
// `strideDeg` about the hip; every other canonical point sits at the pelvis.
Eigen::MatrixX3d skeleton(double strideDeg) {
  Eigen::MatrixX3d c(kNumCanonical, 3);
  const auto set = [&](Canonical k, const Vec3& p) { c.row(static_cast<int>(k)) = p.transpose(); };
  for (int k = 0; k < kNumCanonical; ++k) c.row(k) << 0, 0.9, 0;
  set(Canonical::Neck, {0, 1.5, 0});
  set(Canonical::Head, {0, 1.65, 0});
  for (const double s : {1.0, -1.0}) {
    const bool left = s > 0;
    set(left ? Canonical::LeftShoulder : Canonical::RightShoulder, {s * 0.18, 1.45, 0});
    set(left ? Canonical::LeftElbow : Canonical::RightElbow, {s * 0.4, 1.25, 0});
    set(left ? Canonical::LeftWrist : Canonical::RightWrist, {s * 0.6, 1.05, 0});
    const Vec3 hip(s * 0.09, 0.9, 0);
    const double a = left ? strideDeg * kPi / 180 : 0.0;
    const Vec3 down(0, -std::cos(a), std::sin(a));
    set(left ? Canonical::LeftHip : Canonical::RightHip, hip);
    set(left ? Canonical::LeftKnee : Canonical::RightKnee, hip + 0.42 * down);
    set(left ? Canonical::LeftAnkle : Canonical::RightAnkle, hip + 0.84 * down);
  }
  return c;
}

// A panel whose one seam edge `edge` runs along the given points (a polyline; the mesh is a
// strip of triangles beside it), partnered with panel `partner`.
Panel seamPanel(const std::string& name, const std::string& edge, const std::vector<Vec3>& line,
                int partner) {
  Panel p;
  p.name = name;
  p.garment = "lower";
  p.garmentIndex = 0;
  const int n = static_cast<int>(line.size());
  p.mesh.V.resize(2 * n, 3);
  for (int i = 0; i < n; ++i) {
    p.mesh.V.row(i) = line[i].transpose();
    p.mesh.V.row(n + i) = (line[i] + Vec3(0, 0, 0.05)).transpose();
  }
  p.mesh.F.resize(2 * (n - 1), 3);
  for (int i = 0; i + 1 < n; ++i) {
    p.mesh.F.row(2 * i) << i, i + 1, n + i + 1;
    p.mesh.F.row(2 * i + 1) << i, n + i + 1, n + i;
  }
  PanelEdge e;
  e.name = edge;
  e.opening = false;
  e.partnerPanel = partner;
  for (int i = 0; i < n; ++i) e.vertices.push_back(i);
  p.edges.push_back(e);
  return p;
}

TEST(PatternMetrics, ASideSeamOnAStridingLegIsMeasuredAgainstTheLegsPlane) {
  const double stride = 25;
  const Eigen::MatrixX3d canonical = skeleton(stride);
  // Along the outside of each leg, 10 cm out from its axis, from just below the hip to the ankle.
  std::vector<Vec3> leftSeam, rightSeam;
  const Vec3 leftHip = canonical.row(static_cast<int>(Canonical::LeftHip)).transpose();
  const Vec3 leftAnkle = canonical.row(static_cast<int>(Canonical::LeftAnkle)).transpose();
  const Vec3 rightHip = canonical.row(static_cast<int>(Canonical::RightHip)).transpose();
  const Vec3 rightAnkle = canonical.row(static_cast<int>(Canonical::RightAnkle)).transpose();
  for (int i = 1; i <= 9; ++i) {
    const double t = i / 10.0;
    leftSeam.push_back(leftHip + t * (leftAnkle - leftHip) + Vec3(0.1, 0, 0));
    rightSeam.push_back(rightHip + t * (rightAnkle - rightHip) + Vec3(-0.1, 0, 0));
  }
  PanelsResult r;
  r.panels.push_back(seamPanel("left_front", "left_side", leftSeam, 1));
  r.panels.push_back(seamPanel("left_back", "left_side", leftSeam, 0));
  r.panels.push_back(seamPanel("right_front", "right_side", rightSeam, 3));
  r.panels.push_back(seamPanel("right_back", "right_side", rightSeam, 2));
  GarmentPanels g;
  g.name = "lower";
  g.kind = GarmentKind::Lower;
  g.panels = {0, 1, 2, 3};
  r.garments.push_back(g);

  const PatternScore s = scorePattern(r, Truth{}, makeIcosphere(2, 0.1), canonical);
  ASSERT_EQ(s.sideSeamAngle.size(), 2u);  // one per partner pair
  ASSERT_EQ(s.sideSeamLimbAngle.size(), 2u);
  for (size_t i = 0; i < s.sideSeamAngle.size(); ++i) {
    const bool left = s.sideSeamAngle[i].first.find("left_side") != std::string::npos;
    // Against the body's plane the striding leg's seam is off by the stride; against the leg's
    // own plane it lies in it. The standing leg's seam lies in both.
    EXPECT_NEAR(s.sideSeamAngle[i].second, left ? stride : 0.0, 1e-6) << s.sideSeamAngle[i].first;
    EXPECT_NEAR(s.sideSeamLimbAngle[i].second, 0.0, 1e-6) << s.sideSeamLimbAngle[i].first;
  }
}

// A flat 20 × 30 cm panel on a 5 mm grid with its four sides as edges.
Panel sheet(const std::string& name, double noise, unsigned seed) {
  Panel p;
  p.name = name;
  p.garment = "upper";
  p.garmentIndex = 0;
  const int nx = 40, ny = 60;
  p.mesh = makeGrid(nx, ny, 0.2, 0.3);
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, noise);
  const auto at = [&](int i, int j) { return j * (nx + 1) + i; };
  for (int j = 1; j < ny; ++j)
    for (int i = 1; i < nx; ++i) p.mesh.V(at(i, j), 2) = normal(rng);
  std::vector<int> loop;
  for (int i = 0; i < nx; ++i) loop.push_back(at(i, 0));
  for (int j = 0; j < ny; ++j) loop.push_back(at(nx, j));
  for (int i = nx; i > 0; --i) loop.push_back(at(i, ny));
  for (int j = ny; j > 0; --j) loop.push_back(at(0, j));
  p.loop = loop;
  for (int side = 0; side < 4; ++side) {
    const int n = side % 2 == 0 ? nx : ny;
    const int start = side == 0 ? 0 : side == 1 ? nx : side == 2 ? nx + ny : 2 * nx + ny;
    PanelEdge e;
    e.name = "hem";
    for (int k = 0; k <= n; ++k) e.vertices.push_back(loop[(start + k) % loop.size()]);
    p.edges.push_back(e);
  }
  p.area = surfaceArea(p.mesh);
  return p;
}

TEST(PatternMetrics, MirroredPanelsOfEqualClothAreEqualOnceTheScannersNoiseIsTakenOut) {
  PanelsResult r;
  r.panels.push_back(sheet("left_sleeve", 0.0015, 1));  // a scanner's 1.5 mm of noise
  r.panels.push_back(sheet("right_sleeve", 0.0, 2));
  GarmentPanels g;
  g.name = "upper";
  g.panels = {0, 1};
  r.garments.push_back(g);
  const PatternScore s = scorePattern(r, Truth{}, makeIcosphere(2, 0.1), skeleton(0));
  ASSERT_EQ(s.mirrorAreaDiff.size(), 1u);
  ASSERT_EQ(s.mirrorClothAreaDiff.size(), 1u);
  EXPECT_GT(s.mirrorAreaDiff[0].second, 0.04);  // the noise's wrinkles
  EXPECT_LT(s.mirrorClothAreaDiff[0].second, 0.01);
}

}  // namespace
}  // namespace s2p
