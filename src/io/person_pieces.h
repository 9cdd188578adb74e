// Which pieces (connected components) of a scan are the person (issue 17, "keep the person, drop
// the rest"): the largest piece, plus every piece within reach of it or of a piece already kept
// (legs seen below a skirt, a hand or feet scanned apart, fingertips); flat horizontal patches
// at the feet or head end that reach beyond the feet (floor remnants) and pieces out of reach
// (floaters: a bag on a chair, a speck in the air) are dropped. A scan whose largest piece is
// flat (the floor) or that holds a second person-sized piece out of reach (two people) is
// refused: no choice of pieces would be right.
//
// Works on a scan in metres with +Y up (after normalizeScan); every threshold is relative to
// the largest piece's height or in metres.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/tri_mesh.h"
#include "io/normalize.h"
#include "io/scan.h"

namespace s2p {

enum class PieceRole {
  Person,  // the largest piece or one within reach of the person
  Floor,   // flat, horizontal, at an end of the person, reaching beyond its feet
  Floater  // out of reach of the person
};
const char* toString(PieceRole role);

struct PersonPiecesOptions {
  // A piece belongs to the person when some vertex lies within this fraction of the largest
  // piece's height of a vertex of a piece kept (vertices thinned to one per 1/8 of it).
  // 0.05 ≈ 6–9 cm: legs under a flared skirt, a hand at the wrist.
  double reachFraction = 0.05;
  // Flat: the extent along the piece's thinnest principal axis is below max(this (m), 4 % of
  // its longest extent); floor: flat, its normal within 25° of the vertical, lying within
  // floorBandFraction of the height of the person's lowest (or highest) point, with at least
  // half of its area outside the person's footprint (so a shoe's sole scanned apart stays); the
  // footprint is the set of 2 cm (x, z) cells holding a vertex of the person in that band, grown
  // by one cell (not their bounding box, which holds the floor between the feet).
  double floorThickness = 0.03;
  double floorBandFraction = 0.05;
  // Two people: a piece out of reach with at least this fraction of the largest piece's area
  // and of its height.
  double personAreaFraction = 0.25;
  double personHeightFraction = 0.5;
};

struct PieceInfo {
  int faces = 0, vertices = 0;
  double area = 0;                // m²
  BoundingBox box;                // metres
  double thickness = 0;           // m, extent along the thinnest principal axis
  double length = 0;              // m, extent along the longest principal axis
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();  // the thinnest principal axis
  double distance = 0;            // m, about how far from the person (0 for the person's pieces)
  PieceRole role = PieceRole::Person;
};

struct PersonPieces {
  std::vector<PieceInfo> pieces;  // one per connected component of faces (MeshTopology order)
  int largest = 0;                // index of the largest piece (by area)
  std::vector<bool> keepFace;     // #F: the face belongs to a piece of the person
  int keptPieces = 0, floorPieces = 0, floaterPieces = 0;
  int droppedVertices = 0, droppedFaces = 0;
  double droppedArea = 0;  // m²
  // What was kept and dropped and how much, for the report (empty for a one-piece scan).
  std::vector<std::string> warnings;
};

// Classifies the pieces of `mesh` (metres, +Y up). `what` names the scan in messages. Throws
// InputError when the largest piece is flat (a floor patch: the person is missing or fused to
// it) or a second person-sized piece stands out of reach (two people).
PersonPieces findPersonPieces(const TriMesh& mesh, const PersonPiecesOptions& options = {},
                              const std::string& what = "scan");

// Keeps only the faces with keepFace[f] and the vertices they use, in their original order:
// mesh, colours and the texture's per-face UV rows follow. keepFace has #F entries.
void keepFaces(Scan& scan, const std::vector<bool>& keepFace);

// normalizeScan that keeps only the person: normalises, classifies the pieces in that frame
// and, when some are dropped, keepFaces and normalises what is left again from the file's frame
// (a floor patch or a floater moves the feet, the centre and the up-axis votes). When the whole
// scan cannot be normalised (a floor patch wider than a person is tall), the pieces are
// classified in the largest piece's own frame. Throws as normalizeScan and findPersonPieces.
PersonPieces normalizePerson(Scan& scan, const NormalizeOptions& options, NormalizeReport& report,
                             const PersonPiecesOptions& pieces = {});

}  // namespace s2p
