// Solid-texture patterns, noise, skin tones and hard-case colours with known answers.
#include "synth/appearance.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/colour.h"
#include "core/error.h"

namespace s2p {
namespace {

Look twoColourLook(PatternKind kind, double period) {
  Look l;
  l.base = Eigen::Vector3d(0.1, 0.2, 0.3);
  l.second = Eigen::Vector3d(0.9, 0.8, 0.7);
  l.pattern = kind;
  l.period = period;
  return l;
}

TEST(Pattern, StripesAlternateWithThePeriodAlongY) {
  const double period = 0.05;
  const Look look = twoColourLook(PatternKind::Stripes, period);
  // Sample 1 m along +Y (offset so no sample lands on a band edge): 2 transitions per period.
  int transitions = 0;
  Eigen::Vector3d prev = patternColour(look, {0.13, 0.0013, -0.07}, 1);
  for (int i = 1; i <= 10000; ++i) {
    const Eigen::Vector3d c = patternColour(look, {0.13, 0.0013 + i * 1e-4, -0.07}, 1);
    EXPECT_TRUE(c.isApprox(look.base) || c.isApprox(look.second));
    if (!c.isApprox(prev)) ++transitions;
    prev = c;
  }
  EXPECT_EQ(transitions, 40);
  // Half a period apart: the other colour; a whole period apart: the same.
  const Eigen::Vector3d p(0.3, 0.61, 0.2);
  EXPECT_FALSE(patternColour(look, p, 1)
                   .isApprox(patternColour(look, p + Eigen::Vector3d(0, period / 2, 0), 1)));
  EXPECT_TRUE(patternColour(look, p, 1)
                  .isApprox(patternColour(look, p + Eigen::Vector3d(0, period, 0), 1)));
  // Constant across X and Z (bands go around the body).
  EXPECT_TRUE(patternColour(look, p, 1)
                  .isApprox(patternColour(look, p + Eigen::Vector3d(0.37, 0, -0.21), 1)));
}

TEST(Pattern, ChecksFormFourQuadrants) {
  const double period = 0.1;  // cells 5 cm
  const Look look = twoColourLook(PatternKind::Checks, period);
  const double z = 0.01, d = 0.012;  // inside the cell [0, 0.05) in z; around the corner (0, 0)
  const Eigen::Vector3d pp = patternColour(look, {d, d, z}, 1),
                        mp = patternColour(look, {-d, d, z}, 1),
                        mm = patternColour(look, {-d, -d, z}, 1),
                        pm = patternColour(look, {d, -d, z}, 1);
  EXPECT_TRUE(pp.isApprox(look.base));  // cell (0, 0, 0): even
  EXPECT_TRUE(mm.isApprox(look.base));
  EXPECT_TRUE(mp.isApprox(look.second));
  EXPECT_TRUE(pm.isApprox(look.second));
  // A whole period further: the same colour.
  EXPECT_TRUE(patternColour(look, {d + period, d, z}, 1).isApprox(pp));
}

TEST(Pattern, SolidIsConstantAndDotsHaveTheirArea) {
  const Look solid = twoColourLook(PatternKind::Solid, 0.04);
  const Look dots = twoColourLook(PatternKind::Dots, 0.04);
  int inDot = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    // A fixed pseudo-random walk over a 1 m cube.
    const Eigen::Vector3d p(std::fmod(i * 0.6180339887, 1.0), std::fmod(i * 0.7548776662, 1.0),
                            std::fmod(i * 0.5698402910, 1.0));
    EXPECT_TRUE(patternColour(solid, p, 3).isApprox(solid.base));
    if (patternColour(dots, p, 3).isApprox(dots.second)) ++inDot;
  }
  // Balls of radius period/4 in cells of side period: 4/3·π·(1/4)³ ≈ 0.0654 of the volume.
  EXPECT_NEAR(static_cast<double>(inDot) / n, 4.0 / 3.0 * M_PI / 64.0, 0.01);
}

TEST(Pattern, NoiseIsDeterministicPerSeedAndSmooth) {
  const Look look = twoColourLook(PatternKind::Noise, 0.05);
  double diff = 0, maxJump = 0;
  for (int i = 0; i < 500; ++i) {
    const Eigen::Vector3d p(0.001 * i, 0.3 + 0.0007 * i, -0.1);
    const Eigen::Vector3d a = patternColour(look, p, 42);
    EXPECT_EQ(a, patternColour(look, p, 42));  // bit-identical
    diff += (a - patternColour(look, p, 43)).norm();
    maxJump =
        std::max(maxJump, (a - patternColour(look, p + Eigen::Vector3d(1e-5, 0, 0), 42)).norm());
  }
  EXPECT_GT(diff / 500, 0.02);  // another seed, another texture
  EXPECT_LT(maxJump, 0.01);     // continuous: 10 µm moves the colour very little
  // Value noise stays in [0, 1] and equals the lattice values' interpolation at nodes' range.
  for (int i = 0; i < 1000; ++i) {
    const double v = valueNoise(Eigen::Vector3d(i * 0.37, i * -0.11, i * 0.05), 9);
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 1.0);
  }
}

