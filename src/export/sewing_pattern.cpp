#include "export/sewing_pattern.h"

#include <fmt/format.h>

#include "core/error.h"
#include "export/piece_outline.h"

namespace s2p {

void checkSewingPattern(const SewingPattern& pattern, const std::string& writer) {
  if (pattern.pieces.empty())
    throw InputError(writer + ": the pattern has no piece; nothing to write");
  for (size_t i = 0; i < pattern.pieces.size(); ++i) {
    const SewingPiece& piece = pattern.pieces[i];
    const auto fail = [&](const std::string& what) {
      throw InputError(fmt::format("{}: piece {} (\"{}\" of \"{}\") {}", writer, i, piece.name,
                                   piece.garment, what));
    };
    if (!isSimplePolygon(piece.sewLine))
      fail(fmt::format(
          "has a degenerate sew line ({} points): it must be a closed counter-clockwise polygon "
          "of at least 3 finite points that does not cross itself",
          piece.sewLine.size()));
    if (piece.quantity < 1) fail(fmt::format("has quantity {}; at least 1", piece.quantity));
    for (const SewingNotch& notch : piece.notches)
      if (!notch.at.allFinite() || !notch.normal.allFinite() || notch.normal.norm() < 1e-9)
        fail("has a notch with a non-finite position or no normal");
    if (!piece.grainFrom.allFinite() || !piece.grainTo.allFinite())
      fail("has a non-finite grainline");
    for (const auto& line : piece.internalLines)
      for (const Eigen::Vector2d& p : line)
        if (!p.allFinite()) fail("has a non-finite internal line");
  }
}

}  // namespace s2p
