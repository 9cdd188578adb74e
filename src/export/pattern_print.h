// The printable pattern: pattern.svg and pattern.pdf at 1:1 (cairo). Each piece shows its cut
// line (the sew line plus the seam allowance), its sew line dashed, the grainline arrow, notches
// across the cut line, its internal lines and a label (name, garment, "cut 1" / "cut 2,
// mirrored"). The sheet adds a 10 cm test square and a title block (style, date, units). The
// PDF's first page holds the whole sheet at 1:1 (for a plotter or a copy shop); the pages after
// it tile the sheet on A4 or US Letter for home printing, with overlap strips, alignment crosses
// and "row r, column c (page n of N)".
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "export/piece_outline.h"
#include "export/sewing_pattern.h"

namespace s2p {

enum class Paper { A4, Letter };

struct PrintOptions {
  double seamAllowance = 0.01;  // metres, ≥ 0 (0: the cut line is the sew line)
  Paper paper = Paper::A4;      // the PDF's tile pages
  double sheetWidth =
      1.5;  // metres: pieces are laid out in rows at most this wide (or the widest piece)
};

// === The sheet both files draw: millimetres, x right, y down from the sheet's top-left corner

constexpr double kTestSquareMm = 100;  // the print-scale test square's side

struct PrintedPiece {
  Polygon2 cutLine;  // metres, the piece's own frame (the sew line offset by the allowance)
  LabelSpot label;   // metres, the piece's frame: where its label reads best (found once)
  // Where the piece's frame origin lands on the sheet (mm): a piece point p (m, y up) is drawn at
  // origin + 1000·(p.x, −p.y).
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();
  Eigen::Vector2d toSheet(const Eigen::Vector2d& p) const {
    return origin + 1000.0 * Eigen::Vector2d(p.x(), -p.y());
  }
};

struct PrintSheet {
  Eigen::Vector2d size = Eigen::Vector2d::Zero();        // width, height (mm)
  std::vector<PrintedPiece> pieces;                      // one per SewingPattern::pieces
  Eigen::Vector2d testSquare = Eigen::Vector2d::Zero();  // its top-left corner (mm)
  Eigen::Vector2d titleBlock = Eigen::Vector2d::Zero();  // its top-left corner (mm)
};

// Cut lines and a layout without overlaps: the test square and the title block along the top,
// the pieces below in rows. InputError for an empty pattern, a degenerate piece or a negative
// allowance.
PrintSheet layoutPrintSheet(const SewingPattern& pattern, const PrintOptions& options);

// === Tiling the sheet on pages

// Page (r, c) (from 0) prints the sheet's region origin(r, c) + [0, cell] on the paper inside
// `margin`; neighbouring regions share an `overlap` strip, so the pages together cover the sheet.
struct PageTiling {
  Eigen::Vector2d paper = Eigen::Vector2d::Zero();  // page width, height (mm)
  double margin = 10;                               // unprinted border of each page (mm)
  double overlap = 10;                              // strip printed on both neighbours (mm)
  Eigen::Vector2d cell = Eigen::Vector2d::Zero();   // paper − 2·margin (mm)
  int rows = 1, columns = 1;
  Eigen::Vector2d origin(int row, int column) const {
    return {column * (cell.x() - overlap), row * (cell.y() - overlap)};
  }
};

Eigen::Vector2d paperSize(Paper paper);  // mm: A4 210×297, US Letter 215.9×279.4
PageTiling tilePages(const Eigen::Vector2d& sheetSize, Paper paper);

// === Files (written atomically; IoError when the folder cannot be written, nothing left behind)

// SVG whose width and height are in mm with a viewBox in mm, so it prints at 1:1. The test
// square is the element <rect id="test-square">.
void writePatternSvg(const std::filesystem::path& path, const SewingPattern& pattern,
                     const PrintOptions& options = {});
// PDF: page 1 the whole sheet (page size = sheet size, 72/25.4 pt per mm), then the tile pages.
// The document's creation date is the pattern's, so the same pattern gives the same bytes.
void writePatternPdf(const std::filesystem::path& path, const SewingPattern& pattern,
                     const PrintOptions& options = {});

}  // namespace s2p
