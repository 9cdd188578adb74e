#include "segment/projection.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/mesh_query.h"
#include "core/shapes.h"
#include "segment/biharmonic.h"
#include "segment/isoline.h"

namespace s2p {
namespace {

// A flat sheet over [x0, x1]×[y0, y1] at height z, normals +z (or −z when flipped).
TriMesh sheet(double x0, double x1, double y0, double y1, double z, bool flipped = false) {
  TriMesh m = makeGrid(10, 10, x1 - x0, y1 - y0);
  m.V.rowwise() += Eigen::RowVector3d(x0, y0, z);
  if (flipped) m.F.col(1).swap(m.F.col(2));
  return m;
}

TriMesh join(const TriMesh& a, const TriMesh& b) {
  TriMesh m;
  m.V.resize(a.numVertices() + b.numVertices(), 3);
  m.V << a.V, b.V;
  m.F.resize(a.numFaces() + b.numFaces(), 3);
  m.F << a.F, b.F.array() + a.numVertices();
  return m;
}

// The feature point: on the body face under (0.003, 0.002).
SurfacePoint featureAt(const TriMesh& body) {
  const ClosestHit h = MeshQuery(body).closestPoint(Eigen::Vector3d(0.003, 0.002, 0));
  return {h.face, h.bary};
}

const TriMesh kBody = sheet(-0.5, 0.5, -0.5, 0.5, 0);
const ProjectionOptions kOptions{.bodyLength = 1.0};

TEST(FeatureProjection, GarmentAboveTheBodyIsKept) {
  const FeatureProjector proj(kBody, sheet(-0.5, 0.5, -0.5, 0.5, 0.05), kOptions);
  const ProjectedPoint p = proj.project(featureAt(kBody));
  EXPECT_EQ(p.status, ProjectionStatus::Ok);
  EXPECT_NEAR((p.p - Eigen::Vector3d(0.003, 0.002, 0.05)).norm(), 0, 1e-9);
  EXPECT_NEAR((p.r - p.p).norm(), 0, 1e-6);
}

TEST(FeatureProjection, Rule1NoRayHit) {
  const FeatureProjector proj(kBody, sheet(0.1, 0.5, -0.5, 0.5, 0.05), kOptions);
  const ProjectedPoint p = proj.project(featureAt(kBody));
  EXPECT_EQ(p.status, ProjectionStatus::NoHit);
  EXPECT_NEAR(p.p.x(), 0.1, 1e-9);  // the closest point exists, the ray misses
}

TEST(FeatureProjection, Rule2RayHitsTheBodyFirst) {
  const TriMesh body = join(kBody, sheet(-0.5, 0.5, -0.5, 0.5, 0.03));  // e.g. an arm above
  const FeatureProjector proj(body, sheet(-0.5, 0.5, -0.5, 0.5, 0.05), kOptions);
  const ProjectedPoint p = proj.project(featureAt(kBody));  // a face of the first sheet
  EXPECT_EQ(p.status, ProjectionStatus::HitBody);
  EXPECT_NEAR(p.r.z(), 0.03, 1e-6);
}

TEST(FeatureProjection, Rule3OppositeNormals) {
  // p lands on a flipped patch below (normal −z); the ray reaches the garment above (+z).
  const TriMesh scan =
      join(sheet(-0.5, 0.5, -0.5, 0.5, 0.02), sheet(0.01, 0.2, -0.2, 0.2, -0.012, true));
  const FeatureProjector proj(kBody, scan, kOptions);
  const ProjectedPoint p = proj.project(featureAt(kBody));
  EXPECT_NEAR(p.p.z(), -0.012, 1e-9);
  EXPECT_NEAR(p.r.z(), 0.02, 1e-6);
  EXPECT_EQ(p.status, ProjectionStatus::OppositeNormals);
}

TEST(FeatureProjection, Rule4TooFar) {
  // p lands on a small patch beside q, the ray only meets a sheet 0.5 L away.
  const TriMesh scan = join(sheet(-0.5, 0.5, -0.5, 0.5, 0.5), sheet(0.01, 0.2, -0.2, 0.2, 0.01));
  const FeatureProjector proj(kBody, scan, kOptions);
  const ProjectedPoint p = proj.project(featureAt(kBody));
  EXPECT_EQ(p.status, ProjectionStatus::TooFar);
  // The same with a longer body (0.4 L = 0.8 m > 0.49 m) is kept.
  const FeatureProjector tall(kBody, scan, {.bodyLength = 2.0});
  EXPECT_EQ(tall.project(featureAt(kBody)).status, ProjectionStatus::Ok);
}

TEST(FeatureProjection, RemovedAnchorKeepsTheSplineClosedAroundTheLimb) {
  const TriMesh body = makeCylinder(40, 48, 0.1, 1.0);
  TriMesh scan = cutByPlane(makeCylinder(40, 48, 0.12, 1.0), {1, 0, 0}, 0.1);  // hole at +x
  removeUnreferencedVertices(scan);
  const MeshQuery bq(body);
  std::vector<SurfacePoint> anchors;
  for (int i = 0; i < 8; ++i) {
    const double a = 2 * M_PI * i / 8;
    const ClosestHit h = bq.closestPoint({0.1 * std::cos(a), 0.5, 0.1 * std::sin(a)});
    anchors.push_back({h.face, h.bary});
  }
  const FeatureProjector proj(body, scan, kOptions);
  const std::vector<ProjectedPoint> all = proj.project(anchors);
  EXPECT_FALSE(all[0].ok());  // the anchor at +x faces the hole
  for (int i = 1; i < 8; ++i) EXPECT_TRUE(all[i].ok()) << i;
  const std::vector<SurfacePoint> kept = proj.projectSpline(anchors, "test_ring");
  ASSERT_EQ(kept.size(), 7u);
  // The biharmonic through the 7 survivors still gives one loop around the limb near y = 0.5.
  std::vector<ValueConstraint> c;
  for (const auto& s : kept) c.push_back({s, 0.0});
  const MeshQuery sq(scan);
  for (double y : {0.05, 0.95}) {
    const ClosestHit h = sq.closestPoint({-0.12, y, 0});
    c.push_back({{h.face, h.bary}, y > 0.5 ? 1.0 : -1.0});
  }
  const Isoline iso = extractIsoline(scan, biharmonicFunction(scan, c));
  ASSERT_EQ(iso.curves.size(), 1u);
  for (const auto& p : iso.curves[0].points) EXPECT_NEAR(p.position.y(), 0.5, 0.03);
}

TEST(FeatureProjection, EveryAnchorRemovedOrNoOverlapThrows) {
  const TriMesh body = join(kBody, sheet(-0.5, 0.5, -0.5, 0.5, 0.03));
  const FeatureProjector proj(body, sheet(-0.5, 0.5, -0.5, 0.5, 0.05), kOptions);
  EXPECT_THROW(proj.projectSpline({featureAt(kBody), featureAt(kBody)}, "neck"), InputError);
  TriMesh far = kBody;
  far.V.col(0).array() += 10;
  EXPECT_THROW(FeatureProjector(far, sheet(-0.5, 0.5, -0.5, 0.5, 0.05)), InputError);
  EXPECT_THROW(proj.project(SurfacePoint{-1, {1, 0, 0}}), InputError);
}

}  // namespace
}  // namespace s2p
