// What a synthetic person wears: a list of garments from a fixed catalogue (covering the
// paper's Fig. 18 variety), each with its fit (ease, looseness, length) and its look (base
// colour and a solid-texture pattern), plus the skin tone.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "synth/truth.h"

namespace s2p {

enum class GarmentType {
  TShirt,           // short sleeves, hem at the hips
  LongSleeveShirt,  // sleeves to the wrists
  SleevelessTop,    // no sleeves, armholes at the shoulder
  Dress,            // one piece: top + skirt falling from the hips (free-hanging)
  Trousers,         // legs to the ankles
  Shorts,           // legs to mid-thigh
  KneeSkirt,        // free-hanging from the hips to the knees
  LongSkirt,        // free-hanging from the hips to the calves
  Jacket,           // outer layer over a top (paper case u): long sleeves, hem below the hips
  Shoes,            // closed shoes over the feet and ankles
  Hair,             // long hair over the neck and shoulders (paper case r)
  Bag,              // a bag held against the body (paper case a)
};
const char* toString(GarmentType type);  // "tshirt", "long_sleeve_shirt", ... (truth.json names)
std::optional<GarmentType> parseGarmentType(std::string_view name);
Label labelOf(GarmentType type);          // Upper, Lower, Shoes, Hair, Other (a dress is Upper)
bool isOnePiece(GarmentType type);        // Dress
bool isFreeHanging(GarmentType type);     // Dress, KneeSkirt, LongSkirt

// The pattern a garment of this type should give (truth.json "pattern"): its garment type as
// the pattern stage names it and its panel names, sorted. A jacket seen from outside is a
// long-sleeved top (the generator makes no front opening or collar); knee and long skirts are
// skirts. Shoes, hair and bags give none (empty type).
struct ExpectedPattern {
  std::string type;
  std::vector<std::string> panels;
};
ExpectedPattern expectedPattern(GarmentType type);

enum class PatternKind { Solid, Stripes, Checks, Dots, Noise };
const char* toString(PatternKind kind);
std::optional<PatternKind> parsePatternKind(std::string_view name);

// A solid texture: evaluated at a point of the rest-pose body, so stripes follow the body.
struct Look {
  Eigen::Vector3d base{0.5, 0.5, 0.5};    // sRGB in [0, 1]
  Eigen::Vector3d second{0.9, 0.9, 0.9};  // second colour of stripes, checks, dots
  PatternKind pattern = PatternKind::Solid;
  double period = 0.04;                   // metres: stripe/check/dot spacing, noise scale
};

struct GarmentSpec {
  GarmentType type = GarmentType::TShirt;
  std::string name;          // unique in the outfit; defaults to toString(type)
  Look look;
  double ease = 0.012;       // metres between body and garment where it follows the body
  double looseness = 0;      // 0 fitted .. 1 loose: sleeves and trouser legs wider than the
                             // limb, skirt flare
  double length = 0;         // hem offset from the type's default, metres (+ longer, − shorter)
  bool tuckedIn = false;     // an upper garment tucked into the lower one (the lower occludes it)
};

struct Outfit {
  std::vector<GarmentSpec> garments;           // inner to outer (a jacket after its top)
  Eigen::Vector3d skin{0.80, 0.62, 0.50};      // sRGB skin tone
  Eigen::Vector3d hair{0.20, 0.13, 0.08};      // sRGB, when the outfit has Hair
};

}  // namespace s2p
