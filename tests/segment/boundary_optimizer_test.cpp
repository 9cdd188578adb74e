#include "segment/boundary_optimizer.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/mesh_query.h"
#include "core/mesh_topology.h"
#include "core/shapes.h"
#include "segment/colour_model.h"
#include "segment_test_meshes.h"

namespace s2p {
namespace {

SurfacePoint closest(const MeshQuery& q, const Eigen::Vector3d& p) {
  const ClosestHit h = q.closestPoint(p);
  return {h.face, h.bary};
}

// A ring of `n` surface points around the vertical axis through (cx, ·, 0) at height y.
std::vector<SurfacePoint> ring(const MeshQuery& q, double cx, double y, double r, int n) {
  std::vector<SurfacePoint> s;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * (i + 0.25) / n;
    s.push_back(closest(q, {cx + r * std::cos(a), y, r * std::sin(a)}));
  }
  return s;
}

// Sign points at height y around the axis (cx, ·, 0).
void addSigns(std::vector<ValueConstraint>& out, const MeshQuery& q, double cx, double y, double r,
              double value) {
  for (int i = 0; i < 4; ++i) {
    const double a = M_PI / 2 * i;
    out.push_back({closest(q, {cx + r * std::cos(a), y, r * std::sin(a)}), value});
  }
}

// φ_d of a mesh coloured blue (positive) where positiveColour(y) and red elsewhere, the
// colour model fitted on vertices far from the colour edge; its smoothing grows with `scale`.
template <typename Pred>
Eigen::VectorXd twoColourDisplacement(const TriMesh& m, Pred positiveColour, double edge,
                                      double scale = 1) {
  Eigen::MatrixX3d rgb(m.numVertices(), 3);
  ColourRegion pos{{}, true}, neg{{}, false};
  for (int v = 0; v < m.numVertices(); ++v) {
    const bool p = positiveColour(m.V(v, 1));
    rgb.row(v) = p ? Eigen::RowVector3d(0.85, 0.65, 0.55) : Eigen::RowVector3d(0.15, 0.2, 0.7);
    if (std::abs(m.V(v, 1) - edge) > 0.15 && v % 5 == 0)
      (p ? pos : neg).points.push_back(SurfacePoint::atVertex(m.F, v));
  }
  ColourModelOptions options;
  options.displacementSmoothing *= scale;
  return colourDisplacement(m, rgb, {pos, neg}, options).phiD;
}

struct CylinderCase {
  TriMesh mesh;
  std::vector<std::vector<SurfacePoint>> splines;
  std::vector<ValueConstraint> signs;
  Eigen::VectorXd phiD;
};

// Two-colour cylinder, radius 0.1·s, height s: skin-like colour (positive) above y = 0.3·s,
// blue below; the start ring at 0.45·s.
CylinderCase twoColourCylinder(int rings, int segments, double s) {
  CylinderCase c;
  c.mesh = makeCylinder(rings, segments, 0.1 * s, s);
  const MeshQuery q(c.mesh);
  c.splines = {ring(q, 0, 0.45 * s, 0.1 * s, 12)};
  addSigns(c.signs, q, 0, 0.95 * s, 0.1 * s, 1.0);
  addSigns(c.signs, q, 0, 0.05 * s, 0.1 * s, -1.0);
  c.phiD = twoColourDisplacement(
      c.mesh, [s](double y) { return y >= 0.3 * s; }, 0.3 * s, s);
  return c;
}

double meanY(const Isoline& iso) {
  const Eigen::MatrixX3d P = iso.positions();
  return P.col(1).mean();
}

TEST(BoundaryOptimizer, TwoColourCylinderConvergesToTheColourEdge) {
  const CylinderCase c = twoColourCylinder(137, 48, 1.0);
  for (const bool faithful : {true, false}) {
    SCOPED_TRACE(faithful ? "faithful" : "fast");
    BoundaryOptions o;
    o.faithful = faithful;
    const BoundaryResult r = optimizeBoundary(c.mesh, c.splines, c.signs, c.phiD, o);
    EXPECT_TRUE(r.converged);
    EXPECT_FALSE(r.vanished);
    ASSERT_EQ(r.initial.curves.size(), 1u);
    EXPECT_NEAR(meanY(r.initial), 0.45, 0.005);
    ASSERT_EQ(r.boundary.curves.size(), 1u);
    EXPECT_TRUE(r.boundary.curves[0].closed);
    for (const auto& p : r.boundary.curves[0].points) EXPECT_NEAR(p.position.y(), 0.3, 0.005);
    // It took about (0.45 − 0.3)/α iterations to travel there.
    EXPECT_GE(r.iterations, 12);
    EXPECT_LE(r.iterations, 40);
  }
}

// A scan in pieces: the two-colour cylinder, a second one beside it (its own start ring and sign
// points) and a blue ball with no feature at all under the first (legs seen apart under a skirt
// have none for B(U|S)). Every system (M + βL, the biharmonic, the signed distances) solves on
// the three pieces; both cylinders' boundaries reach the colour edge and the ball stays whole on
// the negative side it sits next to.
TEST(BoundaryOptimizer, ThreeDisconnectedPiecesEachReachItsColourEdge) {
  const CylinderCase a = twoColourCylinder(137, 48, 1.0);
  TriMesh ball = makeIcosphere(3, 0.08);
  ball.V.rowwise() += Eigen::RowVector3d(0, -0.12, 0);
  TriMesh m = a.mesh;
  for (const TriMesh* piece : {&a.mesh, static_cast<const TriMesh*>(&ball)}) {
    const int nv = m.numVertices(), nf = m.numFaces();
    m.V.conservativeResize(nv + piece->numVertices(), 3);
    m.V.bottomRows(piece->numVertices()) = piece->V;
    if (piece == &a.mesh) m.V.bottomRows(piece->numVertices()).col(0).array() += 0.5;
    m.F.conservativeResize(nf + piece->numFaces(), 3);
    m.F.bottomRows(piece->numFaces()) = piece->F.array() + nv;
  }
  const MeshQuery q(m);
  std::vector<std::vector<SurfacePoint>> splines = {ring(q, 0, 0.45, 0.1, 12),
                                                    ring(q, 0.5, 0.45, 0.1, 12)};
  std::vector<ValueConstraint> signs;
  for (const double cx : {0.0, 0.5}) {
    addSigns(signs, q, cx, 0.95, 0.1, 1.0);
    addSigns(signs, q, cx, 0.05, 0.1, -1.0);
  }
  const Eigen::VectorXd phiD = twoColourDisplacement(
      m, [](double y) { return y >= 0.3; }, 0.3);
  const BoundaryResult r = optimizeBoundary(m, splines, signs, phiD);
  EXPECT_TRUE(r.converged);
  EXPECT_FALSE(r.vanished);
  ASSERT_TRUE(r.phi.allFinite());
  ASSERT_EQ(r.boundary.curves.size(), 2u);
  for (const auto& c : r.boundary.curves)
    for (const auto& p : c.points) EXPECT_NEAR(p.position.y(), 0.3, 0.005);
  const int nc = a.mesh.numVertices();
  for (int v = 2 * nc; v < m.numVertices(); ++v) ASSERT_LT(r.phi[v], 0) << v;
}

TEST(BoundaryOptimizer, SameBoundaryAtTwoResolutionsAndScaledTwice_Slow) {
  const CylinderCase fine = twoColourCylinder(137, 48, 1.0);
  const CylinderCase coarse = twoColourCylinder(91, 32, 1.0);
  const CylinderCase big = twoColourCylinder(137, 48, 2.0);
  for (const bool faithful : {true, false}) {
    SCOPED_TRACE(faithful ? "faithful" : "fast");
    BoundaryOptions o;
    o.faithful = faithful;
    const BoundaryOptions o2{.alpha = 2 * o.alpha,
                             .beta = 4 * o.beta,
                             .tolerance = 4 * o.tolerance,
                             .faithful = faithful,
                             .heat = {},
                             .biharmonic = {}};
    const BoundaryResult rf = optimizeBoundary(fine.mesh, fine.splines, fine.signs, fine.phiD, o);
    const BoundaryResult rc =
        optimizeBoundary(coarse.mesh, coarse.splines, coarse.signs, coarse.phiD, o);
    const BoundaryResult rb = optimizeBoundary(big.mesh, big.splines, big.signs, big.phiD, o2);
    ASSERT_TRUE(rf.converged && rc.converged && rb.converged);
    EXPECT_NEAR(meanY(rf.boundary), meanY(rc.boundary), 0.003);
    EXPECT_NEAR(meanY(rb.boundary), 2 * meanY(rf.boundary), 1e-6);
    EXPECT_EQ(rb.iterations, rf.iterations);
  }
}

TEST(BoundaryOptimizer, TwoLegLoopsMergeIntoOneLoopAboveTheFork_Slow) {
  const TriMesh m = testing::makeTrousers(0.013);
  ASSERT_TRUE(MeshTopology(m.F, m.numVertices()).isClosed());
  const MeshQuery q(m);
  const std::vector<std::vector<SurfacePoint>> splines = {ring(q, 0.075, 0.38, 0.055, 10),
                                                          ring(q, -0.075, 0.38, 0.055, 10)};
  std::vector<ValueConstraint> signs;
  addSigns(signs, q, 0.075, 0.1, 0.055, 1.0);  // "feet": skin side
  addSigns(signs, q, -0.075, 0.1, 0.055, 1.0);
  addSigns(signs, q, 0, 0.95, 0.13, -1.0);  // trunk: garment side
  const Eigen::VectorXd phiD = twoColourDisplacement(
      m, [](double y) { return y < 0.7; }, 0.7);
  for (const bool faithful : {true, false}) {  // the fast path changes topology too
    BoundaryOptions o;
    o.faithful = faithful;
    const BoundaryResult r = optimizeBoundary(m, splines, signs, phiD, o);
    EXPECT_EQ(r.initial.curves.size(), 2u);
    EXPECT_TRUE(r.converged);
    ASSERT_EQ(r.boundary.curves.size(), 1u) << faithful;
    EXPECT_TRUE(r.boundary.curves[0].closed);
    for (const auto& p : r.boundary.curves[0].points) EXPECT_NEAR(p.position.y(), 0.7, 0.01);
  }
}

TEST(BoundaryOptimizer, FastPathReachesTheFaithfulBoundaryOnTheCylinder_Slow) {
  const CylinderCase c = twoColourCylinder(137, 48, 1.0);
  BoundaryOptions faithfulOptions, fastOptions;
  faithfulOptions.faithful = true;
  fastOptions.faithful = false;
  const BoundaryResult faithful =
      optimizeBoundary(c.mesh, c.splines, c.signs, c.phiD, faithfulOptions);
  const BoundaryResult fast = optimizeBoundary(c.mesh, c.splines, c.signs, c.phiD, fastOptions);
  ASSERT_TRUE(fast.converged);
  ASSERT_EQ(fast.boundary.curves.size(), 1u);
  EXPECT_NEAR(meanY(fast.boundary), meanY(faithful.boundary), 0.001);
  EXPECT_LT(fast.timings.biharmonic, faithful.timings.biharmonic);  // only φ₀ uses it
}

// φ_b far from its zero constraints is extrapolation: a band where it turns positive again
// (here below y = 0.125, under a curve at y = 0.5) takes the sign that the votes (the
// regularised field φ̄ in the iteration) give its area, unless a sign point in it says otherwise.
TEST(BoundaryOptimizer, RegionWithoutSignPointsTakesTheSignOfTheVotes) {
  const TriMesh m = makeCylinder(40, 24, 0.1, 1.0);
  const MeshTopology topology(m.F, m.numVertices());
  const Eigen::VectorXd area = vertexAreas(m);
  const int nV = m.numVertices();
  Eigen::VectorXd phiB(nV), votes(nV);
  int top = 0, bottom = 0;
  for (int v = 0; v < nV; ++v) {
    const double y = m.V(v, 1);
    votes[v] = y - 0.5;
    phiB[v] = y >= 0.25 ? y - 0.5 : -0.25 + 2 * (0.25 - y);
    if (y > m.V(top, 1)) top = v;
    if (y < m.V(bottom, 1)) bottom = v;
  }
  const Isoline iso = extractIsoline(m, topology, phiB);
  ASSERT_EQ(iso.curves.size(), 2u);
  std::vector<ValueConstraint> constraints{{SurfacePoint::atVertex(m.F, top), 1.0}};

  auto signAt = [&](const Eigen::VectorXd& sign, double lo, double hi, int want) {
    for (int v = 0; v < nV; ++v)
      if (m.V(v, 1) > lo && m.V(v, 1) < hi) {
        EXPECT_GT(want * sign[v], 0) << "y = " << m.V(v, 1);
      }
  };
  const Eigen::VectorXd byVotes = regionSigns(m, topology, area, iso, phiB, constraints, votes);
  signAt(byVotes, -1, 0.45, -1);
  signAt(byVotes, 0.55, 2, +1);
  // Where the sign agrees, φ_b's value is kept (the curve at y = 0.5 stays its zero set).
  for (int v = 0; v < nV; ++v) {
    if (m.V(v, 1) > 0.55) {
      EXPECT_DOUBLE_EQ(byVotes[v], phiB[v]);
    }
  }
  // φ_b voting for itself keeps the stray band positive.
  signAt(regionSigns(m, topology, area, iso, phiB, constraints, phiB), -1, 0.1, +1);
  // A sign point in the band outvotes the area.
  constraints.push_back({SurfacePoint::atVertex(m.F, bottom), 1.0});
  signAt(regionSigns(m, topology, area, iso, phiB, constraints, votes), -1, 0.1, +1);
}

TEST(BoundaryOptimizer, BadInputThrowsInputError) {
  const CylinderCase c = twoColourCylinder(20, 12, 1.0);
  BoundaryOptimizer o(c.mesh);
  EXPECT_THROW(o.run({}, c.signs, c.phiD), InputError);  // no spline
  EXPECT_THROW(o.run(c.splines, c.signs, Eigen::VectorXd::Zero(3)), InputError);
  // One-sided sign points are allowed (the paper's B(L|S) and B(U|L) have only positive ones);
  // none at all, or only zero values, are not.
  EXPECT_THROW(o.run(c.splines, {}, c.phiD), InputError);
  std::vector<ValueConstraint> zeros(c.signs.begin(), c.signs.begin() + 2);
  for (auto& z : zeros) z.value = 0;
  EXPECT_THROW(o.run(c.splines, zeros, c.phiD), InputError);
  BoundaryOptions bad;
  bad.alpha = -1;
  EXPECT_THROW(BoundaryOptimizer(c.mesh, bad), InputError);
}

}  // namespace
}  // namespace s2p

