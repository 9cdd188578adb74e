// The pipeline (src/pipeline) on a scan nobody labelled, as `run` and `demo` perform it, and
// the files it writes: OUT/fit/, OUT/segment/, OUT/pattern/ and report.json.
#pragma once

#include <exception>
#include <filesystem>
#include <memory>
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

// Writes OUT/fit/ and OUT/segment/ as soon as their stage is final, beside the stages that
// follow (the boundaries and the seams run on one core of two). The folders are staged in
// OUT/.staging and moved into place by commit(), so that a run that fails later leaves nothing
// behind: the staging folder is removed, and OUT too when this run made it.
class EarlyWriters {
 public:
  EarlyWriters(std::filesystem::path out, const LoadedScan& scan, const BodyModel& model);
  ~EarlyWriters();  // waits for the writers; removes what is staged unless committed
  EarlyWriters(const EarlyWriters&) = delete;
  EarlyWriters& operator=(const EarlyWriters&) = delete;

  void fitDone(const ScanFit& fit);                // copies the fit, starts writing fit/
  void segmentationDone(const Segmentation& seg);  // copies it, starts writing segment/
  // Waits, rethrows the first writer's error, moves fit/ and segment/ into OUT (replacing the
  // folders of an earlier run there).
  void commit();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Computes everything and writes nothing itself (bad input fails before any output exists);
// with `early`, fit/ and segment/ are staged by it as soon as they are final.
// drape: the drape check after the pattern (off unless asked for: `--drape`).
RunOutput runPipeline(const LoadedScan& scan, const BodyModel& model,
                      const ScanFitOptions& fitOptions, const SegmentationOptions& segmentOptions,
                      Progress& progress, const DrapeStageOptions& drape = {},
                      const PatternOptions& pattern = {}, EarlyWriters* early = nullptr);

// OUT/fit/ (writeFit), OUT/segment/ (writeSegmentation), OUT/pattern/ (writePanels), OUT/drape/
// (writeDrape, when the drape ran) and
// OUT/report.json: stage timings,
// warnings and what was found (garments, one-piece, occlusion).
// With `early` (the writers runPipeline was given), fit/ and segment/ are its, committed here.
void writeRun(const std::filesystem::path& dir, const LoadedScan& scan, const BodyModel& model,
              const RunOutput& run, Progress& progress, const PrintOptions& print = {},
              EarlyWriters* early = nullptr);
nlohmann::json runReport(const LoadedScan& scan, const BodyModel& model, const RunOutput& run);
void printRun(const RunOutput& run, const std::filesystem::path& dir);

}  // namespace s2p::app
