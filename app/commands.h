// The command line's building blocks: every subcommand lives in its own cmd_<name>.cpp and
// registers itself through one add*Command function listed here; main.cpp only builds the
// top-level parser, dispatches and maps errors to exit codes.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>

#include "export/pattern_print.h"
#include <string>
#include <vector>

#include "body/features.h"
#include "core/progress.h"
#include "export/preview.h"
#include "pipeline/pipeline.h"
#include "io/cleanup.h"
#include "io/normalize.h"
#include "io/person_pieces.h"
#include "io/read_scan.h"
#include "io/write_mesh.h"

namespace s2p::app {

// A registered subcommand: its parser and what to run when it was chosen (returns the exit code).
struct Command {
  CLI::App* cli = nullptr;
  std::function<int(Progress&)> run;
};
using Commands = std::vector<Command>;

void addScanCommands(CLI::App& app, Commands& out);  // info, convert, preview
void addBodyCommand(CLI::App& app, Commands& out);   // body
void addDemoCommand(CLI::App& app, Commands& out);   // demo
void addEvalCommand(CLI::App& app, Commands& out);   // eval
void addSynthCommands(CLI::App& app, Commands& out);  // synth, bench-suite
void addSegmentCommand(CLI::App& app, Commands& out);  // segment, segment-suite
void addFitCommands(CLI::App& app, Commands& out);     // fit, run, fit-suite
void addRenderViewsCommand(CLI::App& app, Commands& out);  // render-views
void addPatternCommands(CLI::App& app, Commands& out);  // panels

// === Shared: read + clean + normalise, as every command that takes a SCAN does.

struct LoadedScan {
  Scan scan;
  ReadReport read;
  CleanupReport cleanup;
  NormalizeReport normalize;  // its warnings also carry the pieces' lines (report.json)
  PersonPieces pieces;        // which pieces are the person, what was dropped
  double normalizeSeconds = 0;
};

struct LoadOptions {
  std::string units = "auto";
  std::string up = "auto";
};

void addLoadOptions(CLI::App* cmd, LoadOptions& opt);
LoadedScan loadScan(const std::filesystem::path& path, const LoadOptions& opt, Progress& progress);

// The `info` summary of a loaded scan, and its human-readable form.
nlohmann::json infoJson(const LoadedScan& s);
void printInfo(const nlohmann::json& j);

// "front,back" → views; CLI::ValidationError naming `option` on an unknown name.
std::vector<View> parseViews(const std::string& list, const std::string& option = "--views");
Image renderScan(const Scan& scan, const std::vector<View>& views, int heightPx);
MeshAttributes colourAttributes(const Scan& scan);
void writeJson(const std::filesystem::path& path, const nlohmann::json& j);
// Checks, before any work and without creating anything, that `dir` can be written (or created
// and written): IoError naming the folder otherwise.
void requireWritableFolder(const std::filesystem::path& dir);
// --noise-filter MM for the pattern stage.
void addPatternOptions(CLI::App* cmd, PatternOptions& pattern);
// --seam-allowance MM and --paper a4|letter for the pattern files.
void addPrintOptions(CLI::App* cmd, PrintOptions& print);
// Reads a JSON file; IoError when it cannot be read, FormatError (naming `what`) when not JSON.
nlohmann::json readJsonFile(const std::filesystem::path& path, const std::string& what);

// The truth.json of every entry of a bench-suite folder (only the entry named `only` when not
// empty), sorted; IoError when the folder or its entries are missing.
std::vector<std::filesystem::path> suiteTruths(const std::filesystem::path& suiteDir,
                                               const std::string& only = {});

// Feature splines, sign points and region points drawn over a body (paper Fig. 4 and Fig. 11).
Scene featureScene(const TriMesh& mesh, const FeatureSet& fs);

}  // namespace s2p::app