namespace s2p {
namespace {

// A limb far from its constraints: φ swings + − + along a tube (a biharmonic extrapolated down
// a trouser leg). The sign point lies at the top; the two bands below hold none. Flipping both at
// once would leave a loop between them; taking the side of the region each lies in leaves φ > 0
// all along, and no isoline.
TEST(BoundaryOptimizer, NestedIslandsEndOnTheSideOfTheRegionAroundThem) {
  const TriMesh tube = makeCylinder(40, 24, 0.05, 0.8);
  Eigen::VectorXd phi(tube.numVertices());
  for (int v = 0; v < tube.numVertices(); ++v) {
    const double y = tube.V(v, 1);
    phi[v] = y > 0.5 ? y - 0.45 : (y > 0.25 ? -(0.55 - y) : 0.3 - y);  // + above 0.5, − band, +
  }
  int top = 0;
  for (int v = 1; v < tube.numVertices(); ++v)
    if (tube.V(v, 1) > tube.V(top, 1)) top = v;
  const std::vector<ValueConstraint> signs = {{SurfacePoint::atVertex(tube.F, top), 1.0}};
  const int flipped = removeIslands(tube, phi, std::numeric_limits<double>::infinity(), signs);
  EXPECT_EQ(flipped, 1);  // the − band only; the + band below it was on the right side already
  EXPECT_GT(phi.minCoeff(), 0.0);
  const MeshTopology topo(tube.F, tube.numVertices());
  EXPECT_TRUE(extractIsoline(tube, topo, phi).curves.empty());
}

}  // namespace
}  // namespace s2p

