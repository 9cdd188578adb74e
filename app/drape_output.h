// OUT/drape/ of `run` and `demo` (issue 19): draped.obj (the sewn, draped garments on
// pattern/body_rest.obj, one group per panel), drape_compare.png (the draped garments coloured by
// their distance to the scanned ones, front and back, with a legend, beside the scanned garments
// in the same pose) and the "drape" section of report.json.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>

#include "pipeline/pipeline.h"

namespace s2p::app {

// Whether OUT/drape/ holds a drape: only a run that sewed and settled is one. A drape that
// failed or did not settle in its step budget is reported (report.json) and never written.
bool drapeWritten(const PipelineResult& run);
// Writes draped.obj and drape_compare.png when drapeWritten; otherwise removes those two files
// if an earlier run left them (they would not be this pattern's drape). A drape that ran and did
// not settle leaves its last state as unsettled.obj (never draped.obj). Pattern files are not
// touched either way.
void writeDrape(const std::filesystem::path& dir, const PipelineResult& run);
nlohmann::json drapeToJson(const PipelineResult& run);
void printDrape(const PipelineResult& run);

}  // namespace s2p::app
