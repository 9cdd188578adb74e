#include "synth/raw_scan.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

#include "body/mannequin.h"
#include "core/error.h"
#include "core/labels.h"
#include "core/mesh_topology.h"
#include "io/cleanup.h"
#include "io/person_pieces.h"
#include "synth/presets.h"
#include "synth/synthesize.h"

namespace s2p {
namespace {

const BodyModel& mannequin() {
  static const BodyModel model = makeMannequin();
  return model;
}

// A preset at a coarse voxel size and 3000 vertices: the same degradations, fast.
SynthScan coarse(const std::string& name) {
  SynthOptions o = presetOptions(name);
  o.geometry.voxelSize = 0.012;
  o.geometry.targetVertices = 3000;
  return synthesize(mannequin(), o);
}

int countLabel(const Eigen::VectorXi& labels, Label l) {
  return static_cast<int>((labels.array() == static_cast<int>(l)).count());
}

// phone_scan: the scan arrives in pieces (40 texture charts plus the floor remnants) whose
// border vertices share positions, on a 1 mm grid; clean-up welds the charts back into one
// person and drops exactly the floor.
TEST(RawScan, PhoneScanHasItsDefectsAndCleanUpUndoesThem) {
  const SynthScan s = coarse("phone_scan");
  const RawScanOptions& raw = presetOptions("phone_scan").raw;
  const TriMesh& m = s.scan.mesh;
  ASSERT_EQ(s.vertexLabel.size(), m.numVertices());
  ASSERT_EQ(s.faceLabel.size(), m.numFaces());
  ASSERT_EQ(s.scan.colour.rows(), m.numVertices());

  // Pieces: at least one per chart plus the floor patches.
  const MeshTopology topo(m.F, m.numVertices());
  EXPECT_GE(topo.numComponents(), raw.textureCharts + 1);
  // Duplicate positions: vertices split at chart borders.
  std::set<std::array<long, 3>> positions;
  for (int v = 0; v < m.numVertices(); ++v)
    positions.insert(
        {std::lround(m.V(v, 0) * 1e3), std::lround(m.V(v, 1) * 1e3), std::lround(m.V(v, 2) * 1e3)});
  const int duplicates = m.numVertices() - static_cast<int>(positions.size());
  EXPECT_GT(duplicates, 100);
  // Coordinates on the 1 mm grid.
  EXPECT_LT(((m.V * 1e3).array() - (m.V * 1e3).array().round()).abs().maxCoeff(), 1e-6);
  // Floor remnants under the soles, labelled Other.
  const int floorFaces = countLabel(s.faceLabel, Label::Other);
  EXPECT_GT(floorFaces, 50);
  double personMinY = INFINITY;
  for (int v = 0; v < m.numVertices(); ++v)
    if (s.vertexLabel[v] != static_cast<int>(Label::Other))
      personMinY = std::min(personMinY, m.V(v, 1));
  for (int f = 0; f < m.numFaces(); ++f)
    if (s.faceLabel[f] == static_cast<int>(Label::Other)) {
      EXPECT_LT(m.V(m.F(f, 0), 1), personMinY - 0.003);
    }

  // Clean-up as `run` does it: the charts weld into one piece, the floor patches are dropped,
  // nothing of the person is.
  Scan scan = s.scan;
  const CleanupReport cleaned = cleanScan(scan);
  EXPECT_GE(cleaned.weldedVertices, duplicates);
  NormalizeReport report;
  const PersonPieces pieces = normalizePerson(scan, NormalizeOptions{}, report);
  EXPECT_GE(pieces.floorPieces, 1);
  EXPECT_EQ(pieces.floaterPieces, 0);
  // Nearly all of the floor goes (a crumb of a cell or two under a shoe's edge may stay, as a
  // sole scanned apart would), and nothing else does.
  EXPECT_LE(pieces.droppedFaces, floorFaces);
  EXPECT_GE(pieces.droppedFaces, 0.95 * floorFaces);
  EXPECT_EQ(scan.mesh.numFaces(),
            m.numFaces() - pieces.droppedFaces - cleaned.degenerateFaces - cleaned.duplicateFaces);
}

// skirt_legs_piece: under the knee-length skirt the legs are a piece of their own, and the
// clean-up keeps them.
TEST(RawScan, SkirtLegsAreASeparatePieceThatCleanUpKeeps) {
  const SynthScan s = coarse("skirt_legs_piece");
  const TriMesh& m = s.scan.mesh;
  EXPECT_EQ(countLabel(s.faceLabel, Label::Gap), 0);
  const MeshTopology topo(m.F, m.numVertices());
  ASSERT_GE(topo.numComponents(), 2);
  // The largest piece holds the skirt; another one holds the shoes (the legs' piece).
  std::vector<int> size(topo.numComponents(), 0);
  for (int f = 0; f < m.numFaces(); ++f) ++size[topo.faceComponent()[f]];
  const int largest = static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
  bool shoesApart = false;
  for (int f = 0; f < m.numFaces(); ++f)
    if (s.faceLabel[f] == static_cast<int>(Label::Shoes))
      shoesApart |= topo.faceComponent()[f] != largest;
  EXPECT_TRUE(shoesApart);

  Scan scan = s.scan;
  cleanScan(scan);
  NormalizeReport report;
  const int before = scan.mesh.numFaces();
  const PersonPieces pieces = normalizePerson(scan, NormalizeOptions{}, report);
  EXPECT_GE(pieces.keptPieces, 2);
  EXPECT_EQ(pieces.droppedFaces, 0);
  EXPECT_EQ(scan.mesh.numFaces(), before);
}

TEST(RawScan, OptionsRoundTripAndBadValuesAreRefused) {
  const RawScanOptions o = presetOptions("phone_scan").raw;
  EXPECT_EQ(rawScanOptionsToJson(rawScanOptionsFromJson(rawScanOptionsToJson(o))),
            rawScanOptionsToJson(o));
  RawScanOptions bad;
  bad.quantisation = 0.5;
  EXPECT_THROW(validateRawScanOptions(bad), InputError);
  bad = {};
  bad.smallHoles = -1;
  EXPECT_THROW(validateRawScanOptions(bad), InputError);
}

}  // namespace
}  // namespace s2p
