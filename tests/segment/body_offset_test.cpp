#include "segment/body_offset.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <functional>

#include "core/error.h"
#include "core/mesh_query.h"
#include "segment/boundary_optimizer.h"

namespace s2p {
namespace {

// An open tube about the y axis from y = −h to h, radius r(y), rings `dy` apart, plus the riser
// of any jump of r: `riser` rings at y = 0 between r(0⁻) and r(0⁺) (a flat annulus, like the
// riser under a hem).
TriMesh tube(const std::function<double(double)>& r, double h, double dy, int segments,
             int riser = 0) {
  std::vector<std::pair<double, double>> rings;  // (y, radius)
  const int n = static_cast<int>(std::round(h / dy));
  for (int i = -n; i <= n; ++i) {
    const double y = i * dy;
    if (i == 0 && riser > 0) {
      const double lo = r(-1e-9), hi = r(1e-9);
      for (int k = 0; k <= riser; ++k) rings.push_back({0.0, lo + (hi - lo) * k / riser});
    } else {
      rings.push_back({y, r(y)});
    }
  }
  TriMesh m;
  m.V.resize(static_cast<int>(rings.size()) * segments, 3);
  for (size_t j = 0; j < rings.size(); ++j)
    for (int s = 0; s < segments; ++s) {
      const double a = 2 * M_PI * (s + 0.5 * (j % 2)) / segments;
      m.V.row(static_cast<int>(j) * segments + s) << rings[j].second * std::cos(a), rings[j].first,
          -rings[j].second * std::sin(a);
    }
  m.F.resize(2 * (static_cast<int>(rings.size()) - 1) * segments, 3);
  int f = 0;
  for (int j = 0; j + 1 < static_cast<int>(rings.size()); ++j)
    for (int s = 0; s < segments; ++s) {
      const int a = j * segments + s, b = j * segments + (s + 1) % segments;
      const int c = (j + 1) * segments + s, d = (j + 1) * segments + (s + 1) % segments;
      m.F.row(f++) << a, b, d;
      m.F.row(f++) << a, d, c;
    }
  // Outward normals: make the first face point away from the axis.
  const Eigen::Vector3d p0 = m.V.row(m.F(0, 0)), p1 = m.V.row(m.F(0, 1)), p2 = m.V.row(m.F(0, 2));
  const Eigen::Vector3d c = (p0 + p1 + p2) / 3;
  if ((p1 - p0).cross(p2 - p0).dot(Eigen::Vector3d(c.x(), 0, c.z())) < 0) m.F.col(1).swap(m.F.col(2));
  return m;
}

SurfacePoint closest(const MeshQuery& q, const Eigen::Vector3d& p) {
  const ClosestHit h = q.closestPoint(p);
  return {h.face, h.bary};
}

std::vector<SurfacePoint> ring(const MeshQuery& q, double y, double r, int n) {
  std::vector<SurfacePoint> s;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * (i + 0.25) / n;
    s.push_back(closest(q, {r * std::cos(a), y, r * std::sin(a)}));
  }
  return s;
}

void addSigns(std::vector<ValueConstraint>& out, const MeshQuery& q, double y, double r,
              double value) {
  for (int i = 0; i < 4; ++i) {
    const double a = M_PI / 2 * i;
    out.push_back({closest(q, {r * std::cos(a), y, r * std::sin(a)}), value});
  }
}

const TriMesh& bodyTube() {
  static const TriMesh b = tube([](double) { return 0.10; }, 0.6, 0.01, 64);
  return b;
}

// A top with 2 cm of ease worn over trousers with 1 cm: a 1 cm hem step at y = 0.
TriMesh hemTube() {
  return tube([](double y) { return y > 0 ? 0.12 : 0.11; }, 0.5, 0.008, 64, 3);
}

TEST(BodyOffset, IsTheDistanceOffTheBodyWithItsSign) {
  const MeshQuery q(bodyTube());
  const TriMesh scan = hemTube();
  const Eigen::VectorXd o = bodyOffset(scan, q, bodyTube());
  for (int v = 0; v < scan.numVertices(); ++v) {
    const double r = std::hypot(scan.V(v, 0), scan.V(v, 2));
    EXPECT_NEAR(o[v], r - 0.10, 0.001) << v;
  }
  TriMesh inside = tube([](double) { return 0.095; }, 0.4, 0.01, 48);
  EXPECT_LT(bodyOffset(inside, q, bodyTube()).maxCoeff(), 0);
}

// The step field is positive on the high side of the hem, negative on the low side, and fades
// away from it.
TEST(BodyOffset, StepFieldMarksBothSidesOfTheHem) {
  const MeshQuery q(bodyTube());
  const TriMesh scan = hemTube();
  const Eigen::VectorXd h = stepField(scan, bodyOffset(scan, q, bodyTube()));
  double nearAbove = 0, nearBelow = 0, far = 0;
  for (int v = 0; v < scan.numVertices(); ++v) {
    const double y = scan.V(v, 1);
    if (y > 0.01 && y < 0.02) nearAbove = std::max(nearAbove, h[v]);
    if (y < -0.01 && y > -0.02) nearBelow = std::min(nearBelow, h[v]);
    if (std::abs(y) > 0.25 && std::abs(y) < 0.4) far = std::max(far, std::abs(h[v]));
  }
  EXPECT_GT(nearAbove, 0.002);  // well past the dead zone (1 mm): a full vote
  EXPECT_LT(nearBelow, -0.002);
  EXPECT_LT(far, 0.0002);
}

// The known answer: two garments of the same colour with a 1 cm hem step between them
// are separated within 3 mm of the step, from a start 2.5 cm above it (a 1 cm step reaches
// beyond the dead zone for ≈ L·ln(5 mm / 1 mm) ≈ 4 cm). Colour alone (φ_d = 0) leaves the
// boundary where it started.
TEST(BodyOffset, EqualColoursAreSeparatedAtTheHemStep) {
  const MeshQuery body(bodyTube());
  const TriMesh scan = hemTube();
  const MeshQuery q(scan);
  const Eigen::VectorXd offset = bodyOffset(scan, body, bodyTube());
  const Eigen::VectorXd h = stepField(scan, offset);
  const std::vector<std::vector<SurfacePoint>> splines = {ring(q, 0.025, 0.12, 12)};
  std::vector<ValueConstraint> signs;
  addSigns(signs, q, 0.45, 0.12, 1.0);
  addSigns(signs, q, -0.45, 0.11, -1.0);
  const Eigen::VectorXd colour = Eigen::VectorXd::Zero(scan.numVertices());

  BoundaryOptimizer optimizer(scan);
  const Eigen::VectorXd phi0 = optimizer.initialImplicit(splines, signs);
  // The top is the outer garment and on the positive side: the offset grows toward it.
  EXPECT_GT(stepOrientation(scan, offset, h, phi0, 0.25), 0);
  const Eigen::VectorXd phiD = combinedDisplacement(colour, stepDisplacement(h, 1.0), 1.0);
  const BoundaryResult r = optimizer.iterate(phi0, signs, phiD);
  EXPECT_TRUE(r.converged);
  ASSERT_EQ(r.boundary.curves.size(), 1u);
  for (const IsolinePoint& p : r.boundary.curves[0].points) EXPECT_NEAR(p.position.y(), 0, 0.003);
  EXPECT_GT(hemContrast(scan, r.phi, h, 1.0), 0.002);  // ≈ 0.3 of the 1 cm step, twice the test

  const BoundaryResult blind = optimizer.iterate(phi0, signs, colour);
  ASSERT_FALSE(blind.boundary.curves.empty());
  EXPECT_GT(blind.boundary.positions().col(1).minCoeff(), 0.015);
  EXPECT_LT(hemContrast(scan, blind.phi, h, 1.0), GeometricCueOptions{}.hemContrast);
}

// A tucked-in top: the trousers are the outer garment, the offset grows toward the negative
// side, and the orientation says so.
TEST(BodyOffset, TuckedInTopFacesTheOtherWay) {
  const MeshQuery body(bodyTube());
  const TriMesh scan = tube([](double y) { return y > 0 ? 0.11 : 0.12; }, 0.5, 0.008, 64, 3);
  const MeshQuery q(scan);
  const Eigen::VectorXd offset = bodyOffset(scan, body, bodyTube());
  const Eigen::VectorXd h = stepField(scan, offset);
  std::vector<ValueConstraint> signs;
  addSigns(signs, q, 0.45, 0.11, 1.0);
  addSigns(signs, q, -0.45, 0.12, -1.0);
  BoundaryOptimizer optimizer(scan);
  const Eigen::VectorXd phi0 = optimizer.initialImplicit({ring(q, 0.05, 0.11, 12)}, signs);
  EXPECT_LT(stepOrientation(scan, offset, h, phi0, 0.25), 0);
}

// Colour that tells the sides apart keeps the paper's displacement; colour that cannot is
// overridden at the steps.
TEST(BodyOffset, GeometryWeighsInWhereColourCannotTell) {
  EXPECT_EQ(geometryWeight(30), 0);
  EXPECT_EQ(geometryWeight(20), 0);
  EXPECT_EQ(geometryWeight(5), 1);
  EXPECT_EQ(geometryWeight(2), 1);
  EXPECT_NEAR(geometryWeight(12.5), 0.5, 1e-12);
  const Eigen::VectorXd colour = Eigen::VectorXd::Constant(3, -0.6);
  const Eigen::VectorXd step = (Eigen::VectorXd(3) << 1, 0, -1).finished();
  EXPECT_EQ(combinedDisplacement(colour, step, 0), colour);
  const Eigen::VectorXd blind = combinedDisplacement(colour, step, 1);
  EXPECT_DOUBLE_EQ(blind[0], 1);
  EXPECT_DOUBLE_EQ(blind[1], -0.6);  // no step: the colour, however weak
  EXPECT_DOUBLE_EQ(blind[2], -1);
  EXPECT_THROW(geometryWeight(10, {.blindDeltaE = 20, .clearDeltaE = 10}), InputError);
}

// The known answer: a skin-coloured cylinder over a skin-coloured body with 1 cm of
// ease is clothed by its offset; the bare body is not.
TEST(BodyOffset, SkinColouredSleeveWithEaseIsClothed) {
  const MeshQuery body(bodyTube());
  const TriMesh sleeve = tube([](double) { return 0.11; }, 0.4, 0.01, 48);
  const Eigen::VectorXd o = bodyOffset(sleeve, body, bodyTube());
  EXPECT_TRUE(offsetSaysClothed(std::vector<double>(o.data(), o.data() + o.size())));
  const TriMesh skin = tube([](double) { return 0.1015; }, 0.4, 0.01, 48);  // 1.5 mm: fit error
  const Eigen::VectorXd b = bodyOffset(skin, body, bodyTube());
  EXPECT_FALSE(offsetSaysClothed(std::vector<double>(b.data(), b.data() + b.size())));
  EXPECT_FALSE(offsetSaysClothed({}));
}

// The offset as a displacement between skin (+1, on the body) and a garment (−1, off it by its
// ease), between this scan's two levels.
TEST(BodyOffset, OffsetDisplacementRampsFromSkinToGarment) {
  const Eigen::VectorXd o = (Eigen::VectorXd(5) << -0.001, 0.0, 0.0015, 0.003, 0.01).finished();
  const Eigen::VectorXd d = offsetDisplacement(o, 0.0, 0.003);
  EXPECT_DOUBLE_EQ(d[0], 1);
  EXPECT_DOUBLE_EQ(d[1], 1);
  EXPECT_NEAR(d[2], 0, 1e-12);
  EXPECT_DOUBLE_EQ(d[3], -1);
  EXPECT_DOUBLE_EQ(d[4], -1);
  EXPECT_THROW(offsetDisplacement(o, 0.003, 0.003), InputError);
}

}  // namespace
}  // namespace s2p
