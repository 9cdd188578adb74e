// Patterns I against the truth of a synthetic scan: garment types and panel sets, and where the
// seams landed — every panel a disk, every seam edge with one partner of the same length,
// mirrored panels of equal area, the armhole seams' lowest points at the body's armpit, side
// seams in the body's coronal (side) plane.
#pragma once

#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "core/tri_mesh.h"
#include "pattern/panels.h"
#include "synth/truth.h"

namespace s2p {

struct GarmentPatternScore {
  std::string truthGarment, predictedGarment;  // predictedGarment empty: not found
  std::string expectedType, foundType;
  std::vector<std::string> expectedPanels, foundPanels;  // sorted
  bool typeOk = false, panelsOk = false;
};

struct PatternScore {
  std::vector<GarmentPatternScore> garments;
  bool allTypesOk = true, allPanelsOk = true;
  int panels = 0, disks = 0;
  int seamEdges = 0, unpartnered = 0;
  double maxPartnerMismatch = 0;  // max |L1 − L2| / max(L1, L2) over partner edge pairs
  // |A_left − A_right| / max(A_left, A_right) per mirrored pair ("upper:sleeve", ...)
  std::vector<std::pair<std::string, double>> mirrorAreaDiff;
  // The same with each panel's surface first taken through the pattern stage's noise filter
  // (pattern/panel_denoise.h, 5 mm): the cloth's area. A scanner's noise adds 10–20 % to a
  // panel's area, and not equally on both sides of a scan (noise_holes: 21 % on the left
  // sleeve, 12 % on the right), so the raw areas also compare the noise.
  std::vector<std::pair<std::string, double>> mirrorClothAreaDiff;
  // Per armhole seam: lowest point's height minus the body's armpit height on that side (m).
  std::vector<std::pair<std::string, double>> armholeToArmpit;
  // Per side seam: angle (degrees) between its main direction and the body's coronal plane.
  std::vector<std::pair<std::string, double>> sideSeamAngle;
  // The same against the coronal plane of the limb the seam runs along: on a leg, the plane
  // through the hip-to-ankle axis and the body's left-right axis. A trouser seam on a striding
  // leg follows the leg, which is swung out of the body's plane by the stride; on a standing
  // body the two figures are the same.
  std::vector<std::pair<std::string, double>> sideSeamLimbAngle;
  double maxMirrorAreaDiff() const;
  double maxArmholeToArmpit() const;  // of the absolute values
  double maxSideSeamAngle() const;
  double maxMirrorClothAreaDiff() const;
  double maxSideSeamLimbAngle() const;
};

// Scores `r` against the truth's garments (matched by label: the upper, lower or one-piece
// garment with the largest visible area). body: the posed fitted body (closed); canonical its
// canonical points.
PatternScore scorePattern(const PanelsResult& r, const Truth& truth, const TriMesh& body,
                          const Eigen::MatrixX3d& canonical);

}  // namespace s2p
