#include "export/pattern_print.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <regex>

#include "core/error.h"
#include "pattern_fixtures.h"
#include "test_support.h"

namespace s2p {
namespace {

constexpr double kPtPerMm = 72 / 25.4;

// The value of attribute `name` of the first element matching `element` (e.g. "<svg ").
std::string attribute(const std::string& xml, const std::string& element, const std::string& name) {
  const std::size_t at = xml.find(element);
  if (at == std::string::npos) return {};
  const std::string tag = xml.substr(at, xml.find('>', at) - at);
  std::smatch m;
  if (!std::regex_search(tag, m, std::regex("\\s" + name + "=\"([^\"]*)\""))) return {};
  return m[1];
}

std::vector<Eigen::Vector2d> mediaBoxes(const std::string& pdf) {
  std::vector<Eigen::Vector2d> boxes;
  const std::regex box(
      "/MediaBox\\s*\\[\\s*([-\\d.]+)\\s+([-\\d.]+)\\s+([-\\d.]+)\\s+([-\\d.]+)\\s*\\]");
  for (auto it = std::sregex_iterator(pdf.begin(), pdf.end(), box); it != std::sregex_iterator();
       ++it)
    boxes.emplace_back(std::stod((*it)[3]) - std::stod((*it)[1]),
                       std::stod((*it)[4]) - std::stod((*it)[2]));
  return boxes;
}

bool folderIsEmpty(const std::filesystem::path& dir) {
  return std::filesystem::directory_iterator(dir) == std::filesystem::directory_iterator();
}

TEST(PatternPrint, SvgIsInMillimetresAtOneToOne) {
  test::TempDir dir;
  const SewingPattern pattern = test::twoPiecePattern();
  writePatternSvg(dir / "pattern.svg", pattern);
  const std::string svg = test::readFile(dir / "pattern.svg");
  const PrintSheet sheet = layoutPrintSheet(pattern, {});
  const std::string width = attribute(svg, "<svg ", "width");
  const std::string height = attribute(svg, "<svg ", "height");
  ASSERT_EQ(width.substr(width.size() - 2), "mm");
  ASSERT_EQ(height.substr(height.size() - 2), "mm");
  EXPECT_NEAR(std::stod(width), sheet.size.x(), 1e-3);
  EXPECT_NEAR(std::stod(height), sheet.size.y(), 1e-3);
  // One user unit is one millimetre: the viewBox spans the same numbers.
  std::istringstream viewBox(attribute(svg, "<svg ", "viewBox"));
  double x0, y0, w, h;
  viewBox >> x0 >> y0 >> w >> h;
  EXPECT_EQ(x0, 0);
  EXPECT_EQ(y0, 0);
  EXPECT_NEAR(w, std::stod(width), 1e-6);
  EXPECT_NEAR(h, std::stod(height), 1e-6);
  // The sheet holds the 22 × 32 cm front and the 32 × 32 cm sleeve below a 10 cm header.
  EXPECT_GT(sheet.size.x(), 220 + 320);
  EXPECT_GT(sheet.size.y(), 100 + 320);
}

TEST(PatternPrint, TestSquareMeasures100mmInTheSvg) {
  test::TempDir dir;
  writePatternSvg(dir / "pattern.svg", test::twoPiecePattern());
  const std::string svg = test::readFile(dir / "pattern.svg");
  const double mmPerUnit = std::stod(attribute(svg, "<svg ", "width")) / [&] {
    std::istringstream v(attribute(svg, "<svg ", "viewBox"));
    double a, b, w;
    v >> a >> b >> w;
    return w;
  }();
  const std::string square = "<rect id=\"test-square\"";
  ASSERT_NE(svg.find(square), std::string::npos);
  EXPECT_NEAR(std::stod(attribute(svg, square, "width")) * mmPerUnit, 100, 1e-9);
  EXPECT_NEAR(std::stod(attribute(svg, square, "height")) * mmPerUnit, 100, 1e-9);
  EXPECT_GE(std::stod(attribute(svg, square, "x")), 0);
  EXPECT_GE(std::stod(attribute(svg, square, "y")), 0);
}

TEST(PatternPrint, PdfHasTheWholeSheetThenA4Tiles) {
  test::TempDir dir;
  const SewingPattern pattern = test::twoPiecePattern();
  writePatternPdf(dir / "pattern.pdf", pattern);
  const std::string pdf = test::readFile(dir / "pattern.pdf");
  ASSERT_EQ(pdf.substr(0, 5), "%PDF-");
  const PrintSheet sheet = layoutPrintSheet(pattern, {});
  const PageTiling tiles = tilePages(sheet.size, Paper::A4);
  const std::vector<Eigen::Vector2d> boxes = mediaBoxes(pdf);
  ASSERT_EQ(boxes.size(), static_cast<size_t>(1 + tiles.rows * tiles.columns));
  ASSERT_GT(boxes.size(), 2u);  // a sheet over half a metre wide needs several A4 pages
  EXPECT_NEAR(boxes[0].x(), sheet.size.x() * kPtPerMm, 0.01);
  EXPECT_NEAR(boxes[0].y(), sheet.size.y() * kPtPerMm, 0.01);
  for (size_t i = 1; i < boxes.size(); ++i) {
    EXPECT_NEAR(boxes[i].x(), 595.28, 0.01);
    EXPECT_NEAR(boxes[i].y(), 841.89, 0.01);
  }
}

TEST(PatternPrint, LetterTilesAre612By792pt) {
  test::TempDir dir;
  writePatternPdf(dir / "pattern.pdf", test::twoPiecePattern(), {.paper = Paper::Letter});
  const std::vector<Eigen::Vector2d> boxes = mediaBoxes(test::readFile(dir / "pattern.pdf"));
  ASSERT_GT(boxes.size(), 2u);
  for (size_t i = 1; i < boxes.size(); ++i) {
    EXPECT_NEAR(boxes[i].x(), 612, 0.01);
    EXPECT_NEAR(boxes[i].y(), 792, 0.01);
  }
}

TEST(PatternPrint, TilesCoverTheSheetWithNoPageToSpare) {
  for (const Paper paper : {Paper::A4, Paper::Letter})
    for (const Eigen::Vector2d& size :
         {Eigen::Vector2d(50, 40), Eigen::Vector2d(190, 277), Eigen::Vector2d(370, 544),
          Eigen::Vector2d(371, 545), Eigen::Vector2d(1543.2, 2210.7)}) {
      const PageTiling t = tilePages(size, paper);
      const Eigen::Vector2d step = t.cell - Eigen::Vector2d::Constant(t.overlap);
      EXPECT_NEAR(t.cell.x(), paperSize(paper).x() - 2 * t.margin, 1e-12);
      // Regions [origin, origin + cell] of neighbours overlap by `overlap`, and the last ones
      // reach the sheet's far edges.
      EXPECT_NEAR(t.origin(1, 1).x() - t.origin(0, 0).x(), step.x(), 1e-12);
      EXPECT_GT(step.minCoeff(), 0);
      EXPECT_GE(t.origin(t.rows - 1, t.columns - 1).x() + t.cell.x(), size.x() - 1e-9);
      EXPECT_GE(t.origin(t.rows - 1, t.columns - 1).y() + t.cell.y(), size.y() - 1e-9);
      // One column or row fewer would not.
      if (t.columns > 1) {
        EXPECT_LT(t.origin(0, t.columns - 2).x() + t.cell.x(), size.x());
      }
      if (t.rows > 1) {
        EXPECT_LT(t.origin(t.rows - 2, 0).y() + t.cell.y(), size.y());
      }
    }
  // 190 × 277 mm is exactly one A4 page's printed area.
  const PageTiling one = tilePages({190, 277}, Paper::A4);
  EXPECT_EQ(one.rows * one.columns, 1);
}

TEST(PatternPrint, TestSquareIsWholeOnTheFirstTilePage) {
  for (const Paper paper : {Paper::A4, Paper::Letter}) {
    const PrintSheet sheet = layoutPrintSheet(test::twoPiecePattern(), {.paper = paper});
    const PageTiling t = tilePages(sheet.size, paper);
    EXPECT_GE(sheet.testSquare.minCoeff(), t.origin(0, 0).minCoeff());
    EXPECT_LE((sheet.testSquare + Eigen::Vector2d::Constant(kTestSquareMm)).x(), t.cell.x());
    EXPECT_LE((sheet.testSquare + Eigen::Vector2d::Constant(kTestSquareMm)).y(), t.cell.y());
  }
}

TEST(PatternPrint, CutLineIsTheSewLinePlusTheAllowance) {
  const SewingPattern pattern = test::twoPiecePattern();
  const PrintSheet none = layoutPrintSheet(pattern, {.seamAllowance = 0});
  EXPECT_EQ(none.pieces[0].cutLine, pattern.pieces[0].sewLine);
  EXPECT_EQ(none.pieces[1].cutLine, pattern.pieces[1].sewLine);
  const PrintSheet cm = layoutPrintSheet(pattern, {.seamAllowance = 0.01});
  Eigen::Vector2d lo = cm.pieces[0].cutLine.front(), hi = lo;
  for (const auto& p : cm.pieces[0].cutLine) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  EXPECT_NEAR(hi.x() - lo.x(), 0.22, 1e-12);
  EXPECT_NEAR(hi.y() - lo.y(), 0.32, 1e-12);
  EXPECT_TRUE(test::noSelfIntersection(cm.pieces[1].cutLine));  // the concave L
}

TEST(PatternPrint, PiecesDoNotOverlapEachOtherOrTheHeader) {
  SewingPattern pattern = test::twoPiecePattern();
  for (int i = 0; i < 6; ++i)
    pattern.pieces.push_back(test::rectanglePiece("part", 0.35, 0.25 + 0.05 * i));
  const PrintSheet sheet = layoutPrintSheet(pattern, {});
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> boxes;
  for (const PrintedPiece& p : sheet.pieces) {
    Eigen::Vector2d lo = p.toSheet(p.cutLine.front()), hi = lo;
    for (const auto& q : p.cutLine) {
      lo = lo.cwiseMin(p.toSheet(q));
      hi = hi.cwiseMax(p.toSheet(q));
    }
    EXPECT_GE(lo.minCoeff(), 0);
    EXPECT_LE(hi.x(), sheet.size.x());
    EXPECT_LE(hi.y(), sheet.size.y());
    EXPECT_GT(lo.y(), sheet.testSquare.y() + kTestSquareMm);  // below the header
    boxes.emplace_back(lo, hi);
  }
  for (size_t i = 0; i < boxes.size(); ++i)
    for (size_t j = i + 1; j < boxes.size(); ++j) {
      const bool apart =
          boxes[i].second.x() < boxes[j].first.x() || boxes[j].second.x() < boxes[i].first.x() ||
          boxes[i].second.y() < boxes[j].first.y() || boxes[j].second.y() < boxes[i].first.y();
      EXPECT_TRUE(apart) << "pieces " << i << " and " << j;
    }
}

TEST(PatternPrint, SamePatternGivesTheSameBytes) {
  test::TempDir dir;
  const SewingPattern pattern = test::twoPiecePattern();
  writePatternSvg(dir / "a.svg", pattern);
  writePatternSvg(dir / "b.svg", pattern);
  writePatternPdf(dir / "a.pdf", pattern);
  writePatternPdf(dir / "b.pdf", pattern);
  EXPECT_TRUE(test::readFile(dir / "a.svg") == test::readFile(dir / "b.svg"));
  EXPECT_TRUE(test::readFile(dir / "a.pdf") == test::readFile(dir / "b.pdf"));
}

TEST(PatternPrint, UnwritableFolderIsAnIoErrorAndLeavesNoFile) {
  test::TempDir dir;
  const SewingPattern pattern = test::twoPiecePattern();
  EXPECT_THROW(writePatternSvg(dir / "missing" / "pattern.svg", pattern), IoError);
  EXPECT_THROW(writePatternPdf(dir / "missing" / "pattern.pdf", pattern), IoError);
  EXPECT_FALSE(std::filesystem::exists(dir / "missing"));
  test::writeFile(dir / "file", "x");  // a file as the folder: refused even for root
  EXPECT_THROW(writePatternPdf(dir / "file" / "pattern.pdf", pattern), IoError);
  if (geteuid() != 0) {
    std::filesystem::create_directory(dir / "ro");
    ::chmod((dir / "ro").c_str(), 0500);
    EXPECT_THROW(writePatternSvg(dir / "ro" / "pattern.svg", pattern), IoError);
    EXPECT_THROW(writePatternPdf(dir / "ro" / "pattern.pdf", pattern), IoError);
    EXPECT_TRUE(folderIsEmpty(dir / "ro"));
    ::chmod((dir / "ro").c_str(), 0700);
  }
}

TEST(PatternPrint, EmptyPatternOrDegeneratePieceIsAnInputError) {
  test::TempDir dir;
  EXPECT_THROW(writePatternSvg(dir / "a.svg", SewingPattern{}), InputError);
  SewingPattern line = test::twoPiecePattern();
  line.pieces[1].sewLine = {{0, 0}, {0.1, 0}, {0.2, 0}};  // zero area
  EXPECT_THROW(writePatternPdf(dir / "a.pdf", line), InputError);
  SewingPattern crossed = test::twoPiecePattern();
  crossed.pieces[0].sewLine = {{0, 0}, {0.1, 0.1}, {0.1, 0}, {0, 0.1}};
  EXPECT_THROW(writePatternSvg(dir / "a.svg", crossed), InputError);
  EXPECT_THROW(writePatternSvg(dir / "a.svg", test::twoPiecePattern(), {.seamAllowance = -0.01}),
               InputError);
  EXPECT_TRUE(folderIsEmpty(dir.path()));
}

}  // namespace
}  // namespace s2p
