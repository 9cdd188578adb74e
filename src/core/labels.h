// Per-vertex and per-face label codes shared by the synthetic generator, the segmentation and
// the metrics (the PLY "label" property of scans and segmentation outputs).
#pragma once

#include <optional>
#include <string_view>

namespace s2p {

// Gap marks gap-filling triangles under a free-hanging hem (paper §5.2): they belong to no
// garment, and the metrics leave them out of the IoU.
enum class Label : int { Skin = 0, Upper = 1, Lower = 2, Shoes = 3, Hair = 4, Other = 5, Gap = 6 };
constexpr int kNumLabels = 7;
const char* toString(Label label);                       // "skin", "upper", ...
std::optional<Label> parseLabel(std::string_view name);  // inverse of toString
bool isValidLabel(int code);

}  // namespace s2p
