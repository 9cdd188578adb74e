// Held objects and hair (segment/non_garment.h) on shapes with known answers: a box held against
// a clothed cylinder is found and cut at its edge, a flare all around is not an object; a hair
// cap over a neck is cut at its edge within a few millimetres.
#include "segment/non_garment.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "body/level_set_mesh.h"
#include "core/colour.h"
#include "core/error.h"
#include "core/shapes.h"
#include "segment/isoline.h"

namespace s2p {
namespace {

using Vec3 = Eigen::Vector3d;

constexpr double kBody = 0.15;  // m, radius of the body cylinder (axis x = z = 0)
constexpr double kEase = 0.01;  // m, the garment over it

double boxDistance(const Vec3& p, const Vec3& lo, const Vec3& hi) {
  const Vec3 c = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
  const Vec3 q = (p - c).cwiseAbs() - h;
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

// A clothed trunk (a capsule of radius kBody + kEase, y from 0.2 to 1.0) with `extra` joined to
// it; the offset of every vertex from the body: its distance from the axis minus kBody.
struct Clothed {
  TriMesh mesh;
  Eigen::VectorXd offset;
};
Clothed clothed(const std::function<double(const Vec3&)>& extra) {
  const auto trunk = [](const Vec3& p) {
    const double y = std::clamp(p.y(), 0.2, 1.0);
    return (p - Vec3(0, y, 0)).norm() - (kBody + kEase);
  };
  Clothed c;
  c.mesh = meshImplicit([&](const Vec3& p) { return std::min(trunk(p), extra(p)); },
                        Vec3(-0.4, -0.05, -0.4), Vec3(0.8, 1.3, 0.8), 0.006);
  c.offset.resize(c.mesh.numVertices());
  for (int v = 0; v < c.mesh.numVertices(); ++v)
    c.offset[v] = std::hypot(c.mesh.V(v, 0), c.mesh.V(v, 2)) - kBody;
  return c;
}

TEST(HeldObjects, BoxHeldAgainstTheBodyIsFoundAndCutAtItsEdge) {
  // A bag 20 cm tall, 10 cm wide, standing 7.5 cm off the garment at +x, its back buried in it.
  const Vec3 lo(0.13, 0.45, -0.05), hi(0.235, 0.65, 0.05);
  const Clothed c = clothed([&](const Vec3& p) { return boxDistance(p, lo, hi); });
  const HeldObjects h = findHeldObjects(c.mesh, c.offset, Vec3(0, 0.5, 0), kEase);
  ASSERT_EQ(h.objects.size(), 1u);
  EXPECT_EQ(h.rejectedSeeds, 0);
  EXPECT_LT(h.objects[0].span, 90);
  EXPECT_NEAR(h.objects[0].maxOffset, std::hypot(hi.x(), hi.z()) - kBody, 0.005);
  EXPECT_NEAR(h.objects[0].centroid.y(), 0.55, 0.01);
  // The edge: the crease where the box's sides meet the garment (r = kBody + kEase), within a
  // few mm (the level set rounds the crease over a voxel, 6 mm).
  const Isoline iso = extractIsoline(c.mesh, h.field);
  ASSERT_FALSE(iso.curves.empty());
  int points = 0;
  forEachSegment(iso, [&](const Vec3& a, const Vec3&) {
    ++points;
    EXPECT_LT(boxDistance(a, lo, hi), 0.004) << a.transpose();
    EXPECT_NEAR(std::hypot(a.x(), a.z()) - kBody, kEase, 0.004) << a.transpose();
  });
  EXPECT_GT(points, 50);
  EXPECT_NEAR(h.objects[0].besideLevel, kEase, 0.001);
  EXPECT_NEAR(h.objects[0].lowered, HeldObjectOptions().edgeMargin, 0.001);
  // The seed grown to the edge level: the outer face (0.02 m²), the two sides beyond r = 0.168
  // (2 × 0.2 × 0.075) and the top and bottom beyond it (≈ 2 × 0.1 × 0.07).
  EXPECT_NEAR(h.objects[0].area, 0.064, 0.012);
  // The garment, even beside the box, is not the object.
  for (int v = 0; v < c.mesh.numVertices(); ++v)
    if (boxDistance(c.mesh.V.row(v).transpose(), lo, hi) > 0.02) {
      EXPECT_LT(h.field[v], 0) << v;
    }
}

TEST(HeldObjects, FlareAllAroundIsAGarmentNotAnObject) {
  // A skirt-like flare 8 cm off the body all around the trunk between y = 0.3 and 0.4.
  const Clothed c = clothed([](const Vec3& p) {
    const double r = std::hypot(p.x(), p.z());
    return std::max({r - (kBody + 0.08), 0.3 - p.y(), p.y() - 0.4});
  });
  const HeldObjects h = findHeldObjects(c.mesh, c.offset, Vec3(0, 0.5, 0), kEase);
  EXPECT_TRUE(h.objects.empty());
  EXPECT_EQ(h.rejectedSeeds, 1);
  EXPECT_TRUE((h.field.array() < 0).all());
}

TEST(HeldObjects, SkirtFarOffOnlyAtFrontAndBackIsAGarment) {
  // An elliptic flare: 8 cm off the body at the front and back (two seeds), 3 cm at the sides,
  // where it still stands above the edge level: grown, the seeds join all around.
  const Clothed c = clothed([](const Vec3& p) {
    const double a = kBody + 0.03, b = kBody + 0.08;
    const double e = std::hypot(p.x() / a, p.z() / b) - 1;
    return std::max({e * a, 0.3 - p.y(), p.y() - 0.4});
  });
  const HeldObjects h = findHeldObjects(c.mesh, c.offset, Vec3(0, 0.5, 0), kEase);
  EXPECT_TRUE(h.objects.empty());
  EXPECT_GE(h.rejectedSeeds, 1);
}

TEST(HeldObjects, AVolumeReachingTheHeadIsHairNotAnObject) {
  // The box of the first test raised to the head: it reaches above the chin (ceiling).
  const Vec3 lo(0.13, 0.8, -0.05), hi(0.235, 1.0, 0.05);
  const Clothed c = clothed([&](const Vec3& p) { return boxDistance(p, lo, hi); });
  const HeldObjects h = findHeldObjects(c.mesh, c.offset, Vec3(0, 0.5, 0), kEase, {}, 0.9);
  EXPECT_TRUE(h.objects.empty());
  EXPECT_EQ(h.headSeeds, 1);
  EXPECT_EQ(findHeldObjects(c.mesh, c.offset, Vec3(0, 0.5, 0), kEase, {}, 1.1).objects.size(), 1u);
}

TEST(HeldObjects, AVolumeReachingTheFeetIsAShoeNotAnObject) {
  // The box lowered to the bottom of the trunk, as a shoe's heel stands off a foot fitted short:
  // it reaches below the top of the feet's region points (floor).
  const Vec3 lo(0.13, 0.2, -0.05), hi(0.235, 0.4, 0.05);
  const Clothed c = clothed([&](const Vec3& p) { return boxDistance(p, lo, hi); });
  const double inf = std::numeric_limits<double>::infinity();
  const HeldObjects h = findHeldObjects(c.mesh, c.offset, Vec3(0, 0.5, 0), kEase, {}, inf, 0.3);
  EXPECT_TRUE(h.objects.empty());
  EXPECT_EQ(h.footSeeds, 1);
  EXPECT_EQ(findHeldObjects(c.mesh, c.offset, Vec3(0, 0.5, 0), kEase, {}, inf, 0.1).objects.size(),
            1u);
}

// The box of the first test in colours: over a navy top, a black box is a held object; a lump in
// the top's own navy (a cuff where the scan's shell folded, f2's) is that garment, and
// findHeldObjects says what it left (with its ΔE). Both get ±1 L* of shading.
TEST(HeldObjects, ALumpInTheColourOfTheGarmentBesideItIsNotAnObject) {
  const Vec3 lo(0.13, 0.45, -0.05), hi(0.235, 0.65, 0.05);
  const Clothed c = clothed([&](const Vec3& p) { return boxDistance(p, lo, hi); });
  const Vec3 navy = srgbToLab(Vec3(0.12, 0.16, 0.32)), black = srgbToLab(Vec3(0.10, 0.10, 0.11));
  const auto painted = [&](const Vec3& box) {
    Eigen::MatrixX3d lab(c.mesh.numVertices(), 3);
    for (int v = 0; v < lab.rows(); ++v) {
      const bool onBox = boxDistance(c.mesh.V.row(v).transpose(), lo, hi) < 0.003;
      lab.row(v) = (onBox ? box : navy).transpose();
      lab(v, 0) += std::sin(37.0 * v);
    }
    return lab;
  };
  const double inf = std::numeric_limits<double>::infinity();
  const Eigen::MatrixX3d blackBox = painted(black), navyBox = painted(navy);
  const HeldObjects bag =
      findHeldObjects(c.mesh, c.offset, Vec3(0, 0.5, 0), kEase, {}, inf, -inf, &blackBox);
  ASSERT_EQ(bag.objects.size(), 1u);
  EXPECT_GT(bag.objects[0].besideDeltaE, HeldObjectOptions().sameColourDeltaE);
  EXPECT_TRUE(bag.garmentColoured.empty());
  const HeldObjects lump =
      findHeldObjects(c.mesh, c.offset, Vec3(0, 0.5, 0), kEase, {}, inf, -inf, &navyBox);
  EXPECT_TRUE(lump.objects.empty());
  ASSERT_EQ(lump.garmentColoured.size(), 1u);
  EXPECT_LT(lump.garmentColoured[0], 1.0);
  EXPECT_LT(lump.field.maxCoeff(), 0);  // nothing to cut
}

TEST(HeldObjects, WrongOffsetSizeIsAnInputError) {
  const TriMesh m = makeIcosphere(1);
  EXPECT_THROW(findHeldObjects(m, Eigen::VectorXd::Zero(3), Vec3::Zero(), 0), InputError);
  const Eigen::MatrixX3d lab = Eigen::MatrixX3d::Zero(3, 3);
  EXPECT_THROW(findHeldObjects(m, Eigen::VectorXd::Zero(m.numVertices()), Vec3::Zero(), 0, {}, 1.0,
                               0.0, &lab),
               InputError);
}

// A neck and head: a cylinder of radius 0.06 from y = 0 to 0.3, rings 5 mm apart; hair above
// y = kHairEdge, skin below, with ±3 % shading.
constexpr double kHairEdge = 0.1525;  // between two rings
struct Head {
  TriMesh mesh;
  Eigen::MatrixX3d lab;
};
Head head() {
  Head h;
  h.mesh = makeCylinder(60, 48, 0.06, 0.3);
  h.lab.resize(h.mesh.numVertices(), 3);
  const Vec3 skin = srgbToLab(Vec3(0.85, 0.64, 0.52)), hair = srgbToLab(Vec3(0.2, 0.12, 0.07));
  for (int v = 0; v < h.mesh.numVertices(); ++v) {
    const double shade = 3 * std::sin(37.0 * v);
    h.lab.row(v) = (h.mesh.V(v, 1) > kHairEdge ? hair : skin).transpose();
    h.lab(v, 0) += shade;
  }
  return h;
}

TEST(Hair, SeedsLieOnTheHeadAboveTheFaceAndOffTheSkin) {
  const Head h = head();
  // The face: points at the front between y = 0.05 and 0.14.
  std::vector<Vec3> face;
  for (double y = 0.05; y <= 0.14; y += 0.01) face.push_back(Vec3(0, y, 0.06));
  Eigen::MatrixX3d skinLab(20, 3);
  for (int i = 0; i < 20; ++i) skinLab.row(i) = h.lab.row(i);  // the bottom ring: skin
  const SkinModel skin = fitSkinModel(skinLab);
  const std::vector<int> seeds = hairSeeds(h.mesh, h.lab, face, skin);
  ASSERT_FALSE(seeds.empty());
  for (int v : seeds) EXPECT_GT(h.mesh.V(v, 1), kHairEdge);
  // Every hair vertex is a seed: the cylinder lies within headRadius of the face's axis.
  int hair = 0;
  for (int v = 0; v < h.mesh.numVertices(); ++v) hair += h.mesh.V(v, 1) > kHairEdge;
  EXPECT_EQ(static_cast<int>(seeds.size()), hair);
  // No face, or a head all of skin: no seeds.
  EXPECT_TRUE(hairSeeds(h.mesh, h.lab, {}, skin).empty());
  Eigen::MatrixX3d allSkin = h.lab;
  for (int v = 0; v < allSkin.rows(); ++v) allSkin.row(v) = skinLab.row(v % 20);
  EXPECT_TRUE(hairSeeds(h.mesh, allSkin, face, skin).empty());
}

TEST(Hair, CapOverANeckIsCutAtItsEdgeWithinAFewMillimetres) {
  const Head h = head();
  GmmOptions g;
  g.covarianceFloor = 25;
  std::vector<int> hairRows, skinRows;
  for (int v = 0; v < h.mesh.numVertices(); ++v)
    (h.mesh.V(v, 1) > kHairEdge ? hairRows : skinRows).push_back(v);
  const auto rows = [&](const std::vector<int>& r) {
    Eigen::MatrixX3d out(static_cast<int>(r.size()), 3);
    for (size_t i = 0; i < r.size(); ++i) out.row(static_cast<int>(i)) = h.lab.row(r[i]);
    return out;
  };
  const GaussianMixture hair = fitGaussianMixture(rows(hairRows), g);
  const GaussianMixture skin = fitGaussianMixture(rows(skinRows), g);
  const Eigen::VectorXd phi = hairField(h.mesh, h.lab, hair, skin, Vec3(0, 0.15, 0));
  const Isoline iso = extractIsoline(h.mesh, phi);
  ASSERT_EQ(iso.curves.size(), 1u);
  EXPECT_TRUE(iso.curves[0].closed);
  for (const IsolinePoint& p : iso.curves[0].points) EXPECT_NEAR(p.position.y(), kHairEdge, 0.003);
  // Beyond `reach` of the head's centre nothing is hair, whatever its colour.
  HairOptions near;
  near.reach = 0.05;
  const Eigen::VectorXd phiNear = hairField(h.mesh, h.lab, hair, skin, Vec3(0, 0.0, 0), near);
  EXPECT_TRUE((phiNear.array() < 0).all());
}

}  // namespace
}  // namespace s2p
