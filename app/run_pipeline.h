// The pipeline (src/pipeline) on a scan nobody labelled, as `run` and `demo` perform it, and
// the files it writes: OUT/fit/, OUT/segment/, OUT/pattern/ and report.json.
#pragma once

#include <exception>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "app/commands.h"
#include "app/segment_output.h"
#include "export/pattern_print.h"
#include "fit/scan_fit.h"
#include "pipeline/pipeline.h"

namespace s2p::app {

// The library's result (pipeline.h), with the segmentation moved into `segment` (what the
// segmentation writer takes).
struct RunOutput : PipelineResult {
  SegmentOutput segment;
};

// Computes everything and writes nothing (bad input fails before any output exists).
// drape: the drape check after the pattern (off unless asked for: `--drape`).
RunOutput runPipeline(const LoadedScan& scan, const BodyModel& model,
                      const ScanFitOptions& fitOptions, const SegmentationOptions& segmentOptions,
                      Progress& progress, const DrapeStageOptions& drape = {},
                      const PatternOptions& pattern = {});

// OUT/fit/ (writeFit), OUT/segment/ (writeSegmentation), OUT/pattern/ (writePanels), OUT/drape/
// (writeDrape, when the drape ran) and
// OUT/report.json: stage timings,
// warnings and what was found (garments, one-piece, occlusion).
void writeRun(const std::filesystem::path& dir, const LoadedScan& scan, const BodyModel& model,
              const RunOutput& run, Progress& progress, const PrintOptions& print = {});
nlohmann::json runReport(const LoadedScan& scan, const BodyModel& model, const RunOutput& run);
void printRun(const RunOutput& run, const std::filesystem::path& dir);

}  // namespace s2p::app
