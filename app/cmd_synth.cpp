// synth and bench-suite: synthetic clothed scans with ground truth (src/synth), one preset or the
// whole benchmark suite.
#include <fmt/format.h>

#include <chrono>
#include <map>
#include <memory>

#include "app/commands.h"
#include "body/body_source.h"
#include "core/error.h"
#include "core/mesh_topology.h"
#include "synth/presets.h"
#include "synth/synthesize.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

struct SynthArgs {
  bool list = false;
  std::string preset;
  std::uint64_t seed = 1;
  int vertices = 0;
  std::string format = "ply";
  std::string model = "mannequin";
  double yaw = 0;
  bool noPreviews = false;
  std::string outDir;
};

struct SuiteArgs {
  std::string suite = "bench/suite.json";
  bool skipScaling = false;
  std::string model;  // replaces every entry's body source when set
  bool noPreviews = false;
  std::string only;
  std::string outDir;
};

SynthFormat formatOf(const std::string& name) {
  const auto f = parseSynthFormat(name);
  if (!f) throw CLI::ValidationError("--format", "unknown format '" + name + "': use ply or obj");
  return *f;
}

// What the suite table and report show about one generated scan.
struct ScanSummary {
  int vertices = 0, faces = 0, components = 0, boundaryLoops = 0;
  bool closed = false, manifold = false;
  std::string labels;  // labels present on faces, comma-separated
};

ScanSummary summarise(const SynthScan& s) {
  ScanSummary r;
  const TriMesh& m = s.scan.mesh;
  const MeshTopology topo(m.F, m.numVertices());
  r.vertices = m.numVertices();
  r.faces = m.numFaces();
  r.components = topo.numComponents();
  r.boundaryLoops = static_cast<int>(topo.boundaryLoops().size());
  r.closed = topo.isClosed();
  r.manifold = topo.manifoldness().isManifold();
  for (int l = 0; l < kNumLabels; ++l)
    if ((s.faceLabel.array() == l).any())
      r.labels += (r.labels.empty() ? "" : ",") + std::string(toString(static_cast<Label>(l)));
  return r;
}

int runList() {
  for (const Preset& p : presets())
    fmt::print("{:<24} {:>6} vertices  {}\n", p.name, p.options.geometry.targetVertices,
               p.description);
  return 0;
}

int runSynth(const SynthArgs& a, Progress& progress) {
  if (a.list) return runList();
  if (a.preset.empty())
    throw CLI::ValidationError("--preset", "name a preset (scan2pattern synth --list shows them)");
  if (a.outDir.empty()) throw CLI::ValidationError("-o", "give the output folder with -o DIR");
  const SynthFormat format = formatOf(a.format);
  SynthOptions o = presetOptions(a.preset);
  o.seed = a.seed;
  if (a.model != o.bodySource && !o.shape.empty()) {
    progress.message("note: preset " + a.preset + "'s body shape (" + o.shape +
                     ") is in mannequin parameters; " + a.model + " keeps its mean shape");
    o.shape.clear();
  }
  o.bodySource = a.model;
  o.yawDegrees = a.yaw;
  if (a.vertices != 0) o.geometry.targetVertices = a.vertices;
  const auto t0 = std::chrono::steady_clock::now();
  const SynthScan s = synthesize(o, progress);
  progress.begin("write " + a.outDir);
  const auto written =
      writeSynthScan(a.outDir, s, format, {.previews = !a.noPreviews, .previewHeightPx = 800});
  progress.end();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const ScanSummary r = summarise(s);
  fmt::print(
      "preset {} seed {}: {} vertices, {} faces, {} component(s), {}, {}, labels {} ({:.1f} s)\n",
      a.preset, a.seed, r.vertices, r.faces, r.components,
      r.closed ? "closed" : fmt::format("{} hole(s)", r.boundaryLoops),
      r.manifold ? "manifold" : "NOT manifold", r.labels, seconds);
  std::string names;
  for (const auto& p : written) names += (names.empty() ? "" : ", ") + p.filename().string();
  fmt::print("wrote {}/: {}\n", a.outDir, names);
  return 0;
}

