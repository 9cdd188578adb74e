#include "pattern/remesh.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <iostream>
#include <numbers>

#include "core/error.h"
#include "core/mesh_topology.h"
#include "core/shapes.h"
#include "panel_shapes.h"
#include "pattern/bezier_outline.h"
#include "pattern/flatten.h"
#include "core/uv_locator.h"

namespace s2p {
namespace {

constexpr double kPi = std::numbers::pi;

// n + 1 samples of the straight edge a → b.
Eigen::MatrixX2d line(const Eigen::Vector2d& a, const Eigen::Vector2d& b, int n) {
  Eigen::MatrixX2d p(n + 1, 2);
  for (int i = 0; i <= n; ++i) p.row(i) = (a + (b - a) * (static_cast<double>(i) / n)).transpose();
  return p;
}

// Every output vertex of edge k's list is the sample (bit for bit), and the mesh is a disk
// whose boundary is exactly the boundary vertices.
void expectBoundaryKept(const RemeshedPanel& r, const std::vector<Eigen::MatrixX2d>& edges) {
  ASSERT_EQ(r.edgeVertices.size(), edges.size());
  int samples = 0;
  for (size_t k = 0; k < edges.size(); ++k) {
    ASSERT_EQ(static_cast<int>(r.edgeVertices[k].size()), edges[k].rows()) << "edge " << k;
    for (int j = 0; j < edges[k].rows(); ++j)
      EXPECT_EQ(Eigen::Vector2d(r.V.row(r.edgeVertices[k][j])), Eigen::Vector2d(edges[k].row(j)));
    EXPECT_EQ(r.edgeVertices[k].back(), r.edgeVertices[(k + 1) % edges.size()].front());
    samples += static_cast<int>(edges[k].rows()) - 1;
  }
  EXPECT_EQ(r.numBoundaryVertices, samples);
  EXPECT_EQ(r.boundarySteinerPoints, 0);
  const MeshTopology topology(r.F, static_cast<int>(r.V.rows()));
  ASSERT_EQ(topology.boundaryLoops().size(), 1u);
  EXPECT_EQ(static_cast<int>(topology.boundaryLoops()[0].size()), samples);
  EXPECT_EQ(topology.eulerCharacteristic(), 1);
  for (int v : topology.boundaryLoops()[0]) EXPECT_LT(v, r.numBoundaryVertices);
}

TEST(Remesh, SquareKeepsEverySampleAndReachesTheAngleBound) {
  // 0.3 × 0.2 m, samples every 7 mm (boundarySampleCount), target 1 cm.
  const Eigen::Vector2d a(0, 0), b(0.3, 0), c(0.3, 0.2), d(0, 0.2);
  const std::vector<Eigen::MatrixX2d> edges = {line(a, b, 43), line(b, c, 29), line(c, d, 43),
                                               line(d, a, 29)};
  const RemeshedPanel r = remeshPanel(edges, "square");
  std::cout << "square: " << r.V.rows() << " vertices, " << r.F.rows() << " faces, min angle "
            << r.minAngleDeg << "°, longest edge " << r.longestEdge << " m\n";
  expectBoundaryKept(r, edges);
  EXPECT_GE(r.minAngleDeg, 20.0);
  EXPECT_EQ(r.badFaces, 0);
  EXPECT_NEAR(r.area, 0.06, 1e-14);
  EXPECT_LE(r.longestEdge, 0.01 * (1 + 1e-9));
  EXPECT_GT(r.V.rows(), r.numBoundaryVertices);  // interior vertices were added
}

TEST(Remesh, FlattenedCapOutlineEndToEnd) {
  // Flatten a spherical cap, cut its boundary at four corners, fit Béziers, resample each edge
  // at the target length, remesh, and map every new vertex back onto the flat (and 3D) panel.
  const TriMesh cap = test::makeSphericalCap(24, 0.25, 0.6);
  const PanelFlattening flat = flattenPanel(cap, Eigen::Vector3d::UnitZ(), "cap");
  const int nb = static_cast<int>(flat.boundary.size());
  Eigen::MatrixX2d outline(nb, 2);
  for (int i = 0; i < nb; ++i) outline.row(i) = flat.uv.row(flat.boundary[i]);
  const std::vector<int> corners = {0, nb / 4, nb / 2, 3 * nb / 4};
  const std::vector<BezierChain> chains = fitOutline(outline, corners);
  const double target = 0.01;
  std::vector<Eigen::MatrixX2d> edges;
  for (const BezierChain& chain : chains)
    edges.push_back(resampleChain(chain, boundarySampleCount(chain.length(), target)));
  const RemeshedPanel r = remeshPanel(edges, "cap", {.targetEdgeLength = target});
  std::cout << "cap: " << chains.size() << " edges, " << r.V.rows() << " vertices, " << r.F.rows()
            << " faces, min angle " << r.minAngleDeg << "°, bad faces " << r.badFaces << "\n";
  expectBoundaryKept(r, edges);
  EXPECT_GE(r.minAngleDeg, 20.0);
  EXPECT_LE(r.longestEdge, target * (1 + 1e-9));
  // The area equals the outline polygon's (shoelace).
  double polygonArea = 0.0;
  for (const Eigen::MatrixX2d& e : edges)
    for (int i = 0; i + 1 < e.rows(); ++i)
      polygonArea += 0.5 * (e(i, 0) * e(i + 1, 1) - e(i, 1) * e(i + 1, 0));
  EXPECT_NEAR(r.area, polygonArea, 1e-12 * polygonArea);

  // Map back: inside points reproduce their uv exactly; boundary samples lie within the
  // Bézier tolerance of the flat boundary and map to its closest point.
  const UvLocator locator(flat.uv, cap.F);
  Eigen::VectorXd distance;
  const std::vector<SurfacePoint> where = locator.locate(r.V, &distance);
  const Eigen::MatrixXd back = interpolateAt(where, cap.F, flat.uv);
  double worstInside = 0.0, worstOutside = 0.0;
  for (int v = 0; v < r.V.rows(); ++v) {
    const double err = (back.row(v) - r.V.row(v)).norm();
    if (distance(v) == 0.0)
      worstInside = std::max(worstInside, err);
    else {
      worstOutside = std::max(worstOutside, distance(v));
      EXPECT_NEAR(err, distance(v), 1e-12);
    }
  }
  std::cout << "cap map-back: inside error " << worstInside << " m, boundary samples up to "
            << worstOutside * 1e3 << " mm outside the flat boundary\n";
  EXPECT_LT(worstInside, 1e-9);
  EXPECT_LE(worstOutside, 1e-3);
  // 3D positions travel too: every remeshed vertex on the sphere of radius 0.25.
  const Eigen::MatrixXd p3 = interpolateAt(where, cap.F, cap.V);
  for (int v = 0; v < p3.rows(); ++v) EXPECT_NEAR(p3.row(v).norm(), 0.25, 2e-3);
}

TEST(Remesh, BoundarySpacingDecidesTheSizeBound) {
  // Boundary samples at the target spacing: only triangles on the boundary exceed the size
  // bound, by < 20 %; at boundarySampleCount's spacing (≤ 0.7 × target) none does.
  const Eigen::Vector2d a(0, 0), b(0.3, 0), c(0.3, 0.2), d(0, 0.2);
  const RemeshedPanel coarse =
      remeshPanel({line(a, b, 30), line(b, c, 20), line(c, d, 30), line(d, a, 20)}, "square");
  int longInside = 0;
  for (int f = 0; f < coarse.F.rows(); ++f) {
    bool touches = false;
    double l = 0.0;
    for (int k = 0; k < 3; ++k) {
      touches = touches || coarse.F(f, k) < coarse.numBoundaryVertices;
      l = std::max(l,
                   (coarse.V.row(coarse.F(f, k)) - coarse.V.row(coarse.F(f, (k + 1) % 3))).norm());
    }
    if (l > 0.01 && !touches) ++longInside;
  }
  std::cout << "square, boundary at the target spacing: longest edge " << coarse.longestEdge
            << " m\n";
  EXPECT_EQ(longInside, 0);
  EXPECT_LT(coarse.longestEdge, 0.012);
  EXPECT_EQ(boundarySampleCount(0.3, 0.01), 44);
  EXPECT_EQ(boundarySampleCount(0.0, 0.01), 2);
  const int nx = boundarySampleCount(0.3, 0.01) - 1, ny = boundarySampleCount(0.2, 0.01) - 1;
  const RemeshedPanel fine =
      remeshPanel({line(a, b, nx), line(b, c, ny), line(c, d, nx), line(d, a, ny)}, "square");
  EXPECT_LE(fine.longestEdge, 0.01);
  EXPECT_GE(fine.minAngleDeg, 20.0);
}

TEST(Remesh, StitchedEdgesKeepTheirSampleCounts) {
  // Two panels sharing a seam of 0.4 m: the caller samples it with the same count on both.
  const int seam = 41;
  const RemeshedPanel left =
      remeshPanel({line({0, 0}, {0, 0.4}, seam - 1), line({0, 0.4}, {-0.2, 0.4}, 20),
                   line({-0.2, 0.4}, {0, 0}, 45)},
                  "left");
  const RemeshedPanel right =
      remeshPanel({line({0.5, 0}, {0.5, 0.4}, seam - 1), line({0.5, 0.4}, {0.7, 0.2}, 28),
                   line({0.7, 0.2}, {0.5, 0}, 28)},
                  "right");
  EXPECT_EQ(left.edgeVertices[0].size(), static_cast<size_t>(seam));
  EXPECT_EQ(right.edgeVertices[0].size(), static_cast<size_t>(seam));
  EXPECT_EQ(left.boundarySteinerPoints + right.boundarySteinerPoints, 0);
  EXPECT_GE(std::min(left.minAngleDeg, right.minAngleDeg), 20.0);
}

TEST(Remesh, AShortJogBesideLongSamplesReachesTheAngleBoundWithoutTouchingTheBoundary) {
  // Part of a flattened back panel's outline (a suite scan, mm): 7 mm samples up a side, then
  // two corners 2.4 mm apart turning 72° and 96°. The face between the 2.4 mm segment and the
  // next 7 mm one has a 19.5° angle, and the mesher's refinement point for it (its
  // circumcentre) encroaches upon the boundary, so the mesher alone stops there.
  const std::vector<Eigen::Vector2d> side = {
      {1317.4, -447.2}, {1318.5, -440.3}, {1319.6, -433.4}, {1320.7, -426.5}, {1321.8, -419.6},
      {1322.9, -412.8}, {1324.5, -406.4}, {1326.9, -406.2}, {1325.8, -399.3}, {1324.7, -392.5},
      {1325.1, -385.5}, {1326.3, -378.6}, {1327.7, -371.8}, {1329.1, -364.9}, {1330.4, -358.1},
      {1331.5, -351.2}, {1332.1, -344.2}};
  Eigen::MatrixX2d jog(static_cast<int>(side.size()), 2);
  for (size_t i = 0; i < side.size(); ++i) jog.row(static_cast<int>(i)) = 1e-3 * side[i];
  const Eigen::Vector2d top = jog.row(jog.rows() - 1), bottom = jog.row(0);
  const Eigen::Vector2d topLeft(top.x() - 0.1, top.y()), bottomLeft(top.x() - 0.1, bottom.y());
  const std::vector<Eigen::MatrixX2d> edges = {jog, line(top, topLeft, 15),
                                               line(topLeft, bottomLeft, 15),
                                               line(bottomLeft, bottom, 13)};
  const RemeshedPanel r = remeshPanel(edges, "jog");
  std::cout << "2.4 mm jog beside 7 mm samples: min angle " << r.minAngleDeg << "°, "
            << r.badFaces << " faces below the bound, " << r.V.rows() << " vertices\n";
  expectBoundaryKept(r, edges);
  EXPECT_EQ(r.badFaces, 0);
  EXPECT_GE(r.minAngleDeg, 20.7);
  EXPECT_LE(r.longestEdge, 0.01 * (1 + 1e-9));
}

TEST(Remesh, BoundarySteinerPointsAreReportedInOrder) {
  // A coarse outline (5 cm samples) with a 1 cm target: the ordinary mesher splits the
  // boundary; the inserted vertices appear in each edge's list, in order along it.
  const Eigen::Vector2d a(0, 0), b(0.3, 0), c(0.3, 0.2), d(0, 0.2);
  const std::vector<Eigen::MatrixX2d> edges = {line(a, b, 6), line(b, c, 4), line(c, d, 6),
                                               line(d, a, 4)};
  const RemeshedPanel r =
      remeshPanel(edges, "coarse", {.targetEdgeLength = 0.01, .allowBoundarySteiner = true});
  std::cout << "coarse square with boundary refinement: " << r.boundarySteinerPoints
            << " boundary Steiner points, min angle " << r.minAngleDeg << "°\n";
  EXPECT_GT(r.boundarySteinerPoints, 0);
  EXPECT_GE(r.minAngleDeg, 20.0);
  EXPECT_LE(r.longestEdge, 0.01 * (1 + 1e-9));
  for (size_t k = 0; k < edges.size(); ++k) {
    const std::vector<int>& ids = r.edgeVertices[k];
    const Eigen::Vector2d from = edges[k].row(0), to = edges[k].row(edges[k].rows() - 1);
    double last = -1.0;
    for (int id : ids) {
      const Eigen::Vector2d p = r.V.row(id).transpose();
      const double t = (p - from).dot(to - from) / (to - from).squaredNorm();
      EXPECT_GT(t, last);
      last = t;
      // On the segment.
      EXPECT_LT(std::abs((p - from).x() * (to - from).y() - (p - from).y() * (to - from).x()),
                1e-15);
    }
    EXPECT_EQ(Eigen::Vector2d(r.V.row(ids.front())), from);
    EXPECT_EQ(Eigen::Vector2d(r.V.row(ids.back())), to);
  }
  const MeshTopology topology(r.F, static_cast<int>(r.V.rows()));
  EXPECT_EQ(static_cast<int>(topology.boundaryLoops()[0].size()), r.numBoundaryVertices);
}

TEST(Remesh, BadOutlinesThrowNamingThePanel) {
  auto expectInputError = [](const std::vector<Eigen::MatrixX2d>& edges, const RemeshOptions& o) {
    try {
      remeshPanel(edges, "sleeve_left", o);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("sleeve_left"), std::string::npos) << e.what();
    }
  };
  const Eigen::Vector2d a(0, 0), b(0.3, 0), c(0.3, 0.2), d(0, 0.2);
  expectInputError({line(a, b, 3), line(c, d, 3)}, {});                                // gap
  expectInputError({line(a, c, 3), line(c, b, 3), line(b, d, 3), line(d, a, 3)}, {});  // bow tie
  expectInputError({line(a, b, 3), line(b, a, 3)}, {});                                // no area
  const std::vector<Eigen::MatrixX2d> square = {line(a, b, 3), line(b, c, 3), line(c, d, 3),
                                                line(d, a, 3)};
  expectInputError(square, {.minAngleDeg = 30.0});
  expectInputError(square, {.targetEdgeLength = 0.0});
  expectInputError({}, {});
}

TEST(UvLocator, LocatesInsideAndClosestOutside) {
  TriMesh grid = makeGrid(13, 7, 0.39, 0.21);
  const Eigen::MatrixX2d uv = grid.V.leftCols(2);
  const UvLocator locator(uv, grid.F);
  // Pseudo-random interior points reproduce exactly.
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector2d p(0.39 * std::fmod(0.6180339887 * i, 1.0),
                            0.21 * std::fmod(0.7548776662 * i + 0.1, 1.0));
    double d = -1.0;
    const SurfacePoint s = locator.locate(p, &d);
    ASSERT_GE(s.face, 0);
    EXPECT_EQ(d, 0.0);
    EXPECT_GE(s.bary.minCoeff(), -1e-12);
    EXPECT_NEAR(s.bary.sum(), 1.0, 1e-14);
    const Eigen::Vector2d q = s.bary(0) * uv.row(grid.F(s.face, 0)).transpose() +
                              s.bary(1) * uv.row(grid.F(s.face, 1)).transpose() +
                              s.bary(2) * uv.row(grid.F(s.face, 2)).transpose();
    EXPECT_LT((q - p).norm(), 1e-15);
  }
  // Vertices themselves.
  for (int v = 0; v < uv.rows(); ++v) {
    const SurfacePoint s = locator.locate(Eigen::Vector2d(uv.row(v).transpose()));
    EXPECT_LT((interpolateAt({s}, grid.F, uv).row(0) - uv.row(v)).norm(), 1e-15);
  }
  // Outside: the closest point of the rectangle.
  double d = 0.0;
  const SurfacePoint s = locator.locate(Eigen::Vector2d(0.5, 0.1), &d);
  EXPECT_NEAR(d, 0.11, 1e-12);
  const Eigen::RowVectorXd q = interpolateAt({s}, grid.F, uv).row(0);
  EXPECT_NEAR(q(0), 0.39, 1e-12);
  EXPECT_NEAR(q(1), 0.1, 1e-12);
  const SurfacePoint far = locator.locate(Eigen::Vector2d(-3.0, -4.0), &d);
  EXPECT_NEAR(d, 5.0, 1e-12);
  EXPECT_GE(far.face, 0);
  EXPECT_THROW(UvLocator(uv, Eigen::MatrixX3i(0, 3)), InputError);
}

