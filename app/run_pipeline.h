// The pipeline on a scan nobody labelled, as `run` and `demo` perform it: fit the body, then
// segment the garments with the full fit's feature points; every stage timed for report.json.
#pragma once

#include <exception>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "app/commands.h"
#include "app/segment_output.h"
#include "fit/scan_fit.h"
#include "pattern/flat_pattern.h"
#include "pattern/panels.h"

namespace s2p::app {

struct RunOutput {
  ScanFit fit;
  SegmentOutput segment;
  PanelsResult panels;    // seams, panels, garment types (§6.1)
  FlatPatternResult flat;  // flattened, outlined, remeshed panels (§6.2)
  // The pattern stage's failure, if any: the fit and segmentation are still written (to look
  // at), then the command rethrows it for its exit code.
  std::exception_ptr patternError;
  std::string patternErrorMessage;
  std::vector<std::pair<std::string, double>> stages;  // (stage, seconds): fit, segment, panels
};

// Computes everything and writes nothing (bad input fails before any output exists).
RunOutput runPipeline(const LoadedScan& scan, const BodyModel& model,
                      const ScanFitOptions& fitOptions, const SegmentationOptions& segmentOptions,
                      Progress& progress);

// OUT/fit/ (writeFit), OUT/segment/ (writeSegmentation), OUT/pattern/ (writePanels) and
// OUT/report.json: stage timings,
// warnings and what was found (garments, one-piece, occlusion).
void writeRun(const std::filesystem::path& dir, const LoadedScan& scan, const BodyModel& model,
              const RunOutput& run, Progress& progress);
nlohmann::json runReport(const LoadedScan& scan, const BodyModel& model, const RunOutput& run);
void printRun(const RunOutput& run, const std::filesystem::path& dir);

}  // namespace s2p::app
