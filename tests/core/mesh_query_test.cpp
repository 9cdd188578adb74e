#include "core/mesh_query.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <thread>

#include "core/error.h"
#include "core/shapes.h"
#include "core/winding_number.h"

namespace s2p {
namespace {

Eigen::Vector3d randomDirection(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Vector3d d(n(rng), n(rng), n(rng));
  return d.normalized();
}

Eigen::Vector3d corner(const TriMesh& m, int f, int k) {
  return m.V.row(m.F(f, k)).transpose();
}

// Reference distance from p to triangle (a, b, c), computed independently of the library:
// the plane projection when it falls inside, else the nearest of the three edges.
double referenceDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                         const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  auto segment = [&](const Eigen::Vector3d& s, const Eigen::Vector3d& e) {
    const double t = std::clamp((p - s).dot(e - s) / (e - s).squaredNorm(), 0.0, 1.0);
    return (s + t * (e - s) - p).norm();
  };
  const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
  const Eigen::Vector3d q = p - n.dot(p - a) * n;
  const bool inside = (b - a).cross(q - a).dot(n) >= 0 && (c - b).cross(q - b).dot(n) >= 0 &&
                      (a - c).cross(q - c).dot(n) >= 0;
  if (inside) return (q - p).norm();
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

double bruteForceDistance(const TriMesh& m, const Eigen::Vector3d& p) {
  double best = std::numeric_limits<double>::infinity();
  for (int f = 0; f < m.numFaces(); ++f)
    best = std::min(best, referenceDistance(p, corner(m, f, 0), corner(m, f, 1), corner(m, f, 2)));
  return best;
}

// The hit's barycentrics are valid and reproduce its point.
void expectConsistent(const TriMesh& m, int face, const Eigen::Vector3d& bary,
                      const Eigen::Vector3d& point) {
  ASSERT_GE(face, 0);
  ASSERT_LT(face, m.numFaces());
  EXPECT_NEAR(bary.sum(), 1.0, 1e-12);
  EXPECT_GE(bary.minCoeff(), 0.0);
  const Eigen::Vector3d rebuilt =
      bary(0) * corner(m, face, 0) + bary(1) * corner(m, face, 1) + bary(2) * corner(m, face, 2);
  EXPECT_LT((rebuilt - point).norm(), 1e-12);
}

// Tolerance for "on the sphere" at icosphere level 4: bounds the chord gap checked below.
constexpr double kSphereTol = 3e-3;

// Largest distance between a sphere of radius r and the planes of its icosphere's faces.
double chordGap(const TriMesh& sphere, double r) {
  double gap = 0;
  for (int f = 0; f < sphere.numFaces(); ++f) {
    const Eigen::Vector3d a = corner(sphere, f, 0), b = corner(sphere, f, 1),
                          c = corner(sphere, f, 2);
    gap = std::max(gap, r - std::abs((b - a).cross(c - a).normalized().dot(a)));
  }
  return gap;
}

TEST(MeshQuery, SphereToleranceBoundsTheChordGap) {
  EXPECT_LT(chordGap(makeIcosphere(4, 1.0), 1.0), kSphereTol);
  EXPECT_LT(chordGap(makeIcosphere(4, 2.0), 2.0), 2.0 * kSphereTol);
}

// === Closest point

TEST(MeshQuery, ClosestPointOnSphereInsideAndOutside) {
  const TriMesh sphere = makeIcosphere(4, 1.0);
  const double gap = chordGap(sphere, 1.0);
  const MeshQuery query(sphere);
  std::mt19937 rng(1);
  for (double r : {0.3, 2.5}) {
    for (int i = 0; i < 100; ++i) {
      const Eigen::Vector3d p = r * randomDirection(rng);
      const ClosestHit hit = query.closestPoint(p);
      // The mesh lies between radii 1 − gap and 1: inside, d ∈ [1 − r − gap, 1 − r]; outside,
      // d ∈ [r − 1, r − 1 + gap].
      if (r < 1) {
        EXPECT_LE(hit.distance, 1.0 - r + 1e-12);
        EXPECT_GE(hit.distance, 1.0 - r - gap);
      } else {
        EXPECT_GE(hit.distance, r - 1.0 - 1e-12);
        EXPECT_LE(hit.distance, r - 1.0 + gap);
      }
      EXPECT_GE(hit.point.norm(), 1.0 - gap);    // on the surface
      EXPECT_LE(hit.point.norm(), 1.0 + 1e-12);  // chords lie inside the sphere
      EXPECT_NEAR((hit.point - p).norm(), hit.distance, 1e-12);
      expectConsistent(sphere, hit.face, hit.bary, hit.point);
    }
  }
}

TEST(MeshQuery, ClosestPointIsExactAgainstBruteForce) {
  const TriMesh sphere = makeIcosphere(5, 0.8);  // 20480 faces
  const MeshQuery query(sphere);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> radius(0.0, 2.0);
  Eigen::MatrixX3d P(60, 3);
  for (int i = 0; i < P.rows(); ++i) P.row(i) = radius(rng) * randomDirection(rng).transpose();
  P.row(0).setZero();  // equidistant from everything
  const std::vector<ClosestHit> hits = query.closestPoints(P);
  ASSERT_EQ(hits.size(), 60u);
  for (int i = 0; i < P.rows(); ++i) {
    const Eigen::Vector3d p = P.row(i).transpose();
    EXPECT_NEAR(hits[i].distance, bruteForceDistance(sphere, p), 1e-12) << "point " << i;
    const ClosestHit single = query.closestPoint(p);
    EXPECT_EQ(single.face, hits[i].face);
    EXPECT_EQ(single.distance, hits[i].distance);
  }
}

TEST(MeshQuery, ClosestPointOnGridIsOrthogonalProjection) {
  const TriMesh grid = makeGrid(10, 7, 2.0, 1.0);
  const MeshQuery query(grid);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> x(-0.5, 2.5), y(-0.5, 1.5), z(-1.0, 1.0);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(x(rng), y(rng), z(rng));
    // Projection onto the plane, clamped to the rectangle.
    const Eigen::Vector3d expected(std::clamp(p.x(), 0.0, 2.0), std::clamp(p.y(), 0.0, 1.0), 0);
    const ClosestHit hit = query.closestPoint(p);
    EXPECT_LT((hit.point - expected).norm(), 1e-12) << p.transpose();
    EXPECT_NEAR(hit.distance, (p - expected).norm(), 1e-12);
    expectConsistent(grid, hit.face, hit.bary, hit.point);
  }
}

// === Ray casting

TEST(MeshQuery, RayBarycentricsMapEmbreeUvToCorners) {
  TriMesh tri;
  tri.V.resize(3, 3);
  tri.V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  tri.F.resize(1, 3);
  tri.F << 0, 1, 2;
  const MeshQuery query(tri);
  // Non-unit direction: t must still be the distance travelled.
  const auto hit = query.rayCast(Eigen::Vector3d(0.2, 0.3, 1.5), Eigen::Vector3d(0, 0, -4));
  ASSERT_TRUE(hit.has_value());
  EXPECT_EQ(hit->face, 0);
  EXPECT_NEAR(hit->t, 1.5, 1e-12);
  EXPECT_LT((hit->bary - Eigen::Vector3d(0.5, 0.2, 0.3)).norm(), 1e-12);
  EXPECT_LT((hit->point - Eigen::Vector3d(0.2, 0.3, 0.0)).norm(), 1e-12);
  // Two-sided: the same face is hit from below.
  const auto below = query.rayCast(Eigen::Vector3d(0.2, 0.3, -2), Eigen::Vector3d(0, 0, 1));
  ASSERT_TRUE(below.has_value());
  EXPECT_NEAR(below->t, 2.0, 1e-12);
}

TEST(MeshQuery, RayFromSphereCentreHitsAtRadius) {
  const double r = 2.0;
  const TriMesh sphere = makeIcosphere(4, r);
  const MeshQuery query(sphere);
  std::mt19937 rng(4);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d dir = randomDirection(rng) * (0.1 + i);  // arbitrary lengths
    const auto hit = query.rayCast(Eigen::Vector3d::Zero(), dir);
    ASSERT_TRUE(hit.has_value());
    EXPECT_LE(hit->t, r + 1e-12);
    EXPECT_GE(hit->t, r * (1.0 - kSphereTol));
    EXPECT_LT((hit->point - hit->t * dir.normalized()).norm(), 1e-9);
    expectConsistent(sphere, hit->face, hit->bary, hit->point);
  }
}

