#include "core/labels.h"

#include <array>

namespace s2p {
namespace {

constexpr std::array<const char*, kNumLabels> kLabelNames = {"skin",  "upper", "lower", "shoes",
                                                             "hair",  "other", "gap"};

}  // namespace

const char* toString(Label label) {
  const int i = static_cast<int>(label);
  return isValidLabel(i) ? kLabelNames[i] : "invalid";
}

std::optional<Label> parseLabel(std::string_view name) {
  for (int i = 0; i < kNumLabels; ++i)
    if (name == kLabelNames[i]) return static_cast<Label>(i);
  return std::nullopt;
}

bool isValidLabel(int code) { return code >= 0 && code < kNumLabels; }

}  // namespace s2p
