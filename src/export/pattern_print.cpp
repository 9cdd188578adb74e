#include "export/pattern_print.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <string>

#include "core/error.h"
#include "export/pattern_sheet.h"
#include "io/write_mesh.h"

namespace s2p {
namespace {

// === Sheet dimensions (mm)

constexpr double kMarginMm = 10;        // around the sheet's content
constexpr double kTitleWidthMm = 120;   // the title block beside the test square
constexpr double kHeaderGapMm = 15;     // between the header (square, title) and the pieces
constexpr double kPieceGapM = 0.03;     // between pieces (metres, as layoutPieces takes it)
constexpr double kNotchMm = 6;          // length of a notch, centred on the cut line
constexpr double kArrowMm = 6;          // grainline arrowheads
constexpr double kPtPerMm = 72 / 25.4;  // PDF user space
constexpr double kCrossMm = 5;          // half arm of an alignment cross

// Line widths (mm) and dash patterns.
constexpr double kCutWidth = 0.5;
constexpr double kThinWidth = 0.25;
constexpr std::array<double, 2> kSewDash{4, 2};
constexpr std::array<double, 4> kInternalDash{8, 2, 1, 2};
constexpr std::array<double, 2> kOverlapDash{3, 2};

using CairoPtr = std::unique_ptr<cairo_t, decltype(&cairo_destroy)>;
using SurfacePtr = std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)>;

cairo_status_t appendToString(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

Eigen::Vector2d minCorner(const Polygon2& polygon) {
  return std::accumulate(
      polygon.begin(), polygon.end(),
      Eigen::Vector2d::Constant(std::numeric_limits<double>::max()).eval(),
      [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.cwiseMin(b).eval(); });
}
Eigen::Vector2d maxCorner(const Polygon2& polygon) {
  return std::accumulate(
      polygon.begin(), polygon.end(),
      Eigen::Vector2d::Constant(std::numeric_limits<double>::lowest()).eval(),
      [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.cwiseMax(b).eval(); });
}

// "cut 1", "cut 2, mirrored".
std::string cutText(const SewingPiece& piece) {
  return fmt::format("cut {}{}", piece.quantity, piece.mirrored ? ", mirrored" : "");
}

// === Drawing helpers (user space: sheet millimetres, y down)

void setDash(cairo_t* cr, const double* dashes, int count) {
  cairo_set_dash(cr, dashes, count, 0);
}

void strokeLine(cairo_t* cr, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  cairo_move_to(cr, a.x(), a.y());
  cairo_line_to(cr, b.x(), b.y());
  cairo_stroke(cr);
}

void tracePolyline(cairo_t* cr, const PrintedPiece& at, const Polygon2& points, bool closed) {
  for (size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d q = at.toSheet(points[i]);
    if (i == 0)
      cairo_move_to(cr, q.x(), q.y());
    else
      cairo_line_to(cr, q.x(), q.y());
  }
  if (closed) cairo_close_path(cr);
}

struct TextLine {
  std::string text;
  double size = 4;  // font size (mm)
  bool bold = false;
};

void selectFont(cairo_t* cr, const TextLine& line, double scale) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         line.bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, line.size * scale);
}

double textWidth(cairo_t* cr, const TextLine& line, double scale) {
  selectFont(cr, line, scale);
  cairo_text_extents_t ext;
  cairo_text_extents(cr, line.text.c_str(), &ext);
  return ext.x_advance;
}

// Width and height (mm) of the lines set at `scale`, 1.3 line spacing.
Eigen::Vector2d blockSize(cairo_t* cr, const std::vector<TextLine>& lines, double scale) {
  Eigen::Vector2d size = Eigen::Vector2d::Zero();
  for (const TextLine& line : lines) {
    size.x() = std::max(size.x(), textWidth(cr, line, scale));
    size.y() += 1.3 * line.size * scale;
  }
  return size;
}

