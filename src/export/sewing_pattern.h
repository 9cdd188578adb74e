// A sewing pattern as the printing and cutting files see it: flat pieces with their sew lines,
// notches, grainlines and labels, in metres, nothing about how they were made. The writers
// (pattern_print.h: SVG and PDF at 1:1; pattern_dxf.h: DXF-AAMA) add the seam allowance, the
// layout, the test square and the page tiling.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace s2p {

struct SewingNotch {
  Eigen::Vector2d at = Eigen::Vector2d::Zero();       // on the sew line (m, piece frame)
  Eigen::Vector2d normal = Eigen::Vector2d::UnitY();  // unit, pointing out of the piece
};

struct SewingPiece {
  std::string name;       // "front", "left_sleeve"
  std::string garment;    // "tshirt"
  int quantity = 1;       // how many to cut
  bool mirrored = false;  // quantity 2 of a symmetric pair: the second one cut mirrored
  // The sew line: a closed polygon (metres, the piece's own frame, counter-clockwise, the last
  // point not repeating the first), dense enough to stand for its curves (≤ 1 mm chord error).
  std::vector<Eigen::Vector2d> sewLine;
  // Indices into sewLine where the piece's corners are (where one edge ends and the next begins).
  std::vector<int> corners;
  std::vector<SewingNotch> notches;
  Eigen::Vector2d grainFrom = Eigen::Vector2d::Zero();  // the grainline, an arrow from → to
  Eigen::Vector2d grainTo = Eigen::Vector2d::UnitY();
  std::vector<std::vector<Eigen::Vector2d>> internalLines;  // open polylines (m): fold, darts
};

struct SewingPattern {
  std::string styleName = "scan2pattern";
  std::string creationDate;  // "2026-12-01"
  std::string sampleSize = "scan";
  std::vector<SewingPiece> pieces;
};

// What the writers check first: InputError, naming `writer`, the piece's index and name, when
// there is no piece, a sew line is not a simple counter-clockwise polygon of ≥ 3 points, a
// quantity is below 1, or a notch, the grainline or an internal line is not finite.
void checkSewingPattern(const SewingPattern& pattern, const std::string& writer);

}  // namespace s2p
