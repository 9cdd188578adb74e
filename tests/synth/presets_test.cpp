// The preset catalogue: every name builds valid options; unknown names are refused by name.
#include "synth/presets.h"

#include <gtest/gtest.h>

#include <set>

#include "core/colour.h"
#include "core/error.h"
#include "synth/appearance.h"

namespace s2p {
namespace {

TEST(Presets, AtLeastFourteenWithUniqueNamesAndValidOptions) {
  const auto names = presetNames();
  EXPECT_GE(names.size(), 14u);
  EXPECT_EQ(std::set<std::string>(names.begin(), names.end()).size(), names.size());
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const SynthOptions o = presetOptions(name);
    EXPECT_EQ(o.preset, name);
    EXPECT_FALSE(preset(name).description.empty());
    EXPECT_GE(o.geometry.targetVertices, 7000);
    EXPECT_LE(o.geometry.targetVertices, 50000);
    EXPECT_EQ(o.bodySource, "mannequin");
    // Garment names unique; colours in gamut; appearance accepts the outfit.
    std::set<std::string> garmentNames;
    for (const auto& g : o.outfit.garments) {
      EXPECT_TRUE(garmentNames.insert(g.name).second) << g.name;
      EXPECT_TRUE((g.look.base.array() >= 0).all() && (g.look.base.array() <= 1).all());
    }
    EXPECT_NO_THROW(Appearance(o.outfit, {}));
    // Options survive their JSON form (truth.json "generator").
    EXPECT_EQ(synthOptionsToJson(synthOptionsFromJson(synthOptionsToJson(o))),
              synthOptionsToJson(o));
  }
}

TEST(Presets, CoverTheCataloguePosesAndHardCases) {
  std::set<GarmentType> types;
  std::set<SynthPose> poses;
  std::set<PatternKind> patterns;
  bool gap = false, noise = false, holes = false, shape = false, bareFeet = false;
  int studioLight = 0;  // key light, occlusion, bleeding and JPEG blocks together
  for (const Preset& p : presets()) {
    bool hasShoes = false;
    for (const auto& g : p.options.outfit.garments) {
      types.insert(g.type);
      patterns.insert(g.look.pattern);
      hasShoes |= g.type == GarmentType::Shoes;
    }
    bareFeet |= !hasShoes;
    poses.insert(p.options.pose);
    gap |= p.options.gapColours;
    noise |= p.options.geometry.noise > 0;
    holes |= p.options.geometry.holes > 0;
    shape |= !p.options.shape.empty();
    const BakedLightOptions& l = p.options.light;
    if (p.options.keyLight > 0 && l.occlusion > 0 && l.bounce > 0 && l.chromaBlock > 0)
      ++studioLight;
  }
  EXPECT_EQ(types.size(), 12u);    // every garment type of the catalogue
  EXPECT_EQ(poses.size(), 6u);     // A, T, arms down, walking, bent arm, relaxed
  EXPECT_EQ(patterns.size(), 5u);  // solid, stripes, checks, dots, noise
  EXPECT_TRUE(gap && noise && holes && shape && bareFeet);
  EXPECT_GE(studioLight, 3);  // issue 18: baked light on three skin tones
  // Low contrast (case t): upper and lower within 10 ΔE*ab; close to skin: within 10 of it.
  const SynthOptions lc = presetOptions("low_contrast");
  EXPECT_LT(deltaE76(srgbToLab(lc.outfit.garments[0].look.base),
                     srgbToLab(lc.outfit.garments[1].look.base)),
            10);
  const SynthOptions cs = presetOptions("close_to_skin");
  EXPECT_LT(deltaE76(srgbToLab(cs.outfit.garments[0].look.base), srgbToLab(cs.outfit.skin)), 10);
}

TEST(Presets, UnknownNameListsTheKnownOnes) {
  try {
    presetOptions("nope");
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("nope"), std::string::npos);
    EXPECT_NE(msg.find("tshirt_trousers"), std::string::npos);
    EXPECT_NE(msg.find("walking"), std::string::npos);
  }
}

}  // namespace
}  // namespace s2p