// The lines from `topLeft` down, centred on x = topLeft.x + width/2 when `centred`.
void showBlock(cairo_t* cr, const std::vector<TextLine>& lines, const Eigen::Vector2d& topLeft,
               double width, double scale, bool centred) {
  double y = topLeft.y();
  for (const TextLine& line : lines) {
    y += line.size * scale;
    const double w = textWidth(cr, line, scale);
    cairo_move_to(cr, centred ? topLeft.x() + 0.5 * (width - w) : topLeft.x(), y);
    cairo_show_text(cr, line.text.c_str());
    y += 0.3 * line.size * scale;
  }
}

// === The sheet

void drawGrainline(cairo_t* cr, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = b - a;
  if (d.norm() < 1e-6) return;
  strokeLine(cr, a, b);
  const Eigen::Vector2d u = d.normalized();
  const Eigen::Vector2d v(-u.y(), u.x());
  const double back = kArrowMm * std::cos(0.45), side = kArrowMm * std::sin(0.45);
  for (const auto& [tip, dir] : {std::pair{b, u}, std::pair{a, Eigen::Vector2d(-u)}}) {
    cairo_move_to(cr, (tip - back * dir + side * v).x(), (tip - back * dir + side * v).y());
    cairo_line_to(cr, tip.x(), tip.y());
    cairo_line_to(cr, (tip - back * dir - side * v).x(), (tip - back * dir - side * v).y());
    cairo_stroke(cr);
  }
}

void drawPiece(cairo_t* cr, const SewingPiece& piece, const PrintedPiece& at,
               double seamAllowance) {
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, kCutWidth);
  tracePolyline(cr, at, at.cutLine, true);
  cairo_stroke(cr);

  cairo_set_line_width(cr, kThinWidth);
  if (seamAllowance > 0) {  // with no allowance the cut line is the sew line, drawn once
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    setDash(cr, kSewDash.data(), kSewDash.size());
    tracePolyline(cr, at, piece.sewLine, true);
    cairo_stroke(cr);
  }
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.5);
  setDash(cr, kInternalDash.data(), kInternalDash.size());
  for (const Polygon2& line : piece.internalLines) {
    tracePolyline(cr, at, line, false);
    cairo_stroke(cr);
  }
  setDash(cr, nullptr, 0);

  cairo_set_source_rgb(cr, 0, 0, 0);
  for (const SewingNotch& notch : piece.notches) {
    const Eigen::Vector2d n = notch.normal.normalized();
    const Eigen::Vector2d onCut =
        rayToOutline(at.cutLine, notch.at, n, kSeamMiterLimit * seamAllowance);
    const Eigen::Vector2d q = at.toSheet(onCut), nSheet(n.x(), -n.y());
    strokeLine(cr, q - 0.5 * kNotchMm * nSheet, q + 0.5 * kNotchMm * nSheet);
  }

  cairo_set_line_width(cr, 0.4);
  drawGrainline(cr, at.toSheet(piece.grainFrom), at.toSheet(piece.grainTo));

  // The label where it is farthest from the outline and the grainline, shrunk to fit there.
  const LabelSpot& spot = at.label;
  const std::vector<TextLine> lines{
      {piece.name, 6, true}, {piece.garment, 4.5, false}, {cutText(piece), 4.5, false}};
  const Eigen::Vector2d natural = blockSize(cr, lines, 1);
  const double scale = std::clamp(1000 * spot.clearance / (0.5 * natural.norm() + 1e-9), 0.35, 1.0);
  const Eigen::Vector2d size = blockSize(cr, lines, scale);
  showBlock(cr, lines, at.toSheet(spot.at) - 0.5 * size, size.x(), scale, true);
}

