// Seams and panels (§6.1) on synthetic scans segmented with their true body: the garment types
// and panel sets the truth names, every panel a disk, partners one to one, the armhole seam
// through the armpit and the crotch seam gone from a skirt.
#include <gtest/gtest.h>

#include "eval/pattern_metrics.h"
#include "pattern/panels.h"
#include "segment/segmentation.h"
#include "synth_cases.h"

namespace s2p {
namespace {

struct PatternRun {
  Segmentation seg;
  PanelsResult panels;
  PatternScore score;
};

PatternRun patternOf(const SynthCase& c) {
  PatternRun r;
  r.seg = segmentScan(c.scan.scan.mesh, c.scan.scan.colour, c.body.posed.mesh, c.body.features);
  PanelsInput in;
  for (const GarmentPiece& g : r.seg.garments)
    in.garments.push_back({g.name,
                           g.name == "onepiece"      ? GarmentKind::OnePiece
                           : g.label == Label::Lower ? GarmentKind::Lower
                                                     : GarmentKind::Upper,
                           g.mesh, g.faceOrigin});
  in.body = c.body.posed.mesh;
  in.features = c.body.features;
  in.canonical = c.body.posed.canonical;
  r.panels = runPanels(in);
  r.score = scorePattern(r.panels, c.scan.truth, in.body, in.canonical);
  return r;
}

void expectSound(const PatternScore& s) {
  EXPECT_EQ(s.disks, s.panels);
  EXPECT_EQ(s.unpartnered, 0);
  EXPECT_LT(s.maxPartnerMismatch, 0.005);
  for (const GarmentPatternScore& g : s.garments) {
    EXPECT_TRUE(g.typeOk) << g.truthGarment << ": " << g.foundType << " for " << g.expectedType;
    EXPECT_TRUE(g.panelsOk) << g.truthGarment << ": " << ::testing::PrintToString(g.foundPanels);
  }
}

TEST(Panels, TshirtTrousersGiveTheirPanelsAndTheArmholeMeetsTheArmpit_Slow) {
  const PatternRun r = patternOf(synthCase("tshirt_trousers", 12000));
  expectSound(r.score);
  ASSERT_EQ(r.score.armholeToArmpit.size(), 2u);
  for (const auto& [name, d] : r.score.armholeToArmpit) EXPECT_LT(std::abs(d), 0.03) << name;
  for (const auto& [name, d] : r.score.mirrorAreaDiff) EXPECT_LT(d, 0.03) << name;
  for (const auto& [name, a] : r.score.sideSeamAngle) EXPECT_LT(a, 20) << name;
}

TEST(Panels, ASkirtLosesItsCrotchSeamAndATopWithoutSleevesItsArmholes_Slow) {
  const PatternRun r = patternOf(synthCase("sleeveless_knee_skirt", 12000));
  expectSound(r.score);
  for (const GarmentPanels& g : r.panels.garments) {
    for (const SeamLine& s : g.seams) {
      if (s.kind == SeamKind::LeftRight || s.kind == SeamKind::Armhole) {
        EXPECT_FALSE(s.kept) << g.name << " " << s.name;
      }
    }
  }
}

}  // namespace
}  // namespace s2p
