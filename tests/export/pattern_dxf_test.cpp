#include "export/pattern_dxf.h"

#include <dl_creationadapter.h>
#include <dl_dxf.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <map>
#include <set>

#include "core/error.h"
#include "pattern_fixtures.h"
#include "test_support.h"

namespace s2p {
namespace {

struct Polyline {
  std::string layer;
  bool closed = false;
  std::vector<Eigen::Vector2d> points;
};
struct Line {
  std::string layer;
  Eigen::Vector2d a, b;
};
// What one block (or ENTITIES, named "") holds.
struct Content {
  std::vector<Polyline> polylines;
  std::vector<Line> lines;
  std::vector<std::string> texts;
  std::set<std::string> layers;
};

// Reads a DXF back with dxflib's own reader.
class Reader : public DL_CreationAdapter {
 public:
  std::map<std::string, Content> blocks;
  std::vector<std::string> blockOrder;
  std::vector<std::string> inserts;

  void addBlock(const DL_BlockData& data) override {
    current_ = data.name;
    blockOrder.push_back(data.name);
  }
  void endBlock() override { current_.clear(); }
  void addPolyline(const DL_PolylineData& data) override {
    here().polylines.push_back({layer(), (data.flags & 1) != 0, {}});
  }
  void addVertex(const DL_VertexData& data) override {
    here().polylines.back().points.emplace_back(data.x, data.y);
  }
  void addLine(const DL_LineData& data) override {
    here().lines.push_back({layer(), {data.x1, data.y1}, {data.x2, data.y2}});
  }
  void addText(const DL_TextData& data) override {
    layer();
    here().texts.push_back(data.text);
  }
  void addInsert(const DL_InsertData& data) override {
    layer();
    inserts.push_back(data.name);
  }