void drawTestSquare(cairo_t* cr, const Eigen::Vector2d& corner, bool outline) {
  cairo_set_source_rgb(cr, 0, 0, 0);
  if (outline) {
    cairo_set_line_width(cr, kCutWidth);
    cairo_rectangle(cr, corner.x(), corner.y(), kTestSquareMm, kTestSquareMm);
    cairo_stroke(cr);
  }
  const std::vector<TextLine> lines{{"10 cm", 10, true},
                                    {"test square", 4.5, false},
                                    {"print at 100 % (actual size)", 3.5, false},
                                    {"and check it measures 10 cm", 3.5, false}};
  const Eigen::Vector2d size = blockSize(cr, lines, 1);
  showBlock(cr, lines, corner + 0.5 * (Eigen::Vector2d::Constant(kTestSquareMm) - size), size.x(),
            1, true);
}

void drawTitleBlock(cairo_t* cr, const Eigen::Vector2d& corner, const SewingPattern& pattern,
                    const PrintOptions& options) {
  int toCut = 0;
  for (const SewingPiece& piece : pattern.pieces) toCut += piece.quantity;
  const double allowanceMm = 1000 * options.seamAllowance;
  const std::vector<TextLine> lines{
      {pattern.styleName, 7, true},
      {"date: " + (pattern.creationDate.empty() ? "-" : pattern.creationDate), 4.5, false},
      {"units: millimetres, scale 1:1", 4.5, false},
      {"sample size: " + pattern.sampleSize, 4.5, false},
      {allowanceMm > 0
           ? fmt::format("seam allowance {:g} mm included (dashed: sew line)", allowanceMm)
           : std::string("no seam allowance: cut on the sew line"),
       4.5, false},
      {fmt::format("{} pieces, {} to cut", pattern.pieces.size(), toCut), 4.5, false},
      {"made by scan2pattern", 3.5, false}};
  const double inner = kTitleWidthMm - 10;
  const double scale = std::min(1.0, inner / blockSize(cr, lines, 1).x());
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, kThinWidth);
  cairo_rectangle(cr, corner.x(), corner.y(), kTitleWidthMm, kTestSquareMm);
  cairo_stroke(cr);
  showBlock(cr, lines, corner + Eigen::Vector2d(5, 5), inner, scale, false);
}

// Everything on the sheet; the SVG leaves the test square's outline to its own <rect>.
void drawSheet(cairo_t* cr, const SewingPattern& pattern, const PrintSheet& sheet,
               const PrintOptions& options, bool squareOutline) {
  for (size_t i = 0; i < pattern.pieces.size(); ++i)
    drawPiece(cr, pattern.pieces[i], sheet.pieces[i], options.seamAllowance);
  drawTestSquare(cr, sheet.testSquare, squareOutline);
  drawTitleBlock(cr, sheet.titleBlock, pattern, options);
}

// === Tiles

void drawCross(cairo_t* cr, const Eigen::Vector2d& c) {
  strokeLine(cr, c - Eigen::Vector2d(kCrossMm, 0), c + Eigen::Vector2d(kCrossMm, 0));
  strokeLine(cr, c - Eigen::Vector2d(0, kCrossMm), c + Eigen::Vector2d(0, kCrossMm));
  cairo_new_sub_path(cr);
  cairo_arc(cr, c.x(), c.y(), 0.4 * kCrossMm, 0, 2 * M_PI);
  cairo_stroke(cr);
}

// Alignment crosses in sheet coordinates, at the middle of every overlap strip (so each one is
// printed on both pages that share the strip, four at strip crossings).
void drawAlignmentCrosses(cairo_t* cr, const PageTiling& t) {
  const auto stripCentre = [&](int k, int axis) {  // between page k and k + 1 along the axis
    return t.origin(k + 1, k + 1)[axis] + 0.5 * t.overlap;
  };
  const auto along = [&](int k, int axis) {  // points along page k's extent on the axis
    const double o = t.origin(k, k)[axis], len = t.cell[axis];
    return std::array<double, 3>{o + 0.25 * len, o + 0.5 * len, o + 0.75 * len};
  };
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, kThinWidth);
  for (int c = 0; c + 1 < t.columns; ++c) {
    for (int r = 0; r < t.rows; ++r)
      for (double y : along(r, 1)) drawCross(cr, {stripCentre(c, 0), y});
    for (int r = 0; r + 1 < t.rows; ++r) drawCross(cr, {stripCentre(c, 0), stripCentre(r, 1)});
  }
  for (int r = 0; r + 1 < t.rows; ++r)
    for (int c = 0; c < t.columns; ++c)
      for (double x : along(c, 0)) drawCross(cr, {x, stripCentre(r, 1)});
}

