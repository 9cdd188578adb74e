#include "synth/presets.h"

#include <fmt/format.h>

#include <set>

#include "core/error.h"
#include "io/read_ply.h"
#include "synth/appearance.h"

namespace s2p {
namespace {

using V3 = Eigen::Vector3d;

GarmentSpec garment(GarmentType type, const V3& base, PatternKind pattern = PatternKind::Solid,
                    const V3& second = V3(0.92, 0.92, 0.90), double period = 0.04) {
  GarmentSpec g;
  g.type = type;
  g.name = toString(type);
  g.look.base = base;
  g.look.second = second;
  g.look.pattern = pattern;
  g.look.period = period;
  return g;
}

GarmentSpec shoes() {
  return garment(GarmentType::Shoes, V3(0.12, 0.11, 0.10));
}

// Named colours, sRGB.
const V3 kNavy(0.12, 0.16, 0.32), kRed(0.72, 0.12, 0.14), kDenim(0.22, 0.32, 0.50),
    kKhaki(0.68, 0.60, 0.42), kWhite(0.92, 0.92, 0.90), kBlack(0.10, 0.10, 0.11),
    kGreen(0.20, 0.45, 0.28), kYellow(0.90, 0.76, 0.22), kGrey(0.50, 0.50, 0.52),
    kBurgundy(0.45, 0.10, 0.18), kTeal(0.10, 0.48, 0.50), kBrown(0.40, 0.27, 0.16);

Preset make(const std::string& name, const std::string& description, int vertices, SynthPose pose,
            std::vector<GarmentSpec> garments, double skinTone = 0.3) {
  Preset p;
  p.name = name;
  p.description = description;
  p.options.preset = name;
  p.options.pose = pose;
  p.options.outfit.garments = std::move(garments);
  p.options.outfit.skin = s2p::skinTone(skinTone);
  p.options.geometry.targetVertices = vertices;
  return p;
}

std::vector<Preset> buildCatalogue() {
  std::vector<Preset> c;
  using G = GarmentType;
  using P = PatternKind;
  // Paper Fig. 18 outfits.
  c.push_back(make("tshirt_trousers", "t-shirt and trousers, shoes, A-pose", 22531,
                   SynthPose::APose,
                   {garment(G::TShirt, kRed), garment(G::Trousers, kDenim), shoes()}));
  c.push_back(make("longsleeve_shorts", "long-sleeve shirt and shorts, shoes, A-pose", 13931,
                   SynthPose::APose,
                   {garment(G::LongSleeveShirt, kWhite, P::Stripes, kNavy, 0.07),
                    garment(G::Shorts, kKhaki), shoes()},
                   0.5));
  c.push_back(make("sleeveless_knee_skirt", "sleeveless top and knee-length skirt, A-pose", 31218,
                   SynthPose::APose,
                   {garment(G::SleevelessTop, kYellow), garment(G::KneeSkirt, kNavy), shoes()},
                   0.15));
  {
    Preset p = make("dress", "one-piece dress to the knees, shoes, A-pose", 25000, SynthPose::APose,
                    {garment(G::Dress, kTeal, P::Dots, kWhite, 0.10), shoes()}, 0.6);
    p.options.outfit.garments[0].looseness = 0.4;
    c.push_back(p);
  }
  {
    Preset p = make("long_skirt_gaps",
                    "long skirt over the calves, gap-filling triangles with meaningless colours "
                    "(paper §5.2)",
                    30000, SynthPose::APose,
                    {garment(G::TShirt, kWhite), garment(G::LongSkirt, kBurgundy), shoes()}, 0.4);
    p.options.outfit.garments[1].looseness = 0.6;
    p.options.gapColours = true;
    c.push_back(p);
  }
  // Named hard cases.
  {
    Preset p = make("jacket_layered",
                    "open-hem jacket over a t-shirt and trousers (layered, paper case u)", 50000,
                    SynthPose::APose,
                    {garment(G::TShirt, kWhite), garment(G::Jacket, kBrown),
                     garment(G::Trousers, kBlack), shoes()},
                    0.35);
    p.options.outfit.garments[1].looseness = 0.3;
    c.push_back(p);
  }
  {
    Preset p = make("hair_over_neck", "long hair over the neck and shoulders (paper case r)", 49483,
                    SynthPose::APose,
                    {garment(G::Hair, kBrown), garment(G::TShirt, kGreen),
                     garment(G::Trousers, kGrey), shoes()},
                    0.2);
    p.options.outfit.hair = V3(0.18, 0.11, 0.06);
    c.push_back(p);
  }
  c.push_back(make("bag", "a bag held against the body (paper case a)", 31000, SynthPose::APose,
                   {garment(G::LongSleeveShirt, kNavy), garment(G::Trousers, kKhaki), shoes(),
                    garment(G::Bag, kBlack)},
                   0.45));
  {
    // Upper and lower 6 ΔE*ab apart: hard for the colour model (paper case t).
    GarmentSpec top = garment(G::TShirt, kGrey);
    GarmentSpec bottom = garment(G::Trousers, colourNear(kGrey, 6.0, 41));
    c.push_back(make("low_contrast",
                     "upper and lower garments of nearly the same grey (paper case t)", 14000,
                     SynthPose::APose, {top, bottom, shoes()}, 0.3));
  }
  {
    const V3 skin = s2p::skinTone(0.35);
    Preset p = make(
        "close_to_skin", "beige top 8 ΔE*ab from the skin tone, dark shorts", 7277,
        SynthPose::APose,
        {garment(G::SleevelessTop, colourNear(skin, 8.0, 7)), garment(G::Shorts, kNavy), shoes()},
        0.35);
    c.push_back(p);
  }
  // Bare skin against a garment of the wearer's own skin tone (issue 18): colour cannot tell
  // them apart, the garment's ease over the body can.
  c.push_back(make("shirtless", "bare torso, dark trousers and shoes: no upper garment", 20000,
                   SynthPose::APose, {garment(G::Trousers, kNavy), shoes()}, 0.4));
  c.push_back(make("skin_tone_top", "t-shirt of the wearer's own skin tone, black trousers", 20000,
                   SynthPose::APose,
                   {garment(G::TShirt, s2p::skinTone(0.4)), garment(G::Trousers, kBlack), shoes()},
                   0.4));
  {
    // A sweatshirt and chinos under a baked key light (a textured scan keeps the studio's
    // light): the lit front of the top is lighter than its far side by more than the top and
    // the trousers differ in hue.
    Preset p = make("baked_light", "sweatshirt and chinos with a baked key light (±35 %)", 20000,
                    SynthPose::APose,
                    {garment(G::LongSleeveShirt, V3(0.55, 0.58, 0.66)),
                     garment(G::Trousers, kKhaki), shoes()},
                    0.3);
    p.options.keyLight = 0.35;
    c.push_back(p);
  }
  c.push_back(make("bare_feet", "t-shirt and shorts with bare feet (no shoes), dark skin", 10000,
                   SynthPose::APose, {garment(G::TShirt, kYellow), garment(G::Shorts, kDenim)},
                   0.9));
  // Poses.
  c.push_back(make("tpose", "long-sleeve shirt and trousers in a T-pose", 18000, SynthPose::TPose,
                   {garment(G::LongSleeveShirt, kGreen), garment(G::Trousers, kKhaki), shoes()},
                   0.55));
  c.push_back(make("arms_down", "t-shirt and trousers, arms down but clear of the body", 20000,
                   SynthPose::ArmsDown,
                   {garment(G::TShirt, kNavy), garment(G::Trousers, kGrey), shoes()}, 0.7));
  c.push_back(make("walking", "t-shirt and trousers, mid-stride", 35000, SynthPose::Walking,
                   {garment(G::TShirt, kRed, P::Noise, kBurgundy, 0.08),
                    garment(G::Trousers, kDenim, P::Noise, kNavy, 0.06), shoes()},
                   0.25));
  c.push_back(make("bent_arm", "long-sleeve shirt and trousers, left elbow bent forwards", 22000,
                   SynthPose::BentArm,
                   {garment(G::LongSleeveShirt, kBurgundy), garment(G::Trousers, kBlack), shoes()},
                   0.8));
  // Body shapes (mannequin parameters, +1 = +1 cm).
  {
    Preset p = make(
        "plus_size", "fuller body (chest +12, waist +18, hip +12 cm), t-shirt and trousers", 26000,
        SynthPose::APose, {garment(G::TShirt, kTeal), garment(G::Trousers, kBlack), shoes()}, 0.5);
    p.options.shape = "chest=12,waist=18,hip=12,thigh=6,upper_arm=4";
    c.push_back(p);
  }
  {
    Preset p =
        make("tall_slim", "taller, slimmer body (height +12, chest −6, waist −6 cm), dress", 24000,
             SynthPose::APose, {garment(G::Dress, kRed, P::Stripes, kWhite, 0.08), shoes()}, 0.1);
    p.options.shape = "height=12,chest=-6,waist=-6,hip=-4";
    c.push_back(p);
  }
  // Patterns.
  c.push_back(make("patterns", "checked shirt and striped trousers", 28000, SynthPose::APose,
                   {garment(G::LongSleeveShirt, kRed, P::Checks, kWhite, 0.14),
                    garment(G::Trousers, kNavy, P::Stripes, kGrey, 0.08), shoes()},
                   0.3));
  // Corruptions.
  {
    Preset p = make(
        "noise_holes", "scanner noise (σ 1.5 mm) and 4 holes (armpits, crotch, crown)", 40000,
        SynthPose::APose,
        {garment(G::TShirt, kGreen, P::Dots, kYellow, 0.09), garment(G::Trousers, kKhaki), shoes()},
        0.65);
    p.options.geometry.noise = 0.0015;
    p.options.geometry.holes = 4;
    c.push_back(p);
  }
  // The realistic family (issue 17): the synthetic scans degraded as real scans are
  // (synth/raw_scan.h). bench/suite_realistic.json lists them; bench/suite.json does not.
  {
    // A photogrammetry phone app's export: a relaxed stance (arms against the thighs, head
    // bowed), σ 1 mm noise, holes where no camera looked (armpits, crotch, soles, crown, r 3 cm)
    // and 30 small ones (r 7-17 mm), 3 floor remnants 25 cm wide 6 mm under the soles, the
    // faces in 40 texture charts with their border vertices split, coordinates rounded to 1 mm.
    Preset p = make("phone_scan",
                    "raw phone scan: relaxed pose (arms against the thighs, head bowed), "
                    "split at 40 texture charts, 3 floor patches, 36 holes, 1 mm grid, σ 1 mm",
                    40000, SynthPose::Relaxed,
                    {garment(G::TShirt, kTeal), garment(G::Trousers, kDenim), shoes()}, 0.45);
    p.options.geometry.noise = 0.001;
    p.options.geometry.holes = 6;
    p.options.geometry.holeRadius = 0.03;
    p.options.raw.smallHoles = 30;
    p.options.raw.smallHoleRadius = 0.012;
    p.options.raw.floorPatches = 3;
    p.options.raw.floorPatchSize = 0.25;
    p.options.raw.floorGap = 0.006;
    p.options.raw.textureCharts = 40;
    p.options.raw.quantisation = 0.001;
    c.push_back(p);
  }
  {
    // A camera rig that cannot see the thighs under a knee-length skirt: the cap under the hem
    // and the legs' skin up to 4 cm below the hem are missing, so the legs are pieces of their
    // own; 6 holes (r 7-17 mm) within 3 cm of the hem.
    Preset p = make("skirt_legs_piece",
                    "long-sleeve top and knee-length skirt; legs below the hem a separate piece "
                    "(thighs unseen), 6 holes at the hem",
                    30000, SynthPose::APose,
                    {garment(G::LongSleeveShirt, kGreen), garment(G::KneeSkirt, kKhaki), shoes()},
                    0.2);
    p.options.geometry.noise = 0.0005;
    p.options.raw.unseenUnderHem = true;
    p.options.raw.unseenBelowHem = 0.04;
    p.options.raw.hemHoles = 6;
    p.options.raw.smallHoleRadius = 0.012;
    c.push_back(p);
  }
  {
    // What an image-to-3D tool exports (issue 17's GLB): a striped jersey and shorts, the boots
    // as two pieces of their own (3 pieces), 20 non-manifold edges (6 mm fins), 33 holes (6
    // where no camera looks, r 3 cm, and 27 small ones, r 6-14 mm), σ 1 mm noise.
    Preset p = make("glb_footballer",
                    "image-to-3D footballer: striped jersey, shorts, boots apart (3 pieces), 20 "
                    "non-manifold edges, 33 holes",
                    30000, SynthPose::ArmsDown,
                    {garment(G::TShirt, kRed, P::Stripes, kWhite, 0.10),
                     garment(G::Shorts, kWhite), shoes()},
                    0.6);
    p.options.geometry.noise = 0.001;
    p.options.geometry.holes = 6;
    p.options.geometry.holeRadius = 0.03;
    p.options.raw.smallHoles = 27;
    p.options.raw.smallHoleRadius = 0.01;
    p.options.raw.detachShoes = true;
    p.options.raw.fins = 20;
    c.push_back(p);
  }
  // A studio scan's texture keeps the studio's light (synth/baked_light.h): a key light,
  // ambient occlusion in every crease, the light bounced off one garment tinting its neighbour,
  // and a JPEG texture's chroma blocks. Three skin tones.
  auto studio = [](Preset p, double keyLight) {
    p.options.keyLight = keyLight;
    p.options.light.occlusion = 0.6;
    p.options.light.bounce = 0.6;
    p.options.light.chromaBlock = 0.008;
    p.options.light.blockNoise = 0.008;
    p.options.geometry.noise = 0.0005;
    return p;
  };
  c.push_back(studio(
      make("studio_sweatshirt",
           "sweatshirt and chinos in a studio's baked light (key ±45 %, occlusion, bleeding, "
           "JPEG chroma blocks)",
           30000, SynthPose::APose,
           {garment(G::LongSleeveShirt, V3(0.55, 0.58, 0.66)), garment(G::Trousers, kKhaki),
            shoes()},
           0.35),
      0.45));
  c.push_back(studio(make("studio_dark_skin",
                          "red t-shirt and denim trousers on dark skin, arms down, in a studio's "
                          "baked light (the shirt's red bounced onto the inner arms)",
                          30000, SynthPose::ArmsDown,
                          {garment(G::TShirt, kRed), garment(G::Trousers, kDenim), shoes()}, 0.9),
                     0.35));
  c.push_back(studio(make("studio_light_skin",
                          "white sleeveless top and black shorts on light skin in a studio's "
                          "baked light (the top's shaded side as grey as shadowed skin)",
                          30000, SynthPose::APose,
                          {garment(G::SleevelessTop, kWhite), garment(G::Shorts, kBlack)}, 0.0),
                     0.45));
  // Where lightness is the whole contrast: a navy top over black trousers (ΔE 14, almost all of
  // it L*) in the same light. A colour model that discounts lightness to survive shading must
  // still tell these apart.
  c.push_back(studio(make("studio_navy_black",
                          "navy t-shirt over black trousers in a studio's baked light (the two "
                          "differ mostly in lightness)",
                          30000, SynthPose::APose,
                          {garment(G::TShirt, kNavy), garment(G::Trousers, kBlack), shoes()}, 0.6),
                     0.45));
  {
    // The relaxed stance in the studio: the hanging arms touch the trousers, so the sleeves'
    // light bounces onto the thighs and the trousers' onto the inner arms, and the contact
    // creases are the darkest places of the scan.
    Preset p = studio(make("studio_relaxed",
                           "long-sleeve shirt and chinos, arms hanging against the thighs, in a "
                           "studio's baked light (colour bled across the contacts)",
                           30000, SynthPose::Relaxed,
                           {garment(G::LongSleeveShirt, kGreen), garment(G::Trousers, kKhaki),
                            shoes()},
                           0.5),
                      0.4);
    c.push_back(p);
  }
  return c;
}

}  // namespace

const std::vector<Preset>& presets() {
  static const std::vector<Preset> catalogue = buildCatalogue();
  return catalogue;
}

std::vector<std::string> presetNames() {
  std::vector<std::string> names;
  for (const Preset& p : presets()) names.push_back(p.name);
  return names;
}

const Preset& preset(const std::string& name) {
  for (const Preset& p : presets())
    if (p.name == name) return p;
  std::string known;
  for (const Preset& p : presets()) known += (known.empty() ? "" : ", ") + p.name;
  throw InputError("unknown preset '" + name + "': choose one of " + known +
                   " (scan2pattern synth --list describes them)");
}

SynthOptions presetOptions(const std::string& name) {
  return preset(name).options;
}

SynthOptions SuiteEntry::options() const {
  SynthOptions o = presetOptions(preset);
  o.seed = seed;
  if (vertices > 0) o.geometry.targetVertices = vertices;
  return o;
}

std::vector<SuiteEntry> readSuite(const std::filesystem::path& path) {
  const std::string bytes = readFileBytes(path);
  const std::string what = path.string();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(bytes);
  } catch (const nlohmann::json::exception& e) {
    throw FormatError(fmt::format("{}: not JSON ({})", what, e.what()));
  }
  if (!j.is_object() || !j.contains("entries") || !j["entries"].is_array())
    throw FormatError(what + ": expected an object with an \"entries\" list");
  std::vector<SuiteEntry> out;
  std::set<std::string> names;
  for (std::size_t i = 0; i < j["entries"].size(); ++i) {
    const auto& e = j["entries"][i];
    SuiteEntry s;
    try {
      s.name = e.at("name").get<std::string>();
      s.preset = e.at("preset").get<std::string>();
      s.seed = e.value("seed", std::uint64_t{1});
      s.vertices = e.value("vertices", 0);
      const std::string format = e.value("format", std::string("ply"));
      const auto f = parseSynthFormat(format);
      if (!f)
        throw FormatError(
            fmt::format("{}: entry {} has format '{}' (ply or obj)", what, i, format));
      s.format = *f;
      s.scaling = e.value("scaling", false);
    } catch (const nlohmann::json::exception& ex) {
      throw FormatError(fmt::format("{}: entry {} is malformed ({})", what, i, ex.what()));
    }
    if (s.name.empty() || s.name.find_first_of("/\\") != std::string::npos || s.name == "." ||
        s.name == "..")
      throw FormatError(fmt::format("{}: entry {} has an unusable name '{}'", what, i, s.name));
    if (!names.insert(s.name).second)
      throw FormatError(fmt::format("{}: entry name '{}' appears twice", what, s.name));
    try {
      (void)preset(s.preset);
    } catch (const InputError& ex) {
      throw FormatError(fmt::format("{}: entry '{}': {}", what, s.name, ex.what()));
    }
    if (s.vertices < 0 || s.vertices > 5'000'000)
      throw FormatError(
          fmt::format("{}: entry '{}' asks for {} vertices", what, s.name, s.vertices));
    out.push_back(s);
  }
  return out;
}

}  // namespace s2p