int runSuite(const SuiteArgs& a, Progress& progress) {
  if (a.outDir.empty()) throw CLI::ValidationError("-o", "give the output folder with -o DIR");
  const std::vector<SuiteEntry> entries = readSuite(a.suite);
  std::map<std::string, BodyModel> models;  // loaded once per source
  json report = json::array();
  fmt::print("{:<24} {:>9} {:>9} {:>8} {:>8}  {:<6} {:<8} {:>5}  {}\n", "name", "vertices", "faces",
             "gen. s", "write s", "closed", "manifold", "comp.", "labels");
  int generated = 0;
  for (const SuiteEntry& e : entries) {
    if ((a.skipScaling && e.scaling) || (!a.only.empty() && e.name != a.only)) continue;
    SynthOptions o = e.options();
    if (!a.model.empty() && a.model != o.bodySource) {
      if (!o.shape.empty())
        progress.message("note: entry " + e.name + "'s body shape (" + o.shape +
                         ") is in mannequin parameters; " + a.model + " keeps its mean shape");
      o.shape.clear();
      o.bodySource = a.model;
    }
    if (!models.count(o.bodySource)) models.emplace(o.bodySource, loadBodyModel(o.bodySource));
    progress.message(fmt::format("suite entry {} (preset {}, seed {}, {} vertices)", e.name,
                                 e.preset, e.seed, o.geometry.targetVertices));
    const auto t0 = std::chrono::steady_clock::now();
    const SynthScan s = synthesize(models.at(o.bodySource), o, progress);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto t1 = std::chrono::steady_clock::now();
    writeSynthScan(fs::path(a.outDir) / e.name, s, e.format,
                   {.previews = !a.noPreviews, .previewHeightPx = 800});
    const double writeSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    const ScanSummary r = summarise(s);
    fmt::print("{:<24} {:>9} {:>9} {:>8.2f} {:>8.2f}  {:<6} {:<8} {:>5}  {}\n", e.name, r.vertices,
               r.faces, seconds, writeSeconds, r.closed ? "yes" : "no", r.manifold ? "yes" : "no",
               r.components, r.labels);
    std::fflush(stdout);
    report.push_back({{"name", e.name},
                      {"preset", e.preset},
                      {"seed", e.seed},
                      {"target_vertices", o.geometry.targetVertices},
                      {"vertices", r.vertices},
                      {"faces", r.faces},
                      {"generate_seconds", seconds},
                      {"write_seconds", writeSeconds},
                      {"closed", r.closed},
                      {"boundary_loops", r.boundaryLoops},
                      {"manifold", r.manifold},
                      {"components", r.components},
                      {"labels", r.labels},
                      {"scaling", e.scaling}});
    ++generated;
  }
  if (generated == 0)
    throw InputError(a.only.empty() ? a.suite + ": no entries to generate"
                                    : "no suite entry named '" + a.only + "' in " + a.suite);
  writeJson(fs::path(a.outDir) / "suite_report.json", report);
  fmt::print("wrote {} scans to {}/<name>/ and {}/suite_report.json\n", generated, a.outDir,
             a.outDir);
  return 0;
}

}  // namespace

void addSynthCommands(CLI::App& app, Commands& out) {
  auto sa = std::make_shared<SynthArgs>();
  auto* cmd = app.add_subcommand(
      "synth",
      "Synthesise a scan of a clothed person with ground truth: one fused closed surface with "
      "colours, per-vertex and per-face labels (skin, upper, lower, shoes, hair, other, gap) and "
      "truth.json (garments, true boundaries, the body under the clothes)");
  cmd->add_flag("--list", sa->list, "List the presets with a one-line description each");
  cmd->add_option("--preset", sa->preset, "Preset name (see --list)");
  cmd->add_option("--seed", sa->seed, "Random seed: the same seed gives byte-identical files")
      ->capture_default_str();
  cmd->add_option("--vertices", sa->vertices,
                  "Target vertex count (default: the preset's, 7k to 50k)")
      ->check(CLI::Range(0, 5'000'000));
  cmd->add_option("--format", sa->format,
                  "ply: scan.ply with colours and labels; obj: scan.obj + scan.mtl + scan.png "
                  "(texture atlas) and labels.ply")
      ->capture_default_str();
  cmd->add_option("--model", sa->model, "Body source: mannequin, mpfb2:DIR or smpl:FILE.npz")
      ->capture_default_str();
  cmd->add_option("--yaw", sa->yaw, "Rotate scan and truth about +Y by this many degrees")
      ->capture_default_str();
  cmd->add_flag("--no-previews", sa->noPreviews, "Skip preview_scan.png and preview_labels.png");
  cmd->add_option("-o,--output", sa->outDir, "Output folder");
  cmd->footer(
      "Writes into DIR: scan.ply (or scan.obj/.mtl/.png and labels.ply), truth.json,\n"
      "preview_scan.png (front and back as scanned) and preview_labels.png (by label: skin tan,\n"
      "upper red, lower blue, shoes dark grey, hair brown, other green, gap yellow).\n"
      "Example: scan2pattern synth --preset dress --seed 3 --vertices 20000 -o out/dress");
  out.push_back({cmd, [sa](Progress& progress) { return runSynth(*sa, progress); }});

  auto ua = std::make_shared<SuiteArgs>();
  auto* suite = app.add_subcommand(
      "bench-suite",
      "Generate every entry of the benchmark suite into DIR/<name>/ (scan, truth, previews) and "
      "print a table: vertices, seconds, closed/manifold/components, labels present");
  suite->add_option("--suite", ua->suite, "Suite file")->capture_default_str();
  suite->add_flag("--skip-scaling", ua->skipScaling, "Leave out the 200k and 1M scaling entries");
  suite->add_option("--only", ua->only, "Generate only the entry of this name");
  suite->add_option("--model", ua->model,
                    "Body source for every entry instead of the suite's (e.g. mpfb2:DIR)");
  suite->add_flag("--no-previews", ua->noPreviews, "Skip the preview PNGs");
  suite->add_option("-o,--output", ua->outDir, "Output folder")->required();
  out.push_back({suite, [ua](Progress& progress) { return runSuite(*ua, progress); }});
}

}  // namespace s2p::app