// The frame of the printed cell, the dashed lines where the neighbours' pages end, and the
// page's number and instructions in the margins (page millimetres).
void drawTileFrame(cairo_t* cr, const PageTiling& t, int row, int column, int page, int pages,
                   const std::string& style) {
  const double m = t.margin;
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, kThinWidth);
  cairo_rectangle(cr, m, m, t.cell.x(), t.cell.y());
  cairo_stroke(cr);
  cairo_set_source_rgb(cr, 0.4, 0.4, 0.4);
  setDash(cr, kOverlapDash.data(), kOverlapDash.size());
  const Eigen::Vector2d lo(m, m), hi = lo + t.cell;
  if (column > 0) strokeLine(cr, {m + t.overlap, lo.y()}, {m + t.overlap, hi.y()});
  if (column + 1 < t.columns)
    strokeLine(cr, {hi.x() - t.overlap, lo.y()}, {hi.x() - t.overlap, hi.y()});
  if (row > 0) strokeLine(cr, {lo.x(), m + t.overlap}, {hi.x(), m + t.overlap});
  if (row + 1 < t.rows) strokeLine(cr, {lo.x(), hi.y() - t.overlap}, {hi.x(), hi.y() - t.overlap});
  setDash(cr, nullptr, 0);

  cairo_set_source_rgb(cr, 0, 0, 0);
  const TextLine number{
      fmt::format("{}: row {}, column {} (page {} of {})", style, row + 1, column + 1, page, pages),
      3.5, true};
  const TextLine help{
      "trim the left and top margins on the frame, lay the frame on the "
      "neighbours' dashed lines, crosses on crosses, and tape",
      2.5, false};
  const double helpScale = std::min(1.0, t.cell.x() / textWidth(cr, help, 1));
  showBlock(cr, {help}, {m, 0.5 * m - 1.5}, t.cell.x(), helpScale, true);
  showBlock(cr, {number}, {m, hi.y() + 0.5 * m - 2.5}, t.cell.x(), 1, true);
}

// cairo numbers its surfaces process-wide (id="surface55"): renumbered in order of appearance,
// so that a pattern gives the same bytes however many surfaces the process drew before.
std::string renumberSurfaceIds(const std::string& svg) {
  static const std::string kToken = "surface";
  std::map<std::string, int> number;
  std::string out;
  out.reserve(svg.size());
  std::size_t from = 0;
  for (std::size_t at = svg.find(kToken); at != std::string::npos; at = svg.find(kToken, at)) {
    std::size_t end = at + kToken.size();
    while (end < svg.size() && std::isdigit(static_cast<unsigned char>(svg[end]))) ++end;
    if (end == at + kToken.size()) {  // not followed by a number
      at = end;
      continue;
    }
    const auto [it, fresh] = number.try_emplace(svg.substr(at, end - at), number.size() + 1);
    out.append(svg, from, at - from).append(kToken).append(std::to_string(it->second));
    from = at = end;
  }
  return out.append(svg, from, std::string::npos);
}

void checkCairo(cairo_t* cr, cairo_surface_t* surface, const std::filesystem::path& path) {
  cairo_status_t status = cairo_status(cr);
  if (status == CAIRO_STATUS_SUCCESS) {
    cairo_surface_finish(surface);
    status = cairo_surface_status(surface);
  }
  if (status != CAIRO_STATUS_SUCCESS)
    throw IoError(fmt::format("{}: cairo cannot draw the pattern: {}", path.string(),
                              cairo_status_to_string(status)));
}

}  // namespace

