// pattern.dxf for pattern-making and 3D garment software, in the DXF-AAMA / ASTM D6673 style:
// R12 ASCII (AC1009), 7-bit ASCII text, millimetres. One BLOCK per piece, inserted once in
// ENTITIES, on AAMA's numbered layers:
//   1  cut line (closed POLYLINE) and the piece text: Piece Name, Quantity, Size, Category
//   4  notches (LINE: a slit from the cut line inward)
//   7  grainline (LINE)
//   8  internal lines (POLYLINE)
//   14 sew line (closed POLYLINE)
// The style text (Style Name, Creation Date, Units: METRIC, Sample Size) is in ENTITIES on layer 1.
#pragma once

#include <filesystem>

#include "export/sewing_pattern.h"

namespace s2p {

struct DxfOptions {
  double seamAllowance = 0.01;  // metres, ≥ 0: the cut line (layer 1) is the sew line plus this
};

// Written atomically: IoError when the folder cannot be written (nothing left behind),
// InputError for an empty pattern, a degenerate piece or a negative allowance.
void writePatternDxf(const std::filesystem::path& path, const SewingPattern& pattern,
                     const DxfOptions& options = {});

}  // namespace s2p
