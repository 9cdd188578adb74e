#include "synth/outfit.h"

#include <array>
#include <utility>

namespace s2p {
namespace {

constexpr std::array<std::pair<GarmentType, const char*>, 12> kGarmentNames = {{
    {GarmentType::TShirt, "tshirt"},
    {GarmentType::LongSleeveShirt, "long_sleeve_shirt"},
    {GarmentType::SleevelessTop, "sleeveless_top"},
    {GarmentType::Dress, "dress"},
    {GarmentType::Trousers, "trousers"},
    {GarmentType::Shorts, "shorts"},
    {GarmentType::KneeSkirt, "knee_skirt"},
    {GarmentType::LongSkirt, "long_skirt"},
    {GarmentType::Jacket, "jacket"},
    {GarmentType::Shoes, "shoes"},
    {GarmentType::Hair, "hair"},
    {GarmentType::Bag, "bag"},
}};

constexpr std::array<std::pair<PatternKind, const char*>, 5> kPatternNames = {{
    {PatternKind::Solid, "solid"},
    {PatternKind::Stripes, "stripes"},
    {PatternKind::Checks, "checks"},
    {PatternKind::Dots, "dots"},
    {PatternKind::Noise, "noise"},
}};

template <class Enum, std::size_t N>
const char* nameOf(const std::array<std::pair<Enum, const char*>, N>& table, Enum e) {
  for (const auto& [value, name] : table)
    if (value == e) return name;
  return "invalid";
}

template <class Enum, std::size_t N>
std::optional<Enum> parseName(const std::array<std::pair<Enum, const char*>, N>& table,
                              std::string_view s) {
  for (const auto& [value, name] : table)
    if (s == name) return value;
  return std::nullopt;
}

}  // namespace

const char* toString(GarmentType type) { return nameOf(kGarmentNames, type); }
std::optional<GarmentType> parseGarmentType(std::string_view name) {
  return parseName(kGarmentNames, name);
}
const char* toString(PatternKind kind) { return nameOf(kPatternNames, kind); }
std::optional<PatternKind> parsePatternKind(std::string_view name) {
  return parseName(kPatternNames, name);
}

Label labelOf(GarmentType type) {
  switch (type) {
    case GarmentType::TShirt:
    case GarmentType::LongSleeveShirt:
    case GarmentType::SleevelessTop:
    case GarmentType::Dress:
    case GarmentType::Jacket:
      return Label::Upper;
    case GarmentType::Trousers:
    case GarmentType::Shorts:
    case GarmentType::KneeSkirt:
    case GarmentType::LongSkirt:
      return Label::Lower;
    case GarmentType::Shoes:
      return Label::Shoes;
    case GarmentType::Hair:
      return Label::Hair;
    case GarmentType::Bag:
      return Label::Other;
  }
  return Label::Other;
}

bool isOnePiece(GarmentType type) { return type == GarmentType::Dress; }

bool isFreeHanging(GarmentType type) {
  return type == GarmentType::Dress || type == GarmentType::KneeSkirt ||
         type == GarmentType::LongSkirt;
}

}  // namespace s2p