Eigen::Vector2d paperSize(Paper paper) {
  return paper == Paper::A4 ? Eigen::Vector2d(210, 297) : Eigen::Vector2d(215.9, 279.4);
}

PageTiling tilePages(const Eigen::Vector2d& sheetSize, Paper paper) {
  PageTiling t;
  t.paper = paperSize(paper);
  t.cell = t.paper - Eigen::Vector2d::Constant(2 * t.margin);
  // (n − 1)·step + cell ≥ size, i.e. n ≥ (size − overlap) / step.
  const auto count = [&](double size, double cell) {
    return std::max(1, static_cast<int>(std::ceil((size - t.overlap) / (cell - t.overlap) - 1e-9)));
  };
  t.columns = count(sheetSize.x(), t.cell.x());
  t.rows = count(sheetSize.y(), t.cell.y());
  return t;
}

PrintSheet layoutPrintSheet(const SewingPattern& pattern, const PrintOptions& options) {
  checkSewingPattern(pattern, "pattern print");
  if (!(options.seamAllowance >= 0) || !std::isfinite(options.seamAllowance))
    throw InputError(fmt::format("pattern print: the seam allowance must be ≥ 0 m, got {}",
                                 options.seamAllowance));
  PrintSheet sheet;
  std::vector<SheetPiece> boxes;
  double widest = 0;
  for (const SewingPiece& piece : pattern.pieces) {
    PrintedPiece printed;
    printed.cutLine = offsetOutline(piece.sewLine, options.seamAllowance);
    printed.label = labelSpot(piece.sewLine, {{piece.grainFrom, piece.grainTo}});
    SheetPiece box;
    box.outlines.emplace_back(static_cast<int>(printed.cutLine.size()), 2);
    for (size_t k = 0; k < printed.cutLine.size(); ++k)
      box.outlines.back().row(static_cast<int>(k)) = printed.cutLine[k].transpose();
    widest = std::max(widest, (maxCorner(printed.cutLine) - minCorner(printed.cutLine)).x());
    sheet.pieces.push_back(std::move(printed));
    boxes.push_back(std::move(box));
  }
  // Header: the test square at the top-left (so that the first tile page shows it whole), the
  // title block beside it; the pieces in rows below.
  sheet.testSquare = Eigen::Vector2d::Constant(kMarginMm);
  sheet.titleBlock = sheet.testSquare + Eigen::Vector2d(kTestSquareMm + kMarginMm, 0);
  const double headerWidth = 2 * kMarginMm + kTestSquareMm + kTitleWidthMm;
  const double top = kMarginMm + kTestSquareMm + kHeaderGapMm;
  const double rowWidth = std::max({options.sheetWidth, widest, headerWidth / 1000});
  const Eigen::MatrixX2d offset = layoutPieces(boxes, rowWidth, kPieceGapM);
  Eigen::Vector2d extent(headerWidth, top);
  for (size_t i = 0; i < sheet.pieces.size(); ++i) {
    PrintedPiece& p = sheet.pieces[i];
    const Eigen::Vector2d t = offset.row(static_cast<int>(i)).transpose();
    p.origin = Eigen::Vector2d(kMarginMm + 1000 * t.x(), top - 1000 * t.y());
    const Polygon2& cut = p.cutLine;
    extent = extent.cwiseMax(p.toSheet(Eigen::Vector2d(maxCorner(cut).x(), minCorner(cut).y())) +
                             Eigen::Vector2d::Constant(kMarginMm));
  }
  sheet.size = extent;
  return sheet;
}

