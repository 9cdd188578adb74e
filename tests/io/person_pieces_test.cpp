#include "io/person_pieces.h"

#include <gtest/gtest.h>

#include "core/mesh_topology.h"
#include "core/shapes.h"
#include "io_test_util.h"

namespace s2p {
namespace {

using test::concat;

// Ellipsoid with the given centre and radii (a dense closed piece, poles on ±y).
TriMesh ellipsoid(const Eigen::Vector3d& c, const Eigen::Vector3d& r) {
  TriMesh m = makeUvSphere(40, 48);
  m.V = (m.V * r.asDiagonal()).rowwise() + c.transpose();
  return m;
}
// A flat horizontal square sheet of side `side` at height y, centred on (x, z).
TriMesh sheet(double x, double y, double z, double side) {
  const TriMesh g = makeGrid(30, 30, side, side);
  TriMesh m = g;
  for (int v = 0; v < g.numVertices(); ++v)
    m.V.row(v) << x - side / 2 + g.V(v, 0), y, z - side / 2 + g.V(v, 1);
  return m;
}
// A stand-in person: a torso-and-skirt ellipsoid 0.6–1.75 m (the largest piece) and, as the
// legs seen below a skirt, two leg ellipsoids 0–0.64 m, 2 cm below it.
TriMesh body() {
  return ellipsoid({0, 1.175, 0}, {0.2, 0.575, 0.12});
}
TriMesh legs() {
  return concat(ellipsoid({-0.09, 0.32, 0}, {0.06, 0.32, 0.06}),
                ellipsoid({0.09, 0.32, 0}, {0.06, 0.32, 0.06}));
}
// A floor patch under the feet, 0.8 m wide (smaller than the body).
TriMesh floorPatch() {
  return sheet(0, -0.005, 0, 0.8);
}

int countRole(const PersonPieces& p, PieceRole role) {
  int n = 0;
  for (const PieceInfo& i : p.pieces) n += i.role == role;
  return n;
}

TEST(PersonPieces, BodyAndLegsAreKeptFloorAndFloatersDropped) {
  TriMesh m = concat(body(), legs());
  const int personFaces = m.numFaces(), personVertices = m.numVertices();
  const TriMesh floor = floorPatch();
  m = concat(m, floor);
  // Floaters: a 4 cm ball 0.8 m to the side at chest height and a speck 0.5 m in front.
  const TriMesh ball = ellipsoid({1.0, 1.2, 0}, {0.02, 0.02, 0.02});
  const TriMesh speck = ellipsoid({0, 1.0, 0.6}, {0.005, 0.005, 0.005});
  m = concat(concat(m, ball), speck);
  const PersonPieces p = findPersonPieces(m);
  ASSERT_EQ(p.pieces.size(), 6u);
  EXPECT_EQ(p.keptPieces, 3);  // body and two legs
  EXPECT_EQ(p.floorPieces, 1);
  EXPECT_EQ(p.floaterPieces, 2);
  EXPECT_EQ(countRole(p, PieceRole::Person), 3);
  for (int f = 0; f < m.numFaces(); ++f) ASSERT_EQ(p.keepFace[f], f < personFaces) << f;
  EXPECT_EQ(p.droppedFaces, m.numFaces() - personFaces);
  EXPECT_EQ(p.droppedVertices, m.numVertices() - personVertices);
  EXPECT_NEAR(p.droppedArea, surfaceArea(floor) + surfaceArea(ball) + surfaceArea(speck), 1e-9);
  ASSERT_EQ(p.warnings.size(), 3u);  // kept extra pieces, the floor, the floaters
  EXPECT_NE(p.warnings[0].find("kept 3 pieces"), std::string::npos) << p.warnings[0];
  EXPECT_NE(p.warnings[1].find("1 floor patch"), std::string::npos) << p.warnings[1];
  EXPECT_NE(p.warnings[2].find("2 floaters"), std::string::npos) << p.warnings[2];

  Scan scan;
  scan.mesh = m;
  scan.colour = Eigen::MatrixX3d::Constant(m.numVertices(), 3, 0.5);
  keepFaces(scan, p.keepFace);
  EXPECT_EQ(scan.mesh.numFaces(), personFaces);
  EXPECT_EQ(scan.mesh.numVertices(), personVertices);
  EXPECT_EQ(scan.colour.rows(), personVertices);
  EXPECT_EQ(MeshTopology(scan.mesh.F, scan.mesh.numVertices()).numComponents(), 3);
}

// Legs farther below the body than the reach (5 % of its height, 5.75 cm) are not the person's.
TEST(PersonPieces, LegsOutOfReachAreFloaters) {
  TriMesh far = legs();
  far.V.col(1).array() -= 0.1;  // 12 cm below the body
  const PersonPieces p = findPersonPieces(concat(body(), far));
  EXPECT_EQ(p.keptPieces, 1);
  EXPECT_EQ(p.floaterPieces, 2);
}

TEST(PersonPieces, OnePieceScanKeepsEverythingWithoutWarnings) {
  const PersonPieces p = findPersonPieces(body());
  EXPECT_EQ(p.keptPieces, 1);
  EXPECT_EQ(p.droppedFaces, 0);
  EXPECT_TRUE(p.warnings.empty());
}

// A shoe's sole scanned apart is flat and horizontal at the feet but lies inside the feet's
// footprint: kept, not taken for the floor.
TEST(PersonPieces, SoleUnderTheFeetIsNotFloor) {
  const TriMesh m = concat(concat(body(), legs()), sheet(0.09, -0.005, 0, 0.09));
  const PersonPieces p = findPersonPieces(m);
  EXPECT_EQ(p.keptPieces, 4);
  EXPECT_EQ(p.floorPieces, 0);
}

// A floor remnant between the feet (a phone scan's floor seen between the legs) lies inside
// the bounding box of the feet but under no foot: dropped as floor, not kept as a sole.
TEST(PersonPieces, FloorBetweenTheFeetIsFloor) {
  const TriMesh wideLegs = concat(ellipsoid({-0.15, 0.32, 0}, {0.06, 0.32, 0.06}),
                                  ellipsoid({0.15, 0.32, 0}, {0.06, 0.32, 0.06}));
  const PersonPieces p =
      findPersonPieces(concat(concat(body(), wideLegs), sheet(0, -0.005, 0, 0.12)));
  EXPECT_EQ(p.keptPieces, 3);
  EXPECT_EQ(p.floorPieces, 1);
}

TEST(PersonPieces, LargestPieceFlatIsTheFloorError) {
  const TriMesh m = concat(sheet(0, -0.005, 0, 3.0), body());
  EXPECT_TRUE(test::throwsExactly<InputError>([&] { findPersonPieces(m); }));
  try {
    findPersonPieces(m, {}, "floor.ply");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("floor"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("floor.ply"), std::string::npos) << e.what();
  }
}

TEST(PersonPieces, TwoPeopleError) {
  TriMesh other = concat(body(), legs());
  other.V.rowwise() += Eigen::RowVector3d(1.0, 0, 0);  // a second person 0.6 m to the side
  const TriMesh m = concat(concat(body(), legs()), other);
  EXPECT_TRUE(test::throwsExactly<InputError>([&] { findPersonPieces(m); }));
  try {
    findPersonPieces(m);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("two people"), std::string::npos) << e.what();
  }
}

// normalizePerson: a floor patch lower than the feet moved them off y = 0; once it is dropped
// the feet are on y = 0 again, and a scan in millimetres comes out in metres.
TEST(PersonPieces, NormalizePersonDropsTheFloorBeforePlacingTheFeet) {
  Scan scan;
  TriMesh m = concat(concat(body(), legs()), sheet(0, -0.05, 0, 0.8));
  m.V *= 1000.0;  // millimetres
  scan.mesh = m;
  NormalizeReport report;
  const PersonPieces p = normalizePerson(scan, {}, report);
  EXPECT_EQ(p.floorPieces, 1);
  EXPECT_EQ(report.units, Units::Millimetres);
  EXPECT_EQ(scan.mesh.numFaces(), 3 * body().numFaces());
  EXPECT_NEAR(scan.mesh.V.col(1).minCoeff(), 0.0, 1e-9);
  EXPECT_NEAR(scan.mesh.V.col(1).maxCoeff(), 1.75, 1e-9);
}

}  // namespace
}  // namespace s2p