TEST(MeshQuery, RayIntervalAndMisses) {
  const double r = 1.0;
  const TriMesh sphere = makeIcosphere(4, r);
  const MeshQuery query(sphere);
  const Eigen::Vector3d origin(0, 0, 5), down(0, 0, -1);
  const auto first = query.rayCast(origin, down);
  ASSERT_TRUE(first.has_value());
  EXPECT_NEAR(first->t, 5.0 - r, kSphereTol);
  EXPECT_GT(first->point.z(), 0.9);
  // Starting past the near side finds the far side.
  const auto far = query.rayCast(origin, down, 5.0);
  ASSERT_TRUE(far.has_value());
  EXPECT_NEAR(far->t, 5.0 + r, kSphereTol);
  EXPECT_LT(far->point.z(), -0.9);
  EXPECT_FALSE(query.rayCast(origin, down, 0.0, 3.5).has_value());            // stops short
  EXPECT_FALSE(query.rayCast(origin, Eigen::Vector3d(1, 0, 0)).has_value());  // passes by
  EXPECT_FALSE(query.rayCast(origin, Eigen::Vector3d(0, 0, 1)).has_value());  // points away
}

// === Winding number

TEST(MeshQuery, WindingNumberOfClosedSphere) {
  const TriMesh sphere = makeIcosphere(3, 1.0);
  const MeshQuery query(sphere);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> inner(0.0, 0.9), outer(1.1, 4.0);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d in = inner(rng) * randomDirection(rng);
    const Eigen::Vector3d out = outer(rng) * randomDirection(rng);
    EXPECT_NEAR(windingNumberBruteForce(sphere, in), 1.0, 1e-10);
    EXPECT_NEAR(windingNumberBruteForce(sphere, out), 0.0, 1e-10);
    EXPECT_NEAR(query.windingNumber(in), 1.0, 1e-3);
    EXPECT_NEAR(query.windingNumber(out), 0.0, 1e-3);
    EXPECT_TRUE(query.isInside(in));
    EXPECT_FALSE(query.isInside(out));
  }
}