TEST(SkinTone, RunsFromLightToDark) {
  const auto& table = skinToneTable();
  ASSERT_GE(table.size(), 6u);
  for (size_t i = 1; i < table.size(); ++i)
    EXPECT_LT(srgbToLab(table[i]).x(), srgbToLab(table[i - 1]).x()) << i;
  EXPECT_TRUE(skinTone(0).isApprox(table.front()));
  EXPECT_TRUE(skinTone(1).isApprox(table.back()));
  EXPECT_TRUE(skinTone(-3).isApprox(table.front()));
  EXPECT_TRUE(skinTone(0.5).isApprox(0.5 * (table[3] + table[4])));  // 8 entries: between 3 and 4
}

TEST(HardCases, ColourNearIsAtTheRequestedDistance) {
  const Eigen::Vector3d grey(0.5, 0.5, 0.52);
  for (double dE : {3.0, 6.0, 10.0}) {
    const Eigen::Vector3d c = colourNear(grey, dE, 5);
    EXPECT_NEAR(deltaE76(srgbToLab(grey), srgbToLab(c)), dE, 1e-6);
  }
  EXPECT_EQ(colourNear(grey, 6, 5), colourNear(grey, 6, 5));
  EXPECT_FALSE(colourNear(grey, 6, 5).isApprox(colourNear(grey, 6, 6)));
}

Outfit testOutfit() {
  Outfit o;
  GarmentSpec skirt;
  skirt.type = GarmentType::KneeSkirt;
  skirt.look.base = Eigen::Vector3d(0.6, 0.2, 0.2);
  o.garments.push_back(skirt);
  return o;
}

TEST(Appearance, ShadingIsMildAndMultiplicative) {
  const Outfit o = testOutfit();
  const Appearance app(o, {.shading = 0.06, .seed = 3});
  const Eigen::Vector3d up(0, 1, 0);
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector3d p(0.01 * i, 0.5 + 0.003 * i, 0.1);
    const Eigen::Vector3d c = app.colour(0, Label::Lower, p, up);
    const Eigen::Vector3d ratio = c.cwiseQuotient(o.garments[0].look.base);
    // One factor for all channels, within ±6 %.
    EXPECT_NEAR(ratio.x(), ratio.y(), 1e-9);
    EXPECT_NEAR(ratio.x(), ratio.z(), 1e-9);
    EXPECT_LE(std::abs(ratio.x() - 1), 0.06 + 1e-9);
  }
  const Appearance flat(o, {.shading = 0, .seed = 3});
  EXPECT_TRUE(flat.colour(0, Label::Lower, {0.2, 0.7, 0}, up).isApprox(o.garments[0].look.base));
  // Facing the floor: darker.
  EXPECT_LT(flat.colour(0, Label::Lower, {0.2, 0.7, 0}, -up).sum(),
            flat.colour(0, Label::Lower, {0.2, 0.7, 0}, up).sum());
}

TEST(Appearance, GapFacesInsideColourOrBlotches) {
  const Outfit o = testOutfit();
  const Eigen::Vector3d up(0, 1, 0);
  const Appearance inside(o, {.shading = 0, .gapColours = false, .seed = 3});
  // Without gap colours: the skirt's inside, darker than its base, even with no layer given.
  EXPECT_TRUE(
      inside.colour(0, Label::Gap, {0.1, 0.5, 0}, up).isApprox(0.45 * o.garments[0].look.base));
  EXPECT_TRUE(
      inside.colour(-1, Label::Gap, {0.1, 0.5, 0}, up).isApprox(0.45 * o.garments[0].look.base));
  // With gap colours: varied (several distinct colours over a strip), deterministic.
  const Appearance blotchy(o, {.shading = 0, .gapColours = true, .seed = 3});
  double spread = 0;
  const Eigen::Vector3d c0 = blotchy.colour(0, Label::Gap, {0, 0.5, 0}, up);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d p(0.01 * i, 0.5, 0);
    spread = std::max(spread, (blotchy.colour(0, Label::Gap, p, up) - c0).norm());
    EXPECT_EQ(blotchy.colour(0, Label::Gap, p, up), blotchy.colour(0, Label::Gap, p, up));
  }
  EXPECT_GT(spread, 0.2);
}

TEST(Appearance, SkinUsesTheToneAndBadInputThrows) {
  Outfit o = testOutfit();
  o.skin = skinTone(1.0);
  const Appearance app(o, {.shading = 0, .seed = 1});
  const Eigen::Vector3d c = app.colour(-1, Label::Skin, {0, 1.6, 0}, {0, 0, 1});
  EXPECT_LT((c - o.skin).norm(), 0.05);
  EXPECT_THROW(Appearance(o, {.shading = -1}), InputError);
  o.garments[0].look.period = 0;
  EXPECT_THROW(Appearance(o, {}), InputError);
  const Appearance ok(testOutfit(), {});
  EXPECT_THROW(ok.colours(Eigen::VectorXi::Zero(2), Eigen::VectorXi::Constant(2, 9),
                          Eigen::MatrixX3d::Zero(2, 3), Eigen::MatrixX3d::Zero(2, 3)),
               InputError);
}

}  // namespace
}  // namespace s2p
