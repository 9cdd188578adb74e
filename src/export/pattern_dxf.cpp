// Written with dxflib's writer: in R12 mode (DL_Codes::AC1009) it emits exactly the sections we
// ask for, so the file has what the strictest AAMA importers (Gerber's, see F-patterns.md (b))
// accept: a HEADER with $ACADVER only, no TABLES section (the numbered layers are created by the
// entities that use them), no *MODEL_SPACE / *PAPER_SPACE blocks, one BLOCK per piece and the
// INSERTs and style text in ENTITIES. dxflib opens the file itself, so it writes the temporary
// file of writeFileAtomically. Text is made 7-bit ASCII here: dxflib writes bytes as given.
#include "export/pattern_dxf.h"

#include <dl_dxf.h>
#include <dl_writer_ascii.h>
#include <fmt/format.h>

#include <cctype>
#include <cmath>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "core/error.h"
#include "export/piece_outline.h"
#include "io/write_mesh.h"

namespace s2p {
namespace {

constexpr double kTextHeightMm = 2.5;  // AAMA's usual text height
constexpr double kNotchMm = 6;         // slit length, from the cut line inward
constexpr double kPieceGapMm = 50;     // between the inserted pieces

// 7-bit printable ASCII: every non-ASCII UTF-8 character becomes '?', control characters ' '.
std::string asciiText(const std::string& text) {
  std::string out;
  for (const char ch : text) {
    const auto byte = static_cast<unsigned char>(ch);
    if (byte >= 0x80) {
      if (byte >= 0xC0) out += '?';  // a lead byte; continuation bytes (0x80–0xBF) are dropped
    } else {
      out += byte < 0x20 || byte == 0x7F ? ' ' : ch;
    }
  }
  return out;
}

// A block name R12 readers take: letters, digits, '_' and '-' only, unique in the file.
std::string blockName(const SewingPiece& piece, std::set<std::string>& taken) {
  std::string name = piece.garment.empty() ? piece.name : piece.garment + "_" + piece.name;
  for (char& ch : name)
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '-') ch = '_';
  if (name.empty()) name = "piece";
  std::string unique = name;
  for (int k = 2; taken.count(unique); ++k) unique = fmt::format("{}_{}", name, k);
  taken.insert(unique);
  return unique;
}

Polygon2 toMillimetres(const Polygon2& points) {
  Polygon2 out;
  out.reserve(points.size());
  for (const Eigen::Vector2d& p : points) out.push_back(1000 * p);
  return out;
}

DL_Attributes onLayer(const char* layer) {
  return DL_Attributes(layer, 256 /* BYLAYER */, -1, "BYLAYER", 1.0);
}

void writePolyline(DL_Dxf& dxf, DL_WriterA& dw, const char* layer, const Polygon2& points,
                   bool closed) {
  dxf.writePolyline(dw, DL_PolylineData(static_cast<int>(points.size()), 0, 0, closed ? 1 : 0),
                    onLayer(layer));
  for (const Eigen::Vector2d& p : points) dxf.writeVertex(dw, DL_VertexData(p.x(), p.y(), 0, 0));
  dxf.writePolylineEnd(dw);
}

void writeLine(DL_Dxf& dxf, DL_WriterA& dw, const char* layer, const Eigen::Vector2d& a,
               const Eigen::Vector2d& b) {
  dxf.writeLine(dw, DL_LineData(a.x(), a.y(), 0, b.x(), b.y(), 0), onLayer(layer));
}

// Lines of text on layer 1 from `at` downwards, left-aligned.
void writeTexts(DL_Dxf& dxf, DL_WriterA& dw, const std::vector<std::string>& lines,
                const Eigen::Vector2d& at) {
  for (size_t i = 0; i < lines.size(); ++i) {
    const double y = at.y() - 1.6 * kTextHeightMm * static_cast<double>(i);
    dxf.writeText(dw,
                  DL_TextData(at.x(), y, 0, at.x(), y, 0, kTextHeightMm, 1, 0, 0, 0,
                              asciiText(lines[i]), "STANDARD", 0),
                  onLayer("1"));
  }
}

// One piece's block content, in the piece's frame (mm).
void writePieceBlock(DL_Dxf& dxf, DL_WriterA& dw, const SewingPiece& piece,
                     const std::string& sampleSize, const Polygon2& sew, const Polygon2& cut,
                     double allowanceMm) {
  writePolyline(dxf, dw, "1", cut, true);
  const LabelSpot spot = labelSpot(sew, {{1000 * piece.grainFrom, 1000 * piece.grainTo}});
  writeTexts(dxf, dw,
             {"Piece Name: " + piece.name, fmt::format("Quantity: {}", piece.quantity),
              "Size: " + sampleSize, "Category: " + piece.garment},
             spot.at);
  writePolyline(dxf, dw, "14", sew, true);
  for (const SewingNotch& notch : piece.notches) {
    const Eigen::Vector2d n = notch.normal.normalized();
    const Eigen::Vector2d onCut =
        rayToOutline(cut, 1000 * notch.at, n, kSeamMiterLimit * allowanceMm);
    writeLine(dxf, dw, "4", onCut, onCut - kNotchMm * n);
  }
  writeLine(dxf, dw, "7", 1000 * piece.grainFrom, 1000 * piece.grainTo);
  for (const Polygon2& line : piece.internalLines)
    writePolyline(dxf, dw, "8", toMillimetres(line), false);
}

}  // namespace

