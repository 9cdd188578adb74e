// Seams and panels (§6.1) on synthetic scans segmented with their true body: the garment types
// and panel sets the truth names, every panel a disk, partners one to one, the armhole seam
// through the armpit and the crotch seam gone from a skirt.
#include "pattern/panels.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <string>

#include "eval/pattern_metrics.h"
#include "pattern/body_frame.h"
#include "segment/segmentation.h"
#include "synth_cases.h"

namespace s2p {
namespace {

struct PatternRun {
  Segmentation seg;
  PanelsResult panels;
  PatternScore score;
};

// Lowest height (frame.height) of the panel edges whose name ends with `suffix`, per edge name.
std::map<std::string, double> lowestEdges(const PanelsResult& r, const BodyFrame& frame,
                                          const std::string& suffix) {
  std::map<std::string, double> low;
  for (const Panel& p : r.panels)
    for (const PanelEdge& e : p.edges) {
      if (e.name.size() < suffix.size() ||
          e.name.compare(e.name.size() - suffix.size(), suffix.size(), suffix) != 0)
        continue;
      double& l = low.try_emplace(e.name, std::numeric_limits<double>::infinity()).first->second;
      for (int v : e.vertices) l = std::min(l, frame.height(p.mesh.V.row(v).transpose()));
    }
  return low;
}

PatternRun patternOf(const SynthCase& c, const PanelOptions& options = {}) {
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
  r.panels = runPanels(in, options);
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

// Arms lowered to 18° from the body: a t-shirt's sleeve hangs against the torso's side, and the
// scan joins them along a crease from the cuff up to the armpit, hiding the sleeve's underside
// and the side under the arm. Every seam that parts sleeve from trunk on that surface runs down
// the crease (the armhole's lowest point 11–12 cm below the armpit); with the contact opened and
// the hidden cloth supplied (pattern/contact_opening.h) the armhole passes under the arm: its
// lowest point within 3 cm of the fitted body's armpit on both sides, as the issue asks.
TEST(Panels, LoweredArmsKeepTheArmholeAtTheArmpit_Slow) {
  const SynthCase& c = synthCase("arms_down", 8000);
  const BodyFrame frame(c.body.posed.canonical);
  const auto lowestArmholes = [&](bool open) {
    PanelOptions options;
    options.openFusedContacts = open;
    const PatternRun r = patternOf(c, options);
    expectSound(r.score);
    std::map<std::string, double> below;  // armpit − the armhole's lowest point, per side
    for (const auto& [name, low] : lowestEdges(r.panels, frame, "_armhole")) {
      const std::string side = name.substr(0, name.find('_'));
      below[side] = armpitHeight(c.body.posed.mesh, frame, side == "left") - low;
    }
    return below;
  };
  const std::map<std::string, double> fused = lowestArmholes(false), opened = lowestArmholes(true);
  ASSERT_EQ(fused.size(), 2u);
  ASSERT_EQ(opened.size(), 2u);
  for (const auto& [side, d] : opened) {
    EXPECT_GT(fused.at(side), 0.06) << side << ": the fused crease reaches this far down";
    EXPECT_LT(std::abs(d), 0.03) << side << " armhole, " << fused.at(side) << " m when fused";
  }
}

// Mid-stride: from the crotch down between the legs the left/right function had no sign point,
// and its zero line ran down an inner thigh, leaving a tongue of the other side there (6 trouser
// panels for 4 on this scan).
TEST(Panels, StridingTrousersGiveFourPanels_Slow) {
  const PatternRun r = patternOf(synthCase("walking", 20000, 5));
  expectSound(r.score);
  for (const GarmentPanels& g : r.panels.garments)
    for (const SeamLine& s : g.seams)
      if (s.kind == SeamKind::LeftRight) {
        EXPECT_TRUE(s.kept);
        EXPECT_LT(s.line.length(), 1.2) << "the crotch seam runs front waist → crotch → back waist";
      }
}

// A long-sleeved shirt on arms hanging against the trunk (studio_relaxed): the scan joins each
// sleeve to the side from the armpit to the wrist and the cuffs to the hem. With the cuffs' −1
// as the sleeve's only hold, beside the hem's +1, the trunk's side of the armhole function
// spread over the whole upper sleeve and each sleeve panel was a scrap at the wrist (6 % of the
// shirt). The arm's sign points keep the sleeves whole: each one at least 12 % of the shirt.
TEST(Panels, LongSleevesOnArmsHangingAgainstTheTrunkStaySleeves_Slow) {
  const PatternRun r = patternOf(synthCase("studio_relaxed", 20000));
  expectSound(r.score);
  for (const GarmentPanels& g : r.panels.garments) {
    if (g.kind != GarmentKind::Upper) continue;
    double total = 0;
    for (int p : g.panels) total += r.panels.panels[p].area;
    int sleeves = 0;
    for (int p : g.panels) {
      const Panel& panel = r.panels.panels[p];
      if (panel.name.find("sleeve") == std::string::npos) continue;
      ++sleeves;
      EXPECT_GT(panel.area, 0.12 * total) << panel.name << ": " << panel.area << " of " << total;
    }
    EXPECT_EQ(sleeves, 2);
  }
}

}  // namespace
}  // namespace s2p
