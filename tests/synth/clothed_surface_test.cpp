#include "synth/clothed_surface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "body/mannequin.h"
#include "body/plane_section.h"
#include "body/posing.h"
#include "core/error.h"
#include "core/mesh_query.h"
#include "core/mesh_topology.h"
#include "synth/garment_shapes.h"

namespace s2p {
namespace {

constexpr double kVoxel = 0.008;

const BodyModel& mannequin() {
  static const BodyModel model = makeMannequin(MannequinOptions{.targetVertices = 6000, .base = {}});
  return model;
}

BodyParams restParams() {
  BodyParams p;
  p.pose = BodyPose::zero(mannequin().numJoints());
  return p;
}

BodyParams walkingParams() {
  BodyParams p = restParams();
  const BodyModel& m = mannequin();
  auto joint = [&](Canonical c) { return m.canonical[static_cast<int>(c)].joint; };
  p.pose.axisAngle.row(joint(Canonical::LeftHip)) << -0.4, 0, 0;
  p.pose.axisAngle.row(joint(Canonical::RightHip)) << 0.35, 0, 0;
  p.pose.axisAngle.row(joint(Canonical::RightKnee)) << 0.4, 0, 0;
  return p;
}

GarmentSpec spec(GarmentType type, double ease = 0.012) {
  GarmentSpec s;
  s.type = type;
  s.ease = ease;
  return s;
}

Outfit casualOutfit() {
  Outfit o;
  o.garments = {spec(GarmentType::TShirt), spec(GarmentType::Trousers),
                spec(GarmentType::Shoes, 0.008)};
  return o;
}

GeometryOptions options(int target = 0) {
  GeometryOptions o;
  o.voxelSize = kVoxel;
  o.targetVertices = target;
  return o;
}

// Generated once per outfit name: the suite stays fast.
const ClothedSurface& generated(const std::string& name) {
  static std::map<std::string, ClothedSurface> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second;
  Outfit outfit;
  BodyParams params = restParams();
  if (name == "casual") {
    outfit = casualOutfit();
  } else if (name == "dress") {
    outfit.garments = {spec(GarmentType::Dress), spec(GarmentType::Shoes, 0.008)};
  } else if (name == "skirt-walking") {
    outfit.garments = {spec(GarmentType::TShirt), spec(GarmentType::KneeSkirt)};
    params = walkingParams();
  } else if (name == "jacket") {
    outfit.garments = {spec(GarmentType::TShirt), spec(GarmentType::Trousers),
                       spec(GarmentType::Jacket, 0.02)};
  } else if (name == "loose-jacket") {
    GarmentSpec jacket = spec(GarmentType::Jacket);
    jacket.looseness = 0.3;  // jacket_layered's
    outfit.garments = {spec(GarmentType::TShirt), jacket, spec(GarmentType::Trousers)};
  }
  return cache.emplace(name, makeClothedSurface(mannequin(), params, outfit, options()))
      .first->second;
}

void expectClosedManifoldConnected(const ClothedSurface& s) {
  const MeshTopology topo(s.mesh.F, s.mesh.numVertices());
  EXPECT_TRUE(topo.isClosed());
  EXPECT_TRUE(topo.manifoldness().isManifold());
  EXPECT_EQ(topo.numComponents(), 1);
  EXPECT_EQ(s.vertexLabel.size(), s.mesh.numVertices());
  EXPECT_EQ(s.faceLabel.size(), s.mesh.numFaces());
  EXPECT_EQ(s.restPosition.rows(), s.mesh.numVertices());
}

Eigen::Vector3d canonicalPoint(const BodyParams& params, Canonical c) {
  return poseBody(mannequin(), params).canonical.row(static_cast<int>(c)).transpose();
}

// Label of the surface vertex hit by a ray from far in front of the body towards `target`.
int frontLabel(const ClothedSurface& s, const Eigen::Vector3d& target) {
  const MeshQuery q(s.mesh);
  const auto hit = q.rayCast(target + Eigen::Vector3d(0, 0, 1.0), Eigen::Vector3d(0, 0, -1));
  EXPECT_TRUE(hit.has_value());
  if (!hit) return -1;
  const int f = hit->face;
  return s.faceLabel[f];
}

TEST(ClothedSurface, CasualOutfitIsOneClosedManifold_Slow) {
  expectClosedManifoldConnected(generated("casual"));
}

TEST(ClothedSurface, DressIsOneClosedManifold_Slow) { expectClosedManifoldConnected(generated("dress")); }

TEST(ClothedSurface, LabelsAtKnownBodyPlaces_Slow) {
  const ClothedSurface& s = generated("casual");
  const BodyParams p = restParams();
  const Eigen::Vector3d chest = canonicalPoint(p, Canonical::Chest);
  const Eigen::Vector3d thigh = 0.5 * (canonicalPoint(p, Canonical::LeftHip) +
                                       canonicalPoint(p, Canonical::LeftKnee));
  const Eigen::Vector3d nose = canonicalPoint(p, Canonical::Nose);
  const Eigen::Vector3d toe = canonicalPoint(p, Canonical::LeftToeTip);
  EXPECT_EQ(frontLabel(s, chest), static_cast<int>(Label::Upper));
  EXPECT_EQ(frontLabel(s, thigh), static_cast<int>(Label::Lower));
  EXPECT_EQ(frontLabel(s, nose + Eigen::Vector3d(0, 0.02, 0)), static_cast<int>(Label::Skin));
  EXPECT_EQ(frontLabel(s, toe + Eigen::Vector3d(0, 0.03, -0.05)), static_cast<int>(Label::Shoes));
  // Forearms are bare under short sleeves.
  const Eigen::Vector3d forearm = 0.5 * (canonicalPoint(p, Canonical::LeftElbow) +
                                         canonicalPoint(p, Canonical::LeftWrist));
  EXPECT_EQ(frontLabel(s, forearm), static_cast<int>(Label::Skin));
  // Every label of the outfit shows, nothing else does.
  std::map<int, int> count;
  for (int f = 0; f < s.faceLabel.size(); ++f) ++count[s.faceLabel[f]];
  EXPECT_EQ(count.size(), 4u);
  EXPECT_EQ(count.count(static_cast<int>(Label::Gap)), 0u);
}

TEST(ClothedSurface, JacketHidesTheInnerTShirt_Slow) {
  const ClothedSurface& s = generated("jacket");
  ASSERT_EQ(s.garments.size(), 3u);
  const TrueGarment& tshirt = s.garments[0];
  const TrueGarment& jacket = s.garments[2];
  EXPECT_GT(jacket.visibleArea, 0.5);
  EXPECT_LT(tshirt.visibleArea, 0.01 * jacket.visibleArea);
  EXPECT_NE(std::find(jacket.occludes.begin(), jacket.occludes.end(), "tshirt"),
            jacket.occludes.end());
  EXPECT_TRUE(tshirt.occludes.empty() ||
              std::find(tshirt.occludes.begin(), tshirt.occludes.end(), "jacket") ==
                  tshirt.occludes.end());
}

// A loose sleeve is its cone down to the cuff, closed there by a cap of gap faces (the jacket's
// inside seen through the opening); the body-following part of the sleeve ends inside the cone.
// When that part ran on to the hem, its end face came out through the cap as a ring of "upper"
// around the wrist (45 vertices a cuff at 50k), which no loose sleeve has.
TEST(ClothedSurface, ALooseSleeveEndsInACapOfGapFacesWithoutAClothRingAtTheWrist_Slow) {
  const ClothedSurface& s = generated("loose-jacket");
  const BodyParams p = restParams();
  const Eigen::Vector3d el = canonicalPoint(p, Canonical::LeftElbow);
  const Eigen::Vector3d wr = canonicalPoint(p, Canonical::LeftWrist);
  const double length = (wr - el).norm();
  const Eigen::Vector3d axis = (wr - el) / length;
  int gap = 0, ring = 0;
  for (int v = 0; v < s.mesh.numVertices(); ++v) {
    const Eigen::Vector3d d = s.mesh.V.row(v).transpose() - el;
    const double along = d.dot(axis), radial = (d - along * axis).norm();
    if (along < 0.8 * length || along > 1.0 * length) continue;  // the cap lies at 0.9
    gap += s.vertexLabel[v] == static_cast<int>(Label::Gap);
    ring += s.vertexLabel[v] == static_cast<int>(Label::Upper) && radial < 0.04;
  }
  EXPECT_GT(gap, 10);
  EXPECT_EQ(ring, 0);
}

TEST(ClothedSurface, TuckedInTopIsHiddenByTheTrousersAtTheWaist_Slow) {
  const ClothedSurface& loose = generated("casual");
  EXPECT_EQ(loose.garments[0].occludes, std::vector<std::string>{"trousers"});
  EXPECT_TRUE(loose.garments[1].occludes.empty());
  Outfit tucked = casualOutfit();
  tucked.garments[0].tuckedIn = true;
  const ClothedSurface s = makeClothedSurface(mannequin(), restParams(), tucked, options());
  EXPECT_EQ(s.garments[1].occludes, std::vector<std::string>{"tshirt"});
  EXPECT_TRUE(s.garments[0].occludes.empty());
  EXPECT_LT(s.garments[0].visibleArea, loose.garments[0].visibleArea);
}

TrueBoundary boundaryOf(const ClothedSurface& s, Label a, Label b) {
  for (const TrueBoundary& t : s.boundaries)
    if (t.a == a && t.b == b) return t;
  return {};
}

TriMesh facesWithLabel(const ClothedSurface& s, Label label) {
  TriMesh m;
  m.V = s.mesh.V;
  std::vector<int> faces;
  for (int f = 0; f < s.faceLabel.size(); ++f)
    if (s.faceLabel[f] == static_cast<int>(label)) faces.push_back(f);
  m.F.resize(static_cast<int>(faces.size()), 3);
  for (std::size_t i = 0; i < faces.size(); ++i) m.F.row(int(i)) = s.mesh.F.row(faces[i]);
  return m;
}

TEST(ClothedSurface, BoundaryCurvesLieBetweenTheirLabels_Slow) {
  const ClothedSurface& s = generated("casual");
  for (auto [a, b] : {std::pair{Label::Skin, Label::Upper}, std::pair{Label::Lower, Label::Shoes},
                      std::pair{Label::Upper, Label::Lower}}) {
    const TrueBoundary t = boundaryOf(s, a, b);
    ASSERT_FALSE(t.curves.empty()) << toString(a) << "|" << toString(b);
    const MeshQuery qa(facesWithLabel(s, a)), qb(facesWithLabel(s, b));
    for (const Eigen::MatrixX3d& c : t.curves)
      for (int i = 0; i < c.rows(); ++i) {
        const Eigen::Vector3d p = c.row(i).transpose();
        EXPECT_LT(qa.closestPoint(p).distance, kVoxel);
        EXPECT_LT(qb.closestPoint(p).distance, kVoxel);
      }
  }
  // Skin|upper: neckline and two sleeve hems, each a closed loop.
  const TrueBoundary su = boundaryOf(s, Label::Skin, Label::Upper);
  int closed = 0;
  for (bool c : su.closed) closed += c;
  EXPECT_EQ(closed, 3);
}

TEST(ClothedSurface, SleeveHemLengthIsTheArmGirthAtTheHem_Slow) {
  const ClothedSurface& s = generated("casual");
  const BodyParams p = restParams();
  const PosedBody body = poseBody(mannequin(), p);
  const Eigen::Vector3d sh = canonicalPoint(p, Canonical::LeftShoulder);
  const Eigen::Vector3d el = canonicalPoint(p, Canonical::LeftElbow);
  const Eigen::Vector3d hem = sh + 0.55 * (el - sh);  // t-shirt sleeve hem at 55 % of the arm
  // The arm's girth in the hem plane (the section loop around the arm).
  double girth = 0;
  double best = 1e9;
  for (const SectionLoop& l : planeSection(body.mesh, hem, el - sh)) {
    const double d = (l.points.colwise().mean().transpose() - hem).norm();
    if (!l.closed || d > best) continue;
    best = d;
    girth = 0;
    for (int i = 0; i < l.points.rows(); ++i)
      girth += (l.points.row((i + 1) % l.points.rows()) - l.points.row(i)).norm();
  }
  ASSERT_GT(girth, 0.15);
  // The label changes where the hem's riser meets the skin (the riser belongs to the garment),
  // so the curve is the girth, not the garment rim (girth + 2π·ease ≈ +7.5 cm), up to the
  // level set's rounding of the corner (under one voxel).
  const TrueBoundary su = boundaryOf(s, Label::Skin, Label::Upper);
  double length = -1;
  best = 1e9;
  for (std::size_t k = 0; k < su.curves.size(); ++k) {
    const Eigen::MatrixX3d& c = su.curves[k];
    const double d = (c.colwise().mean().transpose() - hem).norm();
    if (!su.closed[k] || d > best) continue;
    best = d;
    length = 0;
    for (int i = 0; i < c.rows(); ++i) length += (c.row((i + 1) % c.rows()) - c.row(i)).norm();
  }
  EXPECT_LT(best, 0.03);
  const double ease = 0.012;
  EXPECT_GT(length, girth - 0.01);
  EXPECT_LT(length, girth + 2 * M_PI * kVoxel);
  EXPECT_LT(length, girth + 2 * M_PI * ease - 0.03);
}

void expectSkirtHidesThighs(const ClothedSurface& s) {
  const PosedBody rest = poseBody(mannequin(), restParams());
  const RestSkeleton skel(rest.canonical);
  // The hem: the gap cap under the skirt, horizontal, facing down.
  double hemY = -1e9, gapArea = 0;
  Eigen::Vector3d normalSum = Eigen::Vector3d::Zero();
  const Eigen::MatrixX3d N = faceNormals(s.mesh);
  const Eigen::VectorXd A = faceAreas(s.mesh);
  for (int f = 0; f < s.mesh.numFaces(); ++f) {
    if (s.faceLabel[f] != static_cast<int>(Label::Gap)) continue;
    const double y = (s.mesh.V(s.mesh.F(f, 0), 1) + s.mesh.V(s.mesh.F(f, 1), 1) +
                      s.mesh.V(s.mesh.F(f, 2), 1)) / 3;
    hemY = std::max(hemY, y);
    gapArea += A[f];
    normalSum += A[f] * N.row(f).transpose();
  }
  ASSERT_GT(gapArea, 0.005);
  EXPECT_LT(normalSum.y() / gapArea, -0.8);  // mostly downwards
  int bareThigh = 0;
  for (int f = 0; f < s.mesh.numFaces(); ++f) {
    if (s.faceLabel[f] != static_cast<int>(Label::Skin)) continue;
    Eigen::Vector3d c = Eigen::Vector3d::Zero(), r = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      c += s.mesh.V.row(s.mesh.F(f, k)).transpose() / 3;
      r += s.restPosition.row(s.mesh.F(f, k)).transpose() / 3;
    }
    const BodyPart part = skel.locate(r).part;
    if ((part == BodyPart::LeftThigh || part == BodyPart::RightThigh) && c.y() > hemY + 0.01)
      ++bareThigh;
  }
  EXPECT_EQ(bareThigh, 0);
}

TEST(ClothedSurface, DressHidesTheThighsAndClosesWithDownwardGapFaces_Slow) {
  expectSkirtHidesThighs(generated("dress"));
  const ClothedSurface& s = generated("dress");
  EXPECT_TRUE(s.garments[0].onePiece);
  // The hem rim is the upper|skin boundary.
  EXPECT_FALSE(boundaryOf(s, Label::Skin, Label::Upper).curves.empty());
  EXPECT_FALSE(boundaryOf(s, Label::Skin, Label::Gap).curves.empty());
}

TEST(ClothedSurface, SkirtHidesTheThighsWhenWalking_Slow) {
  expectSkirtHidesThighs(generated("skirt-walking"));
  expectClosedManifoldConnected(generated("skirt-walking"));
}

TEST(ClothedSurface, HolesGiveExactlyTheAskedBoundaryLoops_Slow) {
  Outfit outfit = casualOutfit();
  GeometryOptions o = options(8000);
  o.holes = 4;
  const ClothedSurface s = makeClothedSurface(mannequin(), restParams(), outfit, o);
  const MeshTopology topo(s.mesh.F, s.mesh.numVertices());
  EXPECT_EQ(topo.boundaryLoops().size(), 4u);
  EXPECT_EQ(s.stats.holes, 4);
  EXPECT_TRUE(topo.manifoldness().isManifold());
  EXPECT_EQ(s.faceLabel.size(), s.mesh.numFaces());
  EXPECT_EQ(s.vertexLabel.size(), s.mesh.numVertices());
}

TEST(ClothedSurface, DecimationReachesTheTarget_Slow) {
  const ClothedSurface s =
      makeClothedSurface(mannequin(), restParams(), casualOutfit(), options(5000));
  EXPECT_GT(s.stats.levelSetVertices, 20000);
  EXPECT_NEAR(s.mesh.numVertices(), 5000, 500);
  const MeshTopology topo(s.mesh.F, s.mesh.numVertices());
  EXPECT_TRUE(topo.isClosed());
  EXPECT_TRUE(topo.manifoldness().isManifold())
      << topo.manifoldness().nonManifoldEdges.size() << " edges, "
      << topo.manifoldness().nonManifoldVertices.size() << " vertices";
  EXPECT_EQ(topo.numComponents(), 1);
}

TEST(ClothedSurface, SameSeedGivesIdenticalArrays_Slow) {
  GeometryOptions o = options(6000);
  o.noise = 0.001;
  o.holes = 2;
  Outfit outfit;
  outfit.garments = {spec(GarmentType::LongSleeveShirt), spec(GarmentType::Shorts),
                     spec(GarmentType::Hair, 0.015)};
  const ClothedSurface a = makeClothedSurface(mannequin(), walkingParams(), outfit, o);
  const ClothedSurface b = makeClothedSurface(mannequin(), walkingParams(), outfit, o);
  EXPECT_TRUE(a.mesh.V == b.mesh.V);
  EXPECT_TRUE(a.mesh.F == b.mesh.F);
  EXPECT_TRUE(a.vertexLabel == b.vertexLabel);
  EXPECT_TRUE(a.faceLabel == b.faceLabel);
  EXPECT_TRUE(a.restPosition == b.restPosition);
  ASSERT_EQ(a.boundaries.size(), b.boundaries.size());
  for (std::size_t i = 0; i < a.boundaries.size(); ++i) {
    ASSERT_EQ(a.boundaries[i].curves.size(), b.boundaries[i].curves.size());
    for (std::size_t k = 0; k < a.boundaries[i].curves.size(); ++k)
      EXPECT_TRUE(a.boundaries[i].curves[k] == b.boundaries[i].curves[k]);
  }
}

// Small enough for the sanitizer run: a coarse level set of a simple outfit (a sleeveless top
// and shoes), with normal noise of σ metres.
ClothedSurface coarseOutfit(double noise = 0) {
  GeometryOptions o;
  o.voxelSize = 0.014;
  o.targetVertices = 0;
  o.noise = noise;
  Outfit outfit;
  outfit.garments = {spec(GarmentType::SleevelessTop, 0.028), spec(GarmentType::Shoes, 0.02)};
  return makeClothedSurface(mannequin(), restParams(), outfit, o);
}

TEST(ClothedSurface, CoarseOutfitIsClosedAndLabelled) {
  const ClothedSurface s = coarseOutfit();
  expectClosedManifoldConnected(s);
  std::map<int, int> count;
  for (int f = 0; f < s.faceLabel.size(); ++f) ++count[s.faceLabel[f]];
  EXPECT_EQ(count.size(), 3u);  // skin, upper, shoes
  EXPECT_GT(count[static_cast<int>(Label::Upper)], 100);
  EXPECT_GT(count[static_cast<int>(Label::Shoes)], 20);
  // Rest positions of an unposed body are the body points under the surface: within the
  // garment's offset of each vertex.
  for (int v = 0; v < s.mesh.numVertices(); ++v)
    EXPECT_LT((s.mesh.V.row(v) - s.restPosition.row(v)).norm(), 0.06);
}

// The truth describes the scan as delivered: with normal noise, every boundary point lies on an
// edge of the noisy surface (before the fix it lay on the clean one, σ away, and a cut along the
// noisy surface measured longer than the truth from the noise alone).
TEST(ClothedSurface, TrueBoundariesLieOnTheNoisySurface) {
  const ClothedSurface s = coarseOutfit(0.004);
  const MeshQuery query(s.mesh);
  int points = 0;
  for (const TrueBoundary& b : s.boundaries)
    for (const Eigen::MatrixX3d& c : b.curves)
      for (int i = 0; i < c.rows(); ++i, ++points)
        EXPECT_LT(query.closestPoint(c.row(i).transpose()).distance, 1e-9);
  EXPECT_GT(points, 50);
}

TEST(ClothedSurface, BadInputThrowsInputError) {
  Outfit twice;
  twice.garments = {spec(GarmentType::TShirt), spec(GarmentType::TShirt)};
  EXPECT_THROW(makeClothedSurface(mannequin(), restParams(), twice, options()), InputError);
  GeometryOptions o = options();
  o.voxelSize = 0;
  EXPECT_THROW(makeClothedSurface(mannequin(), restParams(), casualOutfit(), o), InputError);
  o = options();
  o.holes = 7;
  EXPECT_THROW(makeClothedSurface(mannequin(), restParams(), casualOutfit(), o), InputError);
  o = options();
  o.noise = std::nan("");
  EXPECT_THROW(makeClothedSurface(mannequin(), restParams(), casualOutfit(), o), InputError);
  Outfit bad = casualOutfit();
  bad.garments[0].ease = -0.01;
  EXPECT_THROW(makeClothedSurface(mannequin(), restParams(), bad, options()), InputError);
}

}  // namespace
}  // namespace s2p