namespace s2p {
namespace {

// Five spheres in a row, one piece each (a scan in pieces: a skirt whose legs are a piece of their
// own). φ is positive on all but the first, which the curve crosses.
struct FivePieces {
  TriMesh mesh;
  std::vector<int> firstVertex;  // of each piece, and the end
};

FivePieces fivePieces() {
  const TriMesh s = makeIcosphere(2, 0.1);
  FivePieces p;
  p.mesh.V.resize(5 * s.numVertices(), 3);
  p.mesh.F.resize(5 * s.numFaces(), 3);
  for (int i = 0; i < 5; ++i) {
    p.firstVertex.push_back(i * s.numVertices());
    p.mesh.V.middleRows(i * s.numVertices(), s.numVertices()) =
        s.V.rowwise() + Eigen::RowVector3d(0.5 * i, 0, 0);
    p.mesh.F.middleRows(i * s.numFaces(), s.numFaces()) =
        s.F.array() + i * s.numVertices();
  }
  p.firstVertex.push_back(p.mesh.numVertices());
  return p;
}

// A piece that no curve crosses and no feature holds takes the side its region points vote for;
// too few votes, split votes, or a feature on the piece leave φ's side.
TEST(BoundaryOptimizer, UncutPieceWithoutFeaturesTakesTheSideOfItsRegionPoints) {
  const FivePieces p = fivePieces();
  const TriMesh& m = p.mesh;
  const MeshQuery q(m);
  Eigen::VectorXd phi(m.numVertices());
  for (int v = 0; v < m.numVertices(); ++v)
    phi[v] = v < p.firstVertex[1] ? m.V(v, 1) : 0.01 + 0.001 * m.V(v, 1);  // piece 0: crossed
  // Piece k's centre.
  const auto at = [&](int k, double dy, double dz) {
    return closest(q, Eigen::Vector3d(0.5 * k, dy, dz + 0.2));
  };
  std::vector<SideVote> votes;
  for (int i = 0; i < 6; ++i) votes.push_back({at(0, 0.05, 0.01 * i), -1});  // crossed: ignored
  for (int i = 0; i < 5; ++i) votes.push_back({at(1, 0, 0.01 * i), -1});     // 5 of 6 say −
  votes.push_back({at(1, 0.05, 0), +1});
  for (int i = 0; i < 3; ++i) votes.push_back({at(2, 0, 0.01 * i), -1});  // only 3: too few
  for (int i = 0; i < 3; ++i) votes.push_back({at(3, 0, 0.01 * i), -1});  // 3 − against 3 +
  for (int i = 0; i < 3; ++i) votes.push_back({at(3, 0.05, 0.01 * i), +1});
  for (int i = 0; i < 5; ++i) votes.push_back({at(4, 0, 0.01 * i), -1});  // a feature lies on it
  const std::vector<SurfacePoint> anchors = {at(0, 0, 0), at(4, 0.05, 0)};
  const Eigen::VectorXd before = phi;
  const std::vector<PieceSide> sides = sidePiecesByVotes(m, phi, anchors, votes);
  ASSERT_EQ(sides.size(), 3u);  // pieces 1, 2, 3: 0 is crossed, 4 anchored
  int flipped = 0;
  for (const PieceSide& s : sides) flipped += s.flipped;
  EXPECT_EQ(flipped, 1);
  for (int k = 0; k < 5; ++k)
    for (int v = p.firstVertex[k]; v < p.firstVertex[k + 1]; ++v) {
      if (k == 1) {
        ASSERT_LT(phi[v], 0) << "piece 1, vertex " << v;
        EXPECT_DOUBLE_EQ(phi[v], -before[v]);
      } else {
        ASSERT_EQ(phi[v], before[v]) << "piece " << k << ", vertex " << v;
      }
    }
  // The curve of piece 0 is still the only one.
  const MeshTopology topo(m.F, m.numVertices());
  EXPECT_EQ(extractIsoline(m, topo, phi).curves.size(), 1u);
  // Votes already agreeing with φ change nothing.
  for (SideVote& v : votes) v.side = -v.side;
  phi = before;
  for (const PieceSide& s : sidePiecesByVotes(m, phi, anchors, votes)) EXPECT_FALSE(s.flipped);
  EXPECT_EQ(phi, before);
  EXPECT_THROW(sidePiecesByVotes(m, phi = Eigen::VectorXd::Zero(3), anchors, votes), InputError);
}

}  // namespace
}  // namespace s2p
