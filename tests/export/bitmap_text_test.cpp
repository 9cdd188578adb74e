#include "export/bitmap_text.h"

#include <gtest/gtest.h>

#include <vector>

#include "export/preview.h"

namespace s2p {
namespace {

Image blank(int w, int h) {
  Image im;
  im.width = w;
  im.height = h;
  im.rgb.assign(std::size_t(w) * h * 3, 255);
  return im;
}

// Inked pixels and their bounding box {x0, y0, x1, y1}.
int inked(const Image& im, std::array<int, 4>* box = nullptr) {
  int n = 0;
  std::array<int, 4> b{im.width, im.height, -1, -1};
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x)
      if (im.rgb[(std::size_t(y) * im.width + x) * 3] != 255) {
        ++n;
        b = {std::min(b[0], x), std::min(b[1], y), std::max(b[2], x), std::max(b[3], y)};
      }
  if (box) *box = b;
  return n;
}

TEST(BitmapText, WidthCountsSixColumnsPerGlyphWithoutTrailingSpace) {
  EXPECT_EQ(textWidth("", 3), 0);
  EXPECT_EQ(textWidth("a", 1), 5);
  EXPECT_EQ(textWidth("front", 2), 5 * 12 - 2);
  EXPECT_EQ(textHeight(4), 28);
}

TEST(BitmapText, DashIsOneScaledBarOnTheMiddleRow) {
  Image im = blank(40, 40);
  drawText(im, 10, 5, "-", 3, Rgb{0, 0, 0});
  std::array<int, 4> box{};
  EXPECT_EQ(inked(im, &box), 5 * 3 * 3);
  EXPECT_EQ(box, (std::array<int, 4>{10, 5 + 3 * 3, 10 + 14, 5 + 3 * 3 + 2}));
}

TEST(BitmapText, UpperCaseIsDrawnAsLowerCaseAndUnknownAsQuestionMark) {
  Image upper = blank(80, 10), lower = blank(80, 10), odd = blank(8, 10), question = blank(8, 10);
  drawText(upper, 0, 0, "FRONT 3/4", 1, Rgb{0, 0, 0});
  drawText(lower, 0, 0, "front 3/4", 1, Rgb{0, 0, 0});
  EXPECT_EQ(upper.rgb, lower.rgb);
  EXPECT_GT(inked(lower), 40);
  drawText(odd, 0, 0, "#", 1, Rgb{0, 0, 0});
  drawText(question, 0, 0, "?", 1, Rgb{0, 0, 0});
  EXPECT_EQ(odd.rgb, question.rgb);
  // Different letters differ.
  Image l = blank(8, 10), i = blank(8, 10);
  drawText(l, 0, 0, "l", 1, Rgb{0, 0, 0});
  drawText(i, 0, 0, "i", 1, Rgb{0, 0, 0});
  EXPECT_NE(l.rgb, i.rgb);
}

// The punctuation labels use has glyphs of its own (the drape legend's "mm; 30" came out
// "mm? 30"): each differs from the unknown mark and from the others.
TEST(BitmapText, PunctuationInLabelsHasItsOwnGlyphs) {
  std::vector<std::vector<unsigned char>> seen;
  for (const char* c : {"?", ";", ",", "'", "+", "=", "<", ">", ":", "."}) {
    Image im = blank(8, 10);
    drawText(im, 0, 0, c, 1, Rgb{0, 0, 0});
    EXPECT_GT(inked(im), 0) << c;
    for (const auto& other : seen) EXPECT_NE(im.rgb, other) << c;
    seen.push_back(im.rgb);
  }
}

TEST(BitmapText, ClipsAtTheImageBorder) {
  Image im = blank(10, 10);
  drawText(im, -7, -20, "-", 2, Rgb{0, 0, 0});  // entirely above
  EXPECT_EQ(inked(im), 0);
  drawText(im, -6, 0, "-", 2, Rgb{0, 0, 0});  // bar spans x in [-6, 4)
  EXPECT_EQ(inked(im), 4 * 2);
}

}  // namespace
}  // namespace s2p