void writePatternSvg(const std::filesystem::path& path, const SewingPattern& pattern,
                     const PrintOptions& options) {
  const PrintSheet sheet = layoutPrintSheet(pattern, options);
  std::string svg;
  {
    // With millimetres as the document unit, cairo writes width="…mm" and a viewBox of the same
    // numbers, so one user unit is one millimetre.
    SurfacePtr surface(
        cairo_svg_surface_create_for_stream(appendToString, &svg, sheet.size.x(), sheet.size.y()),
        cairo_surface_destroy);
    cairo_svg_surface_set_document_unit(surface.get(), CAIRO_SVG_UNIT_MM);
    CairoPtr cr(cairo_create(surface.get()), cairo_destroy);
    drawSheet(cr.get(), pattern, sheet, options, false);
    checkCairo(cr.get(), surface.get(), path);
  }
  // cairo's SVG surface cannot name an element, so the test square's outline is our own <rect>,
  // for tools (and the tests) to find and measure.
  const std::size_t end = svg.rfind("</svg>");
  if (end == std::string::npos)
    throw IoError(path.string() + ": cairo wrote an SVG without its closing </svg>");
  svg.insert(end, fmt::format("<rect id=\"test-square\" x=\"{:g}\" y=\"{:g}\" width=\"{:g}\" "
                              "height=\"{:g}\" style=\"fill:none;stroke:rgb(0%,0%,0%);"
                              "stroke-width:{:g};\"/>\n",
                              sheet.testSquare.x(), sheet.testSquare.y(), kTestSquareMm,
                              kTestSquareMm, kCutWidth));
  writeFileAtomically(path, renumberSurfaceIds(svg));
}

void writePatternPdf(const std::filesystem::path& path, const SewingPattern& pattern,
                     const PrintOptions& options) {
  const PrintSheet sheet = layoutPrintSheet(pattern, options);
  const PageTiling tiles = tilePages(sheet.size, options.paper);
  const int pages = 1 + tiles.rows * tiles.columns;
  std::string pdf;
  {
    SurfacePtr surface(
        cairo_pdf_surface_create_for_stream(appendToString, &pdf, kPtPerMm * sheet.size.x(),
                                            kPtPerMm * sheet.size.y()),
        cairo_surface_destroy);
    cairo_pdf_surface_set_metadata(surface.get(), CAIRO_PDF_METADATA_TITLE,
                                   pattern.styleName.c_str());
    cairo_pdf_surface_set_metadata(surface.get(), CAIRO_PDF_METADATA_CREATOR, "scan2pattern");
    if (!pattern.creationDate.empty())
      cairo_pdf_surface_set_metadata(surface.get(), CAIRO_PDF_METADATA_CREATE_DATE,
                                     pattern.creationDate.c_str());
    CairoPtr owner(cairo_create(surface.get()), cairo_destroy);
    cairo_t* cr = owner.get();
    cairo_scale(cr, kPtPerMm, kPtPerMm);

    drawSheet(cr, pattern, sheet, options, true);
    cairo_show_page(cr);

    cairo_pdf_surface_set_size(surface.get(), kPtPerMm * tiles.paper.x(),
                               kPtPerMm * tiles.paper.y());
    for (int r = 0; r < tiles.rows; ++r)
      for (int c = 0; c < tiles.columns; ++c) {
        cairo_save(cr);
        cairo_rectangle(cr, tiles.margin, tiles.margin, tiles.cell.x(), tiles.cell.y());
        cairo_clip(cr);
        const Eigen::Vector2d shift = Eigen::Vector2d::Constant(tiles.margin) - tiles.origin(r, c);
        cairo_translate(cr, shift.x(), shift.y());
        drawSheet(cr, pattern, sheet, options, true);
        drawAlignmentCrosses(cr, tiles);
        cairo_restore(cr);
        drawTileFrame(cr, tiles, r, c, 2 + r * tiles.columns + c, pages, pattern.styleName);
        cairo_show_page(cr);
      }
    checkCairo(cr, surface.get(), path);
  }
  writeFileAtomically(path, pdf);
}

}  // namespace s2p