TEST(MeshQuery, FastWindingNumberAgreesWithBruteForce) {
  // A sphere with a hole and a cylinder: open surfaces, where w is not piecewise constant.
  for (const TriMesh& mesh : {cutByPlane(makeIcosphere(5, 1.0), Eigen::Vector3d(0, 1, 0), 0.7),
                              makeCylinder(40, 64, 0.5, 2.0)}) {
    const MeshQuery query(mesh);
    std::mt19937 rng(6);
    std::uniform_real_distribution<double> u(-2.0, 2.0);
    Eigen::MatrixX3d P(300, 3);
    for (int i = 0; i < P.rows(); ++i) P.row(i) << u(rng), u(rng), u(rng);
    const Eigen::VectorXd fast = query.windingNumbers(P);
    double maxErr = 0;
    for (int i = 0; i < P.rows(); ++i) {
      const Eigen::Vector3d p = P.row(i).transpose();
      maxErr = std::max(maxErr, std::abs(fast(i) - windingNumberBruteForce(mesh, p)));
      EXPECT_EQ(fast(i), query.windingNumber(p));  // parallel = serial, bit for bit
    }
    EXPECT_LT(maxErr, 1e-3);
  }
}

TEST(MeshQuery, EveryExpansionOrderClassifiesAndConverges) {
  const TriMesh open = cutByPlane(makeIcosphere(4, 1.0), Eigen::Vector3d(0, 1, 0), 0.7);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  Eigen::MatrixX3d P(200, 3);
  for (int i = 0; i < P.rows(); ++i) P.row(i) << u(rng), u(rng), u(rng);
  Eigen::VectorXd exact(P.rows());
  for (int i = 0; i < P.rows(); ++i) exact(i) = windingNumberBruteForce(open, P.row(i).transpose());
  for (int order = 1; order <= 3; ++order) {
    double previous = std::numeric_limits<double>::infinity();
    for (double beta : {2.0, 4.0, 8.0}) {
      const WindingNumberTree tree(open, beta, order);
      double maxErr = 0;
      for (int i = 0; i < P.rows(); ++i)
        maxErr = std::max(maxErr, std::abs(tree.evaluate(P.row(i).transpose()) - exact(i)));
      EXPECT_LT(maxErr, 0.1) << "order " << order << " beta " << beta;       // never misclassifies
      EXPECT_LT(maxErr, previous) << "order " << order << " beta " << beta;  // converges in β
      previous = maxErr;
    }
    EXPECT_LT(previous, order == 3 ? 1e-4 : 5e-3) << "order " << order << " at beta 8";
  }
  EXPECT_THROW(WindingNumberTree(open, 2.0, 4), InputError);
}

TEST(MeshQuery, ConcurrentFirstQueriesShareOneTree) {
  const TriMesh sphere = makeIcosphere(3, 1.0);
  const MeshQuery query(sphere);
  const Eigen::Vector3d p(0.2, 0.1, -0.3);
  std::vector<double> w(4);
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) threads.emplace_back([&, t] { w[t] = query.windingNumber(p); });
  for (std::thread& t : threads) t.join();
  for (int t = 0; t < 4; ++t) EXPECT_EQ(w[t], w[0]);
  EXPECT_NEAR(w[0], 1.0, 1e-3);
}