// Timing of the outline + remesh of a 50k-face panel (printed, not asserted).
TEST(Remesh, FiftyThousandFacePanelOutlineAndRemeshTiming_Slow) {
  const TriMesh cap = test::makeSphericalCap(91, 0.3, 0.8);
  const auto t0 = std::chrono::steady_clock::now();
  const PanelFlattening flat = flattenPanel(cap, Eigen::Vector3d::UnitZ(), "cap50k");
  const auto t1 = std::chrono::steady_clock::now();
  const int nb = static_cast<int>(flat.boundary.size());
  Eigen::MatrixX2d outline(nb, 2);
  for (int i = 0; i < nb; ++i) outline.row(i) = flat.uv.row(flat.boundary[i]);
  const std::vector<BezierChain> chains = fitOutline(outline, {0, nb / 4, nb / 2, 3 * nb / 4});
  std::vector<Eigen::MatrixX2d> edges;
  for (const BezierChain& chain : chains)
    edges.push_back(resampleChain(chain, boundarySampleCount(chain.length(), 0.01)));
  const auto t2 = std::chrono::steady_clock::now();
  const RemeshedPanel r = remeshPanel(edges, "cap50k");
  const auto t3 = std::chrono::steady_clock::now();
  const UvLocator locator(flat.uv, cap.F);
  const std::vector<SurfacePoint> where = locator.locate(r.V);
  const auto t4 = std::chrono::steady_clock::now();
  auto s = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  std::cout << cap.numFaces() << "-face panel: flatten " << s(t0, t1) << " s, outline " << s(t1, t2)
            << " s, remesh " << s(t2, t3) << " s (" << r.F.rows() << " faces, min angle "
            << r.minAngleDeg << "°), map back " << s(t3, t4) << " s\n";
  EXPECT_EQ(where.size(), static_cast<size_t>(r.V.rows()));
}

}  // namespace
}  // namespace s2p
