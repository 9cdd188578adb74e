// Drawings of flat pattern pieces with cairo: pieces laid out side by side on a sheet, each
// filled per triangle (e.g. by strain) and outlined, with a colour legend. Plain 2D data in,
// so the drawing knows nothing of how the pattern was made.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "export/preview.h"

namespace s2p {

struct SheetPiece {
  std::string label;               // drawn at the piece's centre
  Eigen::MatrixX2d V;              // #V×2, metres, in the piece's own frame
  Eigen::MatrixX3i F;              // #F×3 (may be empty: outline only)
  std::vector<Rgb> faceColour;     // #F (or empty: light grey)
  std::vector<Eigen::MatrixX2d> outlines;  // closed polylines, metres, the piece's frame
};

// A colour scale for the legend: values mapped linearly from 0 to maxValue over `colours`.
struct SheetLegend {
  std::string title;                 // e.g. "max(warp, weft) strain"
  double maxValue = 0.1;
  std::vector<Rgb> colours;          // from 0 to maxValue
  std::string unit = "%";            // the labels show value × scale with this unit
  double scale = 100;
};

// Lays the pieces out in rows (no overlaps, a 3 cm gap), returns each piece's translation
// (metres) in the sheet: row i of the result is piece i's offset.
Eigen::MatrixX2d layoutPieces(const std::vector<SheetPiece>& pieces, double rowWidth = 2.0,
                              double gap = 0.03);

// PNG of the laid-out pieces at `pixelsPerMetre` (capped so the image stays below 8000 px),
// with the legend at the bottom (left blank when the legend has no colours). Written atomically; IoError when the folder is not writable.
void writeSheetPng(const std::filesystem::path& path, const std::vector<SheetPiece>& pieces,
                   const SheetLegend& legend, double pixelsPerMetre = 400);

// Blue (0) → green → yellow → red (max): the colours of a strain legend.
std::vector<Rgb> strainColours();
Rgb colourAt(const std::vector<Rgb>& scale, double fraction);  // fraction clamped to [0, 1]

}  // namespace s2p
