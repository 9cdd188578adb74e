// The pipeline on a scan nobody labelled, as `run` and `demo` perform it: fit the body, then
// segment the garments with the full fit's feature points; every stage timed for report.json.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "app/commands.h"
#include "app/segment_output.h"
#include "fit/scan_fit.h"

namespace s2p::app {

struct RunOutput {
  ScanFit fit;
  SegmentOutput segment;
  std::vector<std::pair<std::string, double>> stages;  // (stage, seconds): fit, segment
};

// Computes everything and writes nothing (bad input fails before any output exists).
RunOutput runPipeline(const LoadedScan& scan, const BodyModel& model,
                      const ScanFitOptions& fitOptions, const SegmentationOptions& segmentOptions,
                      Progress& progress);

// OUT/fit/ (writeFit), OUT/segment/ (writeSegmentation) and OUT/report.json: stage timings,
// warnings and what was found (garments, one-piece, occlusion).
void writeRun(const std::filesystem::path& dir, const LoadedScan& scan, const BodyModel& model,
              const RunOutput& run, Progress& progress);
nlohmann::json runReport(const LoadedScan& scan, const BodyModel& model, const RunOutput& run);
void printRun(const RunOutput& run, const std::filesystem::path& dir);

}  // namespace s2p::app
