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

ExpectedPattern expectedPattern(GarmentType type) {
  using G = GarmentType;
  const std::vector<std::string> top = {"back", "front", "left_sleeve", "right_sleeve"};
  const std::vector<std::string> legs = {"left_back", "left_front", "right_back", "right_front"};
  switch (type) {
    case G::TShirt: return {"tshirt", top};
    case G::LongSleeveShirt:
    case G::Jacket: return {"long_sleeve_shirt", top};
    case G::SleevelessTop: return {"sleeveless_top", {"back", "front"}};
    case G::Dress: return {"dress", {"back", "front"}};
    case G::Trousers: return {"trousers", legs};
    case G::Shorts: return {"shorts", legs};
    case G::KneeSkirt:
    case G::LongSkirt: return {"skirt", {"back", "front"}};
    case G::Shoes:
    case G::Hair:
    case G::Bag: return {};
  }
  return {};
}

}  // namespace s2p