void writePatternDxf(const std::filesystem::path& path, const SewingPattern& pattern,
                     const DxfOptions& options) {
  checkSewingPattern(pattern, "pattern DXF");
  if (!(options.seamAllowance >= 0) || !std::isfinite(options.seamAllowance))
    throw InputError(fmt::format("pattern DXF: the seam allowance must be ≥ 0 m, got {}",
                                 options.seamAllowance));
  const double allowanceMm = 1000 * options.seamAllowance;
  std::vector<Polygon2> sew, cut;
  for (const SewingPiece& piece : pattern.pieces) {
    sew.push_back(toMillimetres(piece.sewLine));
    cut.push_back(offsetOutline(sew.back(), allowanceMm));
  }
  std::set<std::string> taken;
  std::vector<std::string> names;
  for (const SewingPiece& piece : pattern.pieces) names.push_back(blockName(piece, taken));

  writeFileAtomically(path, [&](const std::filesystem::path& tmp) {
    DL_Dxf dxf;
    std::unique_ptr<DL_WriterA> dw(dxf.out(tmp.c_str(), DL_Codes::AC1009));
    if (!dw)
      throw IoError(
          fmt::format("{}: cannot create the file; check the folder exists and is "
                      "writable",
                      path.string()));
    dxf.writeHeader(*dw);
    dw->sectionEnd();

    dw->sectionBlocks();
    for (size_t i = 0; i < pattern.pieces.size(); ++i) {
      dxf.writeBlock(*dw, DL_BlockData(names[i], 0, 0, 0, 0));
      writePieceBlock(dxf, *dw, pattern.pieces[i], pattern.sampleSize, sew[i], cut[i], allowanceMm);
      dxf.writeEndBlock(*dw, names[i]);
    }
    dw->sectionEnd();

    // The pieces side by side along +x, their lowest points on y = 0, the style text below.
    dw->sectionEntities();
    double x = 0;
    for (size_t i = 0; i < pattern.pieces.size(); ++i) {
      Eigen::Vector2d lo = cut[i].front(), hi = lo;
      for (const Eigen::Vector2d& p : cut[i]) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
      dxf.writeInsert(*dw, DL_InsertData(names[i], x - lo.x(), -lo.y(), 0, 1, 1, 1, 0, 1, 1, 0, 0),
                      onLayer("1"));
      x += hi.x() - lo.x() + kPieceGapMm;
    }
    writeTexts(dxf, *dw,
               {"Style Name: " + pattern.styleName, "Creation Date: " + pattern.creationDate,
                "Units: METRIC", "Sample Size: " + pattern.sampleSize},
               Eigen::Vector2d(0, -10));
    dw->sectionEnd();
    dw->dxfEOF();
    const bool failed = dw->openFailed();  // the stream's failbit is sticky: any write failed
    dw->close();
    if (failed || dw->openFailed())
      throw IoError(fmt::format("{}: writing failed (disk full?)", path.string()));
  });
}

}  // namespace s2p
