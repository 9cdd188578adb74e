// A tiny built-in 5×7 pixel font for captions on preview images (no font files needed).
// Covers a–z (upper case is drawn as lower case), 0–9, space and - . : / _ ( ) %; any other
// character is drawn as '?'.
#pragma once

#include <string_view>

#include "io/scan.h"

namespace s2p {

struct Rgb;

// Width in pixels of `text` at an integer scale (each glyph cell is 6·scale wide, 7·scale tall
// plus nothing below: the font has no descenders).
int textWidth(std::string_view text, int scale);
constexpr int textHeight(int scale) {
  return 7 * scale;
}

// Draws `text` with its top-left corner at (x, y); pixels outside the image are clipped.
void drawText(Image& image, int x, int y, std::string_view text, int scale, const Rgb& colour);

}  // namespace s2p
