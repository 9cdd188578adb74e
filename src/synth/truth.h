// Ground truth of a synthetic scan (`truth.json`): what was generated, where the garments'
// boundaries truly are, and the body under the clothes. Written by the generator, read by the
// metrics (src/eval) and by stages that are tested before their predecessors exist (a
// segmentation run with the true body, say).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/labels.h"

namespace s2p {

struct TrueGarment {
  std::string name;   // unique in the outfit: "t-shirt", "trousers", "jacket", "shoes", "bag", ...
  std::string type;   // catalogue type: tshirt, long_sleeve_shirt, sleeveless_top, dress,
                      // trousers, shorts, knee_skirt, long_skirt, jacket, shoes, hair, bag
  Label label = Label::Other;  // label carried by its visible surface
  bool onePiece = false;       // covers upper and lower body in one piece (dress, §5.3)
  std::vector<std::string> occludes;  // garments whose part this one hides (upper over lower)
  double visibleArea = 0;      // m², area of the scan surface it shows (0: fully hidden)
  // The pattern it should give (Patterns I): garment type (tshirt, long_sleeve_shirt,
  // sleeveless_top, trousers, shorts, skirt, dress) and panel names, sorted; empty for shoes,
  // hair and bags.
  std::string patternType;
  std::vector<std::string> panels;
};

// The true boundary between two labels: the curves where the label changes on the scan.
struct TrueBoundary {
  Label a = Label::Skin, b = Label::Skin;  // a < b
  std::vector<Eigen::MatrixX3d> curves;    // polylines in the scan's frame (metres)
  std::vector<bool> closed;                // per curve
  double length() const;                   // total length of the curves, metres
};

struct Truth {
  std::string preset;            // suite preset name, or "custom"
  std::uint64_t seed = 0;
  std::string scanFile;          // the scan to feed the pipeline, relative to truth.json
  std::string labelledMesh;      // PLY with the scan's vertices and faces and their "label"
                                 // (vertex and face), relative to truth.json
  std::string frame = "metres, +Y up, facing +Z";  // frame of every coordinate in the file
  std::vector<TrueGarment> garments;
  nlohmann::json body;           // bodyToJson() of the body under the clothes (source, shape,
                                 // pose, translation, joints, canonical)
  std::vector<TrueBoundary> boundaries;
  nlohmann::json generator;      // the generator's options, to reproduce the scan

  const TrueBoundary* boundary(Label a, Label b) const;  // either order; nullptr when absent
  const TrueGarment* garment(std::string_view name) const;
  bool hasOnePiece() const;
};

// The "boundaries" array of truth.json (also the format of a segmentation's boundaries.json):
// [{"labels": [a, b], "length_m", "curves": [{"closed", "points": [[x, y, z], ...]}]}].
nlohmann::json boundariesToJson(const std::vector<TrueBoundary>& boundaries);
// Inverse of boundariesToJson; a malformed entry → FormatError naming `what` and the entry.
// Labels are stored with a < b whatever their order in the file.
std::vector<TrueBoundary> boundariesFromJson(const nlohmann::json& j,
                                             const std::string& what = "boundaries");

nlohmann::json truthToJson(const Truth& truth);
// Malformed or missing entries → FormatError naming `what` and the entry.
Truth truthFromJson(const nlohmann::json& j, const std::string& what = "truth.json");
// File I/O: written atomically; reading a missing file → IoError, bad JSON → FormatError.
void writeTruth(const std::filesystem::path& path, const Truth& truth);
Truth readTruth(const std::filesystem::path& path);

}  // namespace s2p
