#include "export/pattern_sheet.h"

#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "io/write_mesh.h"

namespace s2p {

namespace {

struct Box {
  Eigen::Vector2d lo, hi;
};

// A piece's label at the centre of its box (corners `a`, `b` in pixels), one word a line, in a
// font small enough (16 px at most, 8 at least) for the widest line to fit 90 % of the box's
// width, so that labels of pieces side by side do not run into each other.
void drawLabel(cairo_t* cr, const std::string& label, const Eigen::Vector2d& a,
               const Eigen::Vector2d& b) {
  std::vector<std::string> lines;
  std::istringstream words(label);
  for (std::string w; words >> w;) lines.push_back(w);
  if (lines.empty()) return;
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
  constexpr double kMaxSize = 16, kMinSize = 8;
  cairo_set_font_size(cr, kMaxSize);
  double widest = 0;
  for (const std::string& l : lines) {
    cairo_text_extents_t ext;
    cairo_text_extents(cr, l.c_str(), &ext);
    widest = std::max(widest, ext.x_advance);
  }
  const double room = 0.9 * std::abs(b.x() - a.x());
  const double size =
      widest > room ? std::max(kMinSize, kMaxSize * room / widest) : kMaxSize;
  cairo_set_font_size(cr, size);
  const Eigen::Vector2d c = 0.5 * (a + b);
  const double lineHeight = 1.2 * size;
  double y = c.y() - 0.5 * lineHeight * (static_cast<double>(lines.size()) - 1) + 0.35 * size;
  for (const std::string& l : lines) {
    cairo_text_extents_t ext;
    cairo_text_extents(cr, l.c_str(), &ext);
    cairo_move_to(cr, c.x() - ext.x_advance / 2, y);
    cairo_show_text(cr, l.c_str());
    y += lineHeight;
  }
}

Box boxOf(const SheetPiece& p) {
  Box b{Eigen::Vector2d::Constant(1e30), Eigen::Vector2d::Constant(-1e30)};
  const auto add = [&](const Eigen::MatrixX2d& P) {
    for (int i = 0; i < P.rows(); ++i) {
      b.lo = b.lo.cwiseMin(P.row(i).transpose());
      b.hi = b.hi.cwiseMax(P.row(i).transpose());
    }
  };
  add(p.V);
  for (const auto& o : p.outlines) add(o);
  if (b.lo.x() > b.hi.x()) b.lo = b.hi = Eigen::Vector2d::Zero();
  return b;
}

cairo_status_t appendToString(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

void setColour(cairo_t* cr, const Rgb& c) { cairo_set_source_rgb(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0); }

}  // namespace

std::vector<Rgb> strainColours() {
  return {{40, 70, 200}, {40, 170, 90}, {240, 210, 40}, {220, 40, 30}};
}

Rgb colourAt(const std::vector<Rgb>& scale, double fraction) {
  if (scale.empty()) return {200, 200, 200};
  if (scale.size() == 1) return scale[0];
  const double t = std::clamp(fraction, 0.0, 1.0) * static_cast<double>(scale.size() - 1);
  const int i = std::min(static_cast<int>(t), static_cast<int>(scale.size()) - 2);
  const double u = t - i;
  const auto mix = [&](std::uint8_t a, std::uint8_t b) {
    return static_cast<std::uint8_t>(std::lround((1 - u) * a + u * b));
  };
  return {mix(scale[i].r, scale[i + 1].r), mix(scale[i].g, scale[i + 1].g), mix(scale[i].b, scale[i + 1].b)};
}

Eigen::MatrixX2d layoutPieces(const std::vector<SheetPiece>& pieces, double rowWidth, double gap) {
  Eigen::MatrixX2d offset(static_cast<int>(pieces.size()), 2);
  double x = 0, y = 0, rowHeight = 0;
  for (size_t i = 0; i < pieces.size(); ++i) {
    const Box b = boxOf(pieces[i]);
    const Eigen::Vector2d size = b.hi - b.lo;
    if (x > 0 && x + size.x() > rowWidth) {
      x = 0;
      y -= rowHeight + gap;
      rowHeight = 0;
    }
    // The piece's top-left corner goes to (x, y).
    offset.row(static_cast<int>(i)) << x - b.lo.x(), y - b.hi.y();
    x += size.x() + gap;
    rowHeight = std::max(rowHeight, size.y());
  }
  return offset;
}

void writeSheetPng(const std::filesystem::path& path, const std::vector<SheetPiece>& pieces,
                   const SheetLegend& legend, double pixelsPerMetre) {
  const Eigen::MatrixX2d offset = layoutPieces(pieces);
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e30), hi = Eigen::Vector2d::Constant(-1e30);
  for (size_t i = 0; i < pieces.size(); ++i) {
    const Box b = boxOf(pieces[i]);
    lo = lo.cwiseMin(b.lo + offset.row(static_cast<int>(i)).transpose());
    hi = hi.cwiseMax(b.hi + offset.row(static_cast<int>(i)).transpose());
  }
  if (pieces.empty()) lo = hi = Eigen::Vector2d::Zero();
  const double margin = 0.05;
  const Eigen::Vector2d size = hi - lo + Eigen::Vector2d::Constant(2 * margin);
  double ppm = pixelsPerMetre;
  ppm = std::min(ppm, 8000.0 / std::max(size.x(), size.y()));
  const int legendPx = 70;
  const int w = std::max(200, static_cast<int>(std::ceil(size.x() * ppm)));
  const int h = static_cast<int>(std::ceil(size.y() * ppm)) + legendPx;
  std::unique_ptr<cairo_surface_t, decltype(&cairo_surface_destroy)> surface(
      cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h), cairo_surface_destroy);
  std::unique_ptr<cairo_t, decltype(&cairo_destroy)> owner(cairo_create(surface.get()), cairo_destroy);
  cairo_t* cr = owner.get();
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  // Sheet metres → pixels (y up on the sheet, down in the image).
  const auto px = [&](const Eigen::Vector2d& p) {
    return Eigen::Vector2d((p.x() - lo.x() + margin) * ppm, (hi.y() + margin - p.y()) * ppm);
  };
  for (size_t i = 0; i < pieces.size(); ++i) {
    const SheetPiece& piece = pieces[i];
    const Eigen::Vector2d off = offset.row(static_cast<int>(i)).transpose();
    // Faces filled without antialiasing: pixel-centre coverage tiles adjacent triangles with no
    // gap and no seam, so no stroke is needed to hide one (a fill and a stroke per face took a
    // 50k scan's two sheets 1.3 s). The outlines drawn over them are antialiased.
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_NONE);
    for (int f = 0; f < piece.F.rows(); ++f) {
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d q = px(piece.V.row(piece.F(f, k)).transpose() + off);
        if (k == 0) cairo_move_to(cr, q.x(), q.y());
        else cairo_line_to(cr, q.x(), q.y());
      }
      cairo_close_path(cr);
      setColour(cr, f < static_cast<int>(piece.faceColour.size()) ? piece.faceColour[f] : Rgb{220, 220, 220});
      cairo_fill(cr);
    }
    cairo_set_antialias(cr, CAIRO_ANTIALIAS_DEFAULT);
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 2);
    for (const Eigen::MatrixX2d& o : piece.outlines) {
      for (int k = 0; k < o.rows(); ++k) {
        const Eigen::Vector2d q = px(o.row(k).transpose() + off);
        if (k == 0) cairo_move_to(cr, q.x(), q.y());
        else cairo_line_to(cr, q.x(), q.y());
      }
      cairo_close_path(cr);
      cairo_stroke(cr);
    }
    const Box b = boxOf(piece);
    drawLabel(cr, piece.label, px(b.lo + off), px(b.hi + off));
  }
  // Legend: a colour bar with its ends labelled (none without colours).
  const double y0 = h - legendPx + 15, barW = std::min(400, w - 40);
  if (!legend.colours.empty()) {
  for (int i = 0; i < static_cast<int>(barW); ++i) {
    setColour(cr, colourAt(legend.colours, i / barW));
    cairo_rectangle(cr, 20 + i, y0, 1, 18);
    cairo_fill(cr);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_font_size(cr, 13);
  cairo_move_to(cr, 20, y0 + 36);
  cairo_show_text(cr, "0");
  const std::string maxText = fmt::format("≥ {:g} {}", legend.maxValue * legend.scale, legend.unit);
  cairo_move_to(cr, 20 + barW - 40, y0 + 36);
  cairo_show_text(cr, maxText.c_str());
  cairo_move_to(cr, 40 + barW, y0 + 14);
  cairo_show_text(cr, legend.title.c_str());
  }
  std::string bytes;
  if (cairo_surface_write_to_png_stream(surface.get(), appendToString, &bytes) != CAIRO_STATUS_SUCCESS)
    throw IoError(fmt::format("cannot encode {} as PNG", path.string()));
  writeFileAtomically(path, bytes);
}

}  // namespace s2p