TEST(MeshQuery, WindingNumberSeparatesInsideFromOutsideThroughAHole) {
  // Remove the cap above y = 0.7: the centre sees the sphere minus a cap of half-angle
  // acos(0.7), w = 1 − (1 − 0.7)/2 = 0.85 (up to the jagged cut).
  const TriMesh open = cutByPlane(makeIcosphere(4, 1.0), Eigen::Vector3d(0, 1, 0), 0.7);
  const MeshQuery query(open);
  EXPECT_NEAR(query.windingNumber(Eigen::Vector3d::Zero()), 0.85, 0.02);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> inner(0.0, 0.85), outer(1.15, 3.0);
  int checked = 0;
  for (int i = 0; i < 400; ++i) {
    const Eigen::Vector3d in = inner(rng) * randomDirection(rng);
    const Eigen::Vector3d out = outer(rng) * randomDirection(rng);
    const Eigen::Vector3d holeCentre(0, 0.7, 0);  // skip points very near the opening
    if ((in - holeCentre).norm() > 0.35) {
      EXPECT_GT(query.windingNumber(in), 0.5) << in.transpose();
      ++checked;
    }
    if ((out - holeCentre).norm() > 0.8) {
      EXPECT_LT(query.windingNumber(out), 0.5) << out.transpose();
    }
  }
  EXPECT_GT(checked, 200);
}

TEST(MeshQuery, InvertedOrientationGivesNegativeWindingNumber) {
  TriMesh sphere = makeIcosphere(3, 1.0);
  sphere.F.col(1).swap(sphere.F.col(2));
  const MeshQuery query(sphere);
  EXPECT_NEAR(query.windingNumber(Eigen::Vector3d(0.1, -0.2, 0.3)), -1.0, 1e-3);
  EXPECT_NEAR(query.windingNumber(Eigen::Vector3d(3, 0, 0)), 0.0, 1e-3);
  EXPECT_FALSE(query.isInside(Eigen::Vector3d::Zero()));
}

TEST(MeshQuery, SolidAngleOfOctantTriangleIsHalfPi) {
  // The triangle (e_x, e_y, e_z) seen from the origin covers one octant: 4π/8.
  const double omega = triangleSolidAngle(Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                          Eigen::Vector3d::UnitZ());
  EXPECT_NEAR(omega, std::numbers::pi / 2, 1e-14);
  EXPECT_NEAR(triangleSolidAngle(Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitZ(),
                                 Eigen::Vector3d::UnitY()),
              -std::numbers::pi / 2, 1e-14);
}

// === Bad input

TEST(MeshQuery, RejectsBadInput) {
  EXPECT_THROW(MeshQuery{TriMesh{}}, InputError);
  TriMesh bad = makeGrid(2, 2);
  bad.F(1, 2) = 99;
  EXPECT_THROW(MeshQuery{bad}, InputError);
  TriMesh nan = makeGrid(2, 2);
  nan.V(0, 0) = std::nan("");
  EXPECT_THROW(MeshQuery{nan}, InputError);
  EXPECT_THROW(MeshQuery(makeGrid(2, 2), MeshQueryOptions{.windingBeta = 0.5}), InputError);
  EXPECT_THROW(WindingNumberTree(TriMesh{}), InputError);

  const MeshQuery query(makeGrid(2, 2));
  const Eigen::Vector3d nanPoint(std::nan(""), 0, 0);
  EXPECT_THROW(query.closestPoint(nanPoint), InputError);
  EXPECT_THROW(query.windingNumber(nanPoint), InputError);
  EXPECT_THROW(query.rayCast(nanPoint, Eigen::Vector3d::UnitZ()), InputError);
  EXPECT_THROW(query.rayCast(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()), InputError);
  EXPECT_THROW(query.rayCast(Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ(), 2.0, 1.0),
               InputError);
  Eigen::MatrixX3d P = Eigen::MatrixX3d::Zero(3, 3);
  P(2, 1) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(query.closestPoints(P), InputError);
  EXPECT_THROW(query.windingNumbers(P), InputError);
}

TEST(MeshQuery, DegenerateFacesDoNotBreakQueries) {
  TriMesh m = makeGrid(2, 2);
  // Collapse face 0 to a segment and face 1 to a point.
  m.F.row(0) << 0, 1, 1;
  m.F.row(1) << 4, 4, 4;
  const MeshQuery query(m);
  const ClosestHit hit = query.closestPoint(Eigen::Vector3d(0.5, 0.5, 0.25));
  EXPECT_NEAR(hit.distance, 0.25, 1e-12);
  EXPECT_TRUE(std::isfinite(query.windingNumber(Eigen::Vector3d(0.5, 0.5, 0.25))));
}

}  // namespace
}  // namespace s2p
