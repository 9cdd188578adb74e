// The pattern files of Patterns III that `run` and `panels` write into OUT/pattern/:
// pattern.json (GarmentCode), pattern.svg / pattern.pdf (1:1 print), pattern.dxf (DXF-AAMA),
// panels.obj (the remeshed panels placed around the rest body, one group each; same vertex
// order as panels_flat.obj), stitches.json (vertex pairs into panels.obj), body_rest.obj (the
// full fit: it follows the scanned clothes), body_under.obj (the body fitted under the clothes,
// in the same frame: what to sew and drape the panels on) and pattern.png.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "export/pattern_print.h"
#include "export/sewing_pattern.h"
#include "io/scan.h"
#include "pipeline/pipeline.h"

namespace s2p::app {

// The pieces to cut: every flattened panel, a symmetric left/right pair of one garment drawn
// once as "cut 2, mirrored" (its left piece; both stay apart in pattern.json and panels.obj);
// notches at the stitches' match points (their middle; thirds on seams over 40 cm) and at the
// corners where panels meet.
SewingPattern sewingPattern(const PatternResult& pattern, const std::string& date);

// stitches.json's content (vertex ids into panels.obj).
nlohmann::json stitchesToJson(const PatternResult& pattern);
// report.json's "placement" and "stitches" figures.
nlohmann::json placementToJson(const PatternResult& pattern);

void writePatternFiles(const std::filesystem::path& dir, const Scan& scan,
                       const PatternResult& pattern, const PrintOptions& print);
void printPatternFiles(const PatternResult& pattern);

}  // namespace s2p::app
