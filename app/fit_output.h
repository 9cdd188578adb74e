// What `fit` (and the pipeline's fit step) writes: body_fit.obj, body_full.obj, body.json and
// the previews; and the fitted body as the segmentation's input.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "app/segment_output.h"
#include "fit/scan_fit.h"
#include "io/scan.h"

namespace s2p::app {

// bodyToJson of the fit plus "to_scan_file" (4×4, row-major: the posed body → the scan file's
// frame and units), "full_mesh" (the non-rigid fit's file, for `segment --body`),
// "measurements" (rest body) and "fit" (orientation, timings, warnings). "joints" and
// "canonical" are in the scan file's frame, as in truth.json, so `eval --body` compares them.
nlohmann::json fitBodyJson(const BodyModel& model, const ScanFit& fit, const Scan& scan);

// Writes body_fit.obj, body_full.obj (scan file's frame), body.json, fit_front.png and
// fit_side.png (the scan semi-transparent over the body) into `dir` (created).
void writeFit(const std::filesystem::path& dir, const Scan& scan, const BodyModel& model,
              const ScanFit& fit);
void printFit(const ScanFit& fit);

// The start the fit was finished from and, with multi-start, every start's score:
// {"name": …, "score_mm": …, "scores_mm": {name: mm, …}} (scores: pose_start.h).
nlohmann::json fitStartJson(const ScanFit& fit);

}  // namespace s2p::app