 private:
  Content& here() { return blocks[current_]; }
  std::string layer() {
    const std::string name = getAttributes().getLayer();
    here().layers.insert(name);
    return name;
  }
  std::string current_;
};

Reader readBack(const std::filesystem::path& path) {
  Reader reader;
  DL_Dxf dxf;
  EXPECT_TRUE(dxf.in(path.string(), &reader));
  return reader;
}

bool contains(const std::vector<std::string>& texts, const std::string& text) {
  return std::find(texts.begin(), texts.end(), text) != texts.end();
}

Eigen::Vector2d extent(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d lo = points.front(), hi = lo;
  for (const auto& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return hi - lo;
}

const Polyline* onLayer(const Content& c, const std::string& layer) {
  for (const Polyline& p : c.polylines)
    if (p.layer == layer) return &p;
  return nullptr;
}

TEST(PatternDxf, IsR12AsciiWithNoTables) {
  test::TempDir dir;
  SewingPattern pattern = test::twoPiecePattern();
  pattern.pieces[0].name = "devant \xc3\xa9paule";  // "devant épaule"
  writePatternDxf(dir / "pattern.dxf", pattern);
  const std::string bytes = test::readFile(dir / "pattern.dxf");
  for (const char ch : bytes) ASSERT_LT(static_cast<unsigned char>(ch), 128);
  EXPECT_NE(bytes.find("$ACADVER\n  1\nAC1009\n"), std::string::npos);
  EXPECT_EQ(bytes.find("TABLES"), std::string::npos);
  EXPECT_EQ(bytes.find("MODEL_SPACE"), std::string::npos);
  const Reader dxf = readBack(dir / "pattern.dxf");
  EXPECT_TRUE(contains(dxf.blocks.at(dxf.blockOrder[0]).texts, "Piece Name: devant ?paule"));
}

TEST(PatternDxf, OneBlockPerPieceOnTheAamaLayers) {
  test::TempDir dir;
  const SewingPattern pattern = test::twoPiecePattern();
  writePatternDxf(dir / "pattern.dxf", pattern);
  const Reader dxf = readBack(dir / "pattern.dxf");
  ASSERT_EQ(dxf.blockOrder.size(), pattern.pieces.size());
  EXPECT_EQ(dxf.blockOrder[0], "tshirt_front");
  EXPECT_EQ(dxf.blockOrder[1], "tshirt_left_sleeve");
  EXPECT_EQ(dxf.inserts, dxf.blockOrder);  // each inserted once, in ENTITIES

  const Content& front = dxf.blocks.at("tshirt_front");
  EXPECT_EQ(front.layers, (std::set<std::string>{"1", "4", "7", "8", "14"}));
  for (const char* text : {"Piece Name: front", "Quantity: 1", "Size: M", "Category: tshirt"})
    EXPECT_TRUE(contains(front.texts, text)) << text;
  EXPECT_TRUE(contains(dxf.blocks.at("tshirt_left_sleeve").texts, "Quantity: 2"));

  const Content& entities = dxf.blocks.at("");
  EXPECT_EQ(entities.layers, std::set<std::string>{"1"});
  for (const char* text :
       {"Style Name: test style", "Creation Date: 2026-12-01", "Units: METRIC", "Sample Size: M"})
    EXPECT_TRUE(contains(entities.texts, text)) << text;
}

TEST(PatternDxf, CoordinatesAreMillimetres) {
  test::TempDir dir;
  writePatternDxf(dir / "pattern.dxf", test::twoPiecePattern());
  const Content front = readBack(dir / "pattern.dxf").blocks.at("tshirt_front");
  // The 20 × 30 cm sew line is 200 × 300 units; the cut line has the 10 mm allowance.
  const Polyline* sew = onLayer(front, "14");
  const Polyline* cut = onLayer(front, "1");
  ASSERT_TRUE(sew && cut);
  EXPECT_TRUE(sew->closed);
  EXPECT_TRUE(cut->closed);
  EXPECT_NEAR(extent(sew->points).x(), 200, 1e-9);
  EXPECT_NEAR(extent(sew->points).y(), 300, 1e-9);
  EXPECT_NEAR(extent(cut->points).x(), 220, 1e-9);
  EXPECT_NEAR(extent(cut->points).y(), 320, 1e-9);
  // Notches: 6 mm slits from the cut line inward, one per notch; the grainline as given.
  int notches = 0;
  for (const Line& l : front.lines) {
    if (l.layer == "7") {
      EXPECT_NEAR((l.a - Eigen::Vector2d(100, 60)).norm(), 0, 1e-9);
      EXPECT_NEAR((l.b - Eigen::Vector2d(100, 240)).norm(), 0, 1e-9);
    }
    if (l.layer != "4") continue;
    ++notches;
    EXPECT_NEAR((l.b - l.a).norm(), 6, 1e-9);
    EXPECT_NEAR(test::distanceToOutline(cut->points, l.a), 0, 1e-9);
    EXPECT_NEAR(test::distanceToOutline(sew->points, l.b), 4, 1e-9);  // 10 mm − 6 mm
  }
  EXPECT_EQ(notches, 4);
}

TEST(PatternDxf, ZeroAllowanceCutsOnTheSewLine) {
  test::TempDir dir;
  writePatternDxf(dir / "pattern.dxf", test::twoPiecePattern(), {.seamAllowance = 0});
  const Content sleeve = readBack(dir / "pattern.dxf").blocks.at("tshirt_left_sleeve");
  ASSERT_TRUE(onLayer(sleeve, "1") && onLayer(sleeve, "14"));
  EXPECT_EQ(onLayer(sleeve, "1")->points, onLayer(sleeve, "14")->points);
}

TEST(PatternDxf, BlockNamesAreUniqueAndPlain) {
  test::TempDir dir;
  SewingPattern pattern = test::twoPiecePattern();
  pattern.pieces[1] = pattern.pieces[0];  // two "front" pieces of the same garment
  pattern.pieces[1].name = "front";
  pattern.pieces.push_back(test::rectanglePiece("back piece/2", 0.1, 0.1));
  writePatternDxf(dir / "pattern.dxf", pattern);
  const Reader dxf = readBack(dir / "pattern.dxf");
  EXPECT_EQ(dxf.blockOrder,
            (std::vector<std::string>{"tshirt_front", "tshirt_front_2", "tshirt_back_piece_2"}));
}

TEST(PatternDxf, UnwritableFolderIsAnIoErrorAndLeavesNoFile) {
  test::TempDir dir;
  const SewingPattern pattern = test::twoPiecePattern();
  EXPECT_THROW(writePatternDxf(dir / "missing" / "pattern.dxf", pattern), IoError);
  test::writeFile(dir / "file", "x");
  EXPECT_THROW(writePatternDxf(dir / "file" / "pattern.dxf", pattern), IoError);
  if (geteuid() != 0) {
    std::filesystem::create_directory(dir / "ro");
    ::chmod((dir / "ro").c_str(), 0500);
    EXPECT_THROW(writePatternDxf(dir / "ro" / "pattern.dxf", pattern), IoError);
    EXPECT_TRUE(std::filesystem::is_empty(dir / "ro"));
    ::chmod((dir / "ro").c_str(), 0700);
  }
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.path())) ++files;
  EXPECT_EQ(files, geteuid() != 0 ? 2 : 1);  // "file" (and "ro")
}

TEST(PatternDxf, EmptyPatternOrDegeneratePieceIsAnInputError) {
  test::TempDir dir;
  EXPECT_THROW(writePatternDxf(dir / "a.dxf", SewingPattern{}), InputError);
  SewingPattern two = test::twoPiecePattern();
  two.pieces[0].sewLine.resize(2);
  EXPECT_THROW(writePatternDxf(dir / "a.dxf", two), InputError);
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace s2p
