// What the pattern stage writes into OUT/pattern/: panels.json (panels, edges with tags and
// partners, corners, garment types, seams removed and why), panels_3d.obj (one group per
// panel) and panels.png (the scan with the panels coloured and the seam lines drawn).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "app/segment_output.h"
#include "eval/pattern_metrics.h"
#include "io/scan.h"
#include "pattern/flat_pattern.h"
#include "pattern/panels.h"

namespace s2p::app {

// All coordinates in the scan file's frame (toInput).
// The figures of a pattern score that say where the seams landed, as pattern_score.json and the
// fit-suite report write them: armhole_minus_armpit_mm, mirror_area_diff,
// mirror_cloth_area_diff, side_seam_degrees, side_seam_limb_degrees.
nlohmann::json patternScoreFigures(const PatternScore& ps);

nlohmann::json panelsToJson(const PanelsResult& r, const Eigen::Affine3d& toInput);

void writePanels(const std::filesystem::path& dir, const Scan& scan, const PanelsResult& r);
void printPanels(const PanelsResult& r);

// Patterns II: the per-panel flattening figures and the stitched pairs' 2D lengths.
nlohmann::json flatPatternToJson(const PanelsResult& panels, const FlatPatternResult& flat);
// panels_flat.obj (the remeshed panels laid out at z = 0, one group each, vertex colours and,
// for a textured scan, texture coordinates from the scan), pattern_strain.png, flat.json.
void writeFlatPattern(const std::filesystem::path& dir, const Scan& scan, const PanelsResult& panels,
                      const FlatPatternResult& flat);
// The scan's colour at every remeshed vertex of a flattened panel (#V×3 sRGB; light grey when
// the scan has no colour).
Eigen::MatrixX3d remeshedColours(const Scan& scan, const FlatPanel& fp);
void printFlatPattern(const PanelsResult& panels, const FlatPatternResult& flat);

}  // namespace s2p::app
