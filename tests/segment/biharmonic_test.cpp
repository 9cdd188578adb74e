#include "segment/biharmonic.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/mesh_query.h"
#include "core/shapes.h"

namespace s2p {
namespace {

// Constraint at the surface point of `mesh` closest to p.
ValueConstraint at(const MeshQuery& q, const Eigen::Vector3d& p, double value) {
  const ClosestHit h = q.closestPoint(p);
  return {SurfacePoint{h.face, h.bary}, value};
}

TEST(Biharmonic, RingOfZerosOnCylinderGivesThatRingAsZeroIsoline) {
  const double r = 0.15, y0 = 0.437;
  const TriMesh cyl = makeCylinder(50, 40, r, 1.0);
  const MeshQuery q(cyl);
  std::vector<ValueConstraint> c;
  for (int i = 0; i < 17; ++i) {  // zero ring at y0, points inside faces (not at vertices)
    const double a = 2 * M_PI * (i + 0.3) / 17;
    c.push_back(at(q, {r * std::cos(a), y0, r * std::sin(a)}, 0.0));
  }
  c.push_back(at(q, {r, 0.95, 0}, 1.0));
  c.push_back(at(q, {-r, 0.05, 0}, -1.0));
  Biharmonic b(cyl);
  const Eigen::VectorXd phi = b.solve(c);
  const Isoline iso = extractIsoline(cyl, phi);
  ASSERT_EQ(iso.curves.size(), 1u);
  EXPECT_TRUE(iso.curves[0].closed);
  for (const auto& p : iso.curves[0].points) EXPECT_NEAR(p.position.y(), y0, 0.01 * r);
  // Sign: above positive, below negative.
  for (int v = 0; v < cyl.numVertices(); ++v)
    if (std::abs(cyl.V(v, 1) - y0) > 0.05) {
      EXPECT_EQ(phi[v] > 0, cyl.V(v, 1) > y0);
    }
}

TEST(Biharmonic, ConstraintInsideAFaceIsMetTo1e6AndRefactorReusesAnalysis) {
  const TriMesh s = makeIcosphere(3);
  Biharmonic b(s);
  const std::vector<ValueConstraint> c1 = {{SurfacePoint{7, {0.2, 0.3, 0.5}}, 0.0},
                                           {SurfacePoint{100, {0.6, 0.1, 0.3}}, 1.0},
                                           {SurfacePoint{250, {1.0 / 3, 1.0 / 3, 1.0 / 3}}, -1.0}};
  const Eigen::VectorXd phi = b.solve(c1);
  for (const auto& c : c1) EXPECT_NEAR(c.point.interpolate(s.F, phi), c.value, 1e-6);
  EXPECT_FALSE(b.lastStats().refactored);
  const std::vector<ValueConstraint> c2 = {{SurfacePoint{31, {0.5, 0.5, 0.0}}, 0.25},
                                           {SurfacePoint{300, {0.1, 0.1, 0.8}}, -0.5}};
  const Eigen::VectorXd phi2 = b.solve(c2);
  EXPECT_TRUE(b.lastStats().refactored);
  for (const auto& c : c2) EXPECT_NEAR(c.point.interpolate(s.F, phi2), c.value, 1e-6);
}

TEST(Biharmonic, EqualConstraintValuesGiveThatConstant) {
  // Constants span the null space of L M⁻¹ L: equal values everywhere are the minimiser.
  const TriMesh g = makeGrid(20, 20);
  const std::vector<ValueConstraint> c = {{SurfacePoint{10, {0.2, 0.3, 0.5}}, 0.7},
                                          {SurfacePoint{400, {0.3, 0.3, 0.4}}, 0.7},
                                          {SurfacePoint{700, {0.6, 0.2, 0.2}}, 0.7}};
  const Eigen::VectorXd u = biharmonicFunction(g, c);
  EXPECT_LT((u.array() - 0.7).abs().maxCoeff(), 1e-6);
}

// A piece of the mesh with no constraint (an island a previous cut left, legs scanned apart
// under a skirt) does not break the factorisation: it takes the value of the nearest solved
// vertex, and the constrained piece its exact constant.
TEST(Biharmonic, UnconstrainedPieceTakesTheNearestSolvedValue) {
  const TriMesh a = makeGrid(12, 12);
  TriMesh two = a;
  two.V.conservativeResize(2 * a.numVertices(), 3);
  two.V.bottomRows(a.numVertices()) = a.V.rowwise() + Eigen::RowVector3d(5, 0, 0);
  two.F.conservativeResize(2 * a.numFaces(), 3);
  two.F.bottomRows(a.numFaces()) = a.F.array() + a.numVertices();
  const std::vector<ValueConstraint> c = {{SurfacePoint{3, {0.2, 0.3, 0.5}}, 0.7},
                                          {SurfacePoint{100, {0.3, 0.3, 0.4}}, 0.7}};
  Biharmonic b(two);
  const Eigen::VectorXd u = b.solve(c);
  EXPECT_LT((u.head(a.numVertices()).array() - 0.7).abs().maxCoeff(), 1e-6);
  EXPECT_LT((u.tail(a.numVertices()).array() - 0.7).abs().maxCoeff(), 1e-6);
  EXPECT_EQ(b.lastStats().unconstrainedPieces, 1);
}

// Three disconnected pieces (a scan in pieces): two cylinders, each with its own zero ring and
// sign points, and a sphere with none beside the first cylinder's top. Each cylinder's zero set
// is its own ring, the sphere takes the positive side it sits next to, and a second solve with
// the same pieces constrained only refactors.
TEST(Biharmonic, ThreeDisconnectedPiecesSolveEachOnItsOwn) {
  const double r = 0.15;
  const TriMesh cyl = makeCylinder(40, 32, r, 1.0);
  TriMesh ball = makeIcosphere(2, 0.1);
  ball.V.rowwise() += Eigen::RowVector3d(0, 1.2, 0);  // above the first cylinder's top
  TriMesh second = cyl;
  second.V.rowwise() += Eigen::RowVector3d(1.0, 0, 0);
  TriMesh three = cyl;
  for (const TriMesh* m : {&second, &ball}) {
    const int nv = three.numVertices(), nf = three.numFaces();
    three.V.conservativeResize(nv + m->numVertices(), 3);
    three.V.bottomRows(m->numVertices()) = m->V;
    three.F.conservativeResize(nf + m->numFaces(), 3);
    three.F.bottomRows(m->numFaces()) = m->F.array() + nv;
  }
  const MeshQuery q(three);
  const double y0 = 0.437, y1 = 0.61;
  std::vector<ValueConstraint> c;
  for (int i = 0; i < 17; ++i) {
    const double t = 2 * M_PI * (i + 0.3) / 17;
    c.push_back(at(q, {r * std::cos(t), y0, r * std::sin(t)}, 0.0));
    c.push_back(at(q, {1.0 + r * std::cos(t), y1, r * std::sin(t)}, 0.0));
  }
  c.push_back(at(q, {r, 0.95, 0}, 1.0));
  c.push_back(at(q, {-r, 0.05, 0}, -1.0));
  c.push_back(at(q, {1.0 + r, 0.95, 0}, 1.0));
  c.push_back(at(q, {1.0 - r, 0.05, 0}, -1.0));
  Biharmonic b(three);
  const Eigen::VectorXd phi = b.solve(c);
  ASSERT_TRUE(phi.allFinite());
  EXPECT_EQ(b.lastStats().unconstrainedPieces, 1);
  const Isoline iso = extractIsoline(three, phi);
  ASSERT_EQ(iso.curves.size(), 2u);
  for (const IsolineCurve& curve : iso.curves) {
    EXPECT_TRUE(curve.closed);
    const bool first = curve.points.front().position.x() < 0.5;
    for (const auto& p : curve.points) EXPECT_NEAR(p.position.y(), first ? y0 : y1, 0.01 * r);
  }
  const int nc = cyl.numVertices();
  for (int v = 2 * nc; v < three.numVertices(); ++v) EXPECT_GT(phi[v], 0.5) << v;
  for (int v = 0; v < 2 * nc; ++v)
    if (std::abs(three.V(v, 1) - (v < nc ? y0 : y1)) > 0.05) {
      EXPECT_EQ(phi[v] > 0, three.V(v, 1) > (v < nc ? y0 : y1)) << v;
    }
  c.back().value = -0.5;
  b.solve(c);
  EXPECT_TRUE(b.lastStats().refactored);
}

// An exact cut that passes a hair's breadth from a row of vertices leaves a strip of slivers
// along the new border (vertex areas 1e-10 m² beside 1e-4 m²). The solution elsewhere must not
// notice: the operator's scale (regularisation, penalty) is the diagonal's median and each
// vertex weighs at least 1 % of the median vertex area.
// With its mean the strip screened the solution, which died out ~10 cm from each constraint
// (jacket_layered's trousers: a crotch seam function ~0 along both legs, 13 panels for 4).
TEST(Biharmonic, ASliverStripAlongTheBorderLeavesTheSolutionAsItWas) {
  const int rings = 40, segments = 40;
  const double r = 0.1, step = 1.0 / rings;
  // The reference: rings 1..40 of a unit cylinder. The same with a ring 1e-7 m below its
  // bottom ring: a strip of slivers along the border.
  TriMesh clean = makeCylinder(rings - 1, segments, r, 1.0 - step);
  clean.V.col(1).array() += step;
  TriMesh slivers = makeCylinder(rings, segments, r, 1.0);
  for (int i = 0; i < segments; ++i) slivers.V(i, 1) = step - 1e-7;
  const MeshQuery q(clean);
  std::vector<ValueConstraint> onClean, onSlivers;
  for (int i = 0; i < 6; ++i)
    for (const auto& [y, value] : {std::pair{0.9, 1.0}, std::pair{0.6, -1.0}}) {
      const double a = 2 * M_PI * (i + 0.25) / 6;
      ValueConstraint k = at(q, {r * std::cos(a), y, r * std::sin(a)}, value);
      onClean.push_back(k);
      k.point.face += 2 * segments;  // the same face one ring up
      onSlivers.push_back(k);
    }
  const Eigen::VectorXd a = biharmonicFunction(clean, onClean),
                        b = biharmonicFunction(slivers, onSlivers);
  // Between the constraint rings the two agree; below them each extrapolates by its own border
  // (the strip's ring shifts the bottom's natural condition: −2.6 against −3.1 at y = 0.025).
  double largest = 0;
  for (int v = 0; v < clean.numVertices(); ++v)
    if (clean.V(v, 1) >= 0.6) largest = std::max(largest, std::abs(a[v] - b[v + segments]));
  EXPECT_LT(largest, 0.03);
  // The solution carries on past the −1 ring (a smooth extrapolation, not a decay to 0). With
  // the mean as the scale the strip made the system indefinite (the factorisation failed).
  for (int v = 0; v < segments; ++v) EXPECT_LT(b[segments + v], -2.0) << v;
}

// A 1 mm grid (phone_scan) leaves faces with an angle of 1e-14 rad: cotangents of 1e14, a
// bilaplacian diagonal of 1e36 beside a median of 1e4, and no Cholesky factor. Ten vertices moved
// to within 1e-13 m of a neighbour make such faces; with the cotangents clamped the solution away
// from them is the clean cylinder's.
TEST(Biharmonic, FacesWithAnAngleOfNearlyZeroStillSolve) {
  const int rings = 40, segments = 40;
  const double r = 0.1;
  const TriMesh clean = makeCylinder(rings, segments, r, 1.0);
  TriMesh pinched = clean;
  std::vector<int> moved;
  for (int k = 0; k < 10; ++k) {
    const int ring = 5 + 3 * k, i = (7 * k) % segments;
    const int v = ring * segments + i, u = (ring + 1) * segments + i;
    pinched.V.row(v) = clean.V.row(u) + Eigen::RowVector3d(1e-13, 0, 0);
    moved.push_back(v);
  }
  const MeshQuery q(clean);
  std::vector<ValueConstraint> constraints;
  for (int i = 0; i < 6; ++i)
    for (const auto& [y, value] : {std::pair{0.9, 1.0}, std::pair{0.1, -1.0}}) {
      const double a = 2 * M_PI * (i + 0.25) / 6;
      constraints.push_back(at(q, {r * std::cos(a), y, r * std::sin(a)}, value));
    }
  const Eigen::VectorXd a = biharmonicFunction(clean, constraints);
  Eigen::VectorXd b;
  ASSERT_NO_THROW(b = biharmonicFunction(pinched, constraints));
  ASSERT_TRUE(b.allFinite());
  // Away from the pinched vertices (more than two rings off) the two agree.
  double largest = 0;
  for (int v = 0; v < clean.numVertices(); ++v) {
    bool near = false;
    for (int m : moved) near |= (clean.V.row(v) - clean.V.row(m)).norm() < 2.5 / rings;
    if (!near) largest = std::max(largest, std::abs(a[v] - b[v]));
  }
  EXPECT_LT(largest, 0.05);
}

TEST(Biharmonic, BadConstraintsThrowInputError) {
  const TriMesh s = makeIcosphere(1);
  Biharmonic b(s);
  EXPECT_THROW(b.solve({}), InputError);
  EXPECT_THROW(b.solve({{SurfacePoint{s.numFaces(), {1, 0, 0}}, 0}}), InputError);
  EXPECT_THROW(b.solve({{SurfacePoint{0, {0.5, 0.2, 0.1}}, 0}}), InputError);
}

}  // namespace
}  // namespace s2p
