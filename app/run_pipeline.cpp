#include "app/run_pipeline.h"

#include <fmt/format.h>
#include <tbb/task_group.h>

#include <chrono>
#include <functional>
#include <future>
#include <utility>

#include "app/drape_output.h"
#include "app/fit_output.h"
#include "app/pattern_files.h"
#include "app/pattern_output.h"
#include "core/error.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

json segmentationSummary(const Segmentation& s) {
  json garments = json::array();
  for (const GarmentPiece& g : s.garments)
    garments.push_back({{"name", g.name}, {"occluded", g.occluded}, {"faces", g.mesh.numFaces()}});
  json boundaries = json::array();
  for (const BoundaryReport& b : s.boundaries)
    boundaries.push_back({{"name", b.name},
                          {"iterations", b.iterations},
                          {"converged", b.converged},
                          {"curves", b.finalCurves.size()}});
  json held = json::array();
  for (const HeldObject& o : s.heldObjects)
    held.push_back({{"area_m2", o.area}, {"max_offset_m", o.maxOffset}});
  return {{"layout", toString(s.layout)},
          {"one_piece", s.layout == GarmentLayout::OnePiece},
          {"hair_area_m2", s.hairArea},
          {"held_objects", held},
          {"occlusion", toString(s.occlusion)},
          {"shoes", s.shoes},
          {"garments", garments},
          {"boundaries", boundaries}};
}

}  // namespace

// === EarlyWriters

struct EarlyWriters::State {
  fs::path out, staging;
  bool outExisted = false;
  const LoadedScan& scan;
  const BodyModel& model;
  std::vector<std::pair<std::string, std::future<void>>> writers;  // (subfolder, its writer)
  bool committed = false;

  State(fs::path o, const LoadedScan& s, const BodyModel& m)
      : out(std::move(o)), staging(out / ".staging"), scan(s), model(m) {}

  // Starts `write` on a thread of its own into staging/sub (made here, so that no two race).
  void start(const std::string& sub, std::function<void(const fs::path&)> write) {
    std::error_code ec;
    if (writers.empty()) {
      outExisted = fs::exists(out, ec);
      fs::remove_all(staging, ec);
    }
    if (!fs::create_directories(staging / sub, ec) && ec) failed("make", staging / sub, ec);
    writers.emplace_back(
        sub, std::async(std::launch::async,
                        [write = std::move(write), dir = staging / sub] { write(dir); }));
  }
  [[noreturn]] static void failed(const char* what, const fs::path& path, std::error_code ec) {
    throw IoError("cannot " + std::string(what) + " the output folder " + path.string() + ": " +
                  ec.message() + "; check its permissions and the free disk space");
  }
  // Waits for every writer; the first one's exception, if any.
  std::exception_ptr wait() {
    std::exception_ptr first;
    for (auto& [sub, w] : writers) try {
        if (w.valid()) w.get();
      } catch (...) {
        if (!first) first = std::current_exception();
      }
    return first;
  }
};

EarlyWriters::EarlyWriters(fs::path out, const LoadedScan& scan, const BodyModel& model)
    : state_(std::make_unique<State>(std::move(out), scan, model)) {}

EarlyWriters::~EarlyWriters() {
  state_->wait();
  if (state_->committed || state_->writers.empty()) return;
  std::error_code ec;
  fs::remove_all(state_->staging, ec);
  if (!state_->outExisted) fs::remove(state_->out, ec);  // only when left empty
}

void EarlyWriters::fitDone(const ScanFit& fit) {
  auto copy = std::make_shared<const ScanFit>(fit);
  State& s = *state_;
  s.start("fit", [&s, copy](const fs::path& dir) { writeFit(dir, s.scan.scan, s.model, *copy); });
}

void EarlyWriters::segmentationDone(const Segmentation& seg) {
  auto copy = std::make_shared<const SegmentOutput>(SegmentOutput{seg, "curve"});
  State& s = *state_;
  s.start("segment",
          [&s, copy](const fs::path& dir) { writeSegmentation(dir, s.scan.scan, *copy); });
}

void EarlyWriters::commit() {
  State& s = *state_;
  if (const std::exception_ptr e = s.wait()) std::rethrow_exception(e);
  std::error_code ec;
  for (const auto& [sub, w] : s.writers) {
    fs::remove_all(s.out / sub, ec);
    if (ec) State::failed("replace", s.out / sub, ec);
    fs::rename(s.staging / sub, s.out / sub, ec);
    if (ec) State::failed("move into place", s.out / sub, ec);
  }
  if (!s.writers.empty()) fs::remove_all(s.staging, ec);
  s.committed = true;
}

// === The run

RunOutput runPipeline(const LoadedScan& scan, const BodyModel& model,
                      const ScanFitOptions& fitOptions, const SegmentationOptions& segmentOptions,
                      Progress& progress, const DrapeStageOptions& drape,
                      const PatternOptions& pattern, EarlyWriters* early) {
  PipelineOptions options;
  options.pattern = pattern;
  options.fit = fitOptions;
  options.segment = segmentOptions;
  options.drape = drape;
  if (early) {
    options.onFit = [early](const ScanFit& fit) { early->fitDone(fit); };
    options.onSegmentation = [early](const Segmentation& seg) { early->segmentationDone(seg); };
  }
  RunOutput out;
  static_cast<PipelineResult&>(out) = s2p::runPipeline(scan.scan, model, options, progress);
  out.segment = {std::move(out.segmentation), "curve"};
  return out;
}

json runReport(const LoadedScan& scan, const BodyModel& model, const RunOutput& run) {
  const ScanFit& fit = run.fit;
  const Segmentation& seg = run.segment.segmentation;
  std::vector<std::string> warnings = scan.normalize.warnings;
  for (const auto& w : scan.read.warnings) warnings.push_back(w);
  for (const auto& w : fit.warnings) warnings.push_back("fit: " + w);
  for (const auto& n : seg.notes) warnings.push_back("segment: " + n);
  for (const auto& w : run.pattern.panels.warnings) warnings.push_back("pattern: " + w);
  for (const auto& w : run.pattern.flat.warnings) warnings.push_back("pattern: " + w);
  for (const auto& w : run.pattern.placement.warnings) warnings.push_back("placement: " + w);
  for (const auto& w : run.pattern.stitches.warnings) warnings.push_back("stitches: " + w);
  for (const auto& w : run.drape.warnings) warnings.push_back(w);
  json pattern = json::array();
  for (const GarmentPanels& g : run.pattern.panels.garments) {
    json panels = json::array();
    for (int p : g.panels) panels.push_back(run.pattern.panels.panels[p].name);
    pattern.push_back(
        {{"garment", g.name}, {"type", g.type}, {"panels", panels}, {"notes", g.notes}});
  }
  json stages = json::array();
  stages.push_back({{"stage", "read"}, {"seconds", scan.read.seconds}});
  stages.push_back({{"stage", "normalise"}, {"seconds", scan.normalizeSeconds}});
  for (const auto& [name, s] : run.stages) stages.push_back({{"stage", name}, {"seconds", s}});
  json fitTimings = json::object();
  for (const auto& [name, s] : fit.timings) fitTimings[name] = s;
  return {{"scan", scan.scan.sourcePath},
          {"model", model.source},
          {"stages", stages},
          {"fit",
           {{"timings", fitTimings},
            {"yaw_degrees", fit.orientation.yaw * 180 / M_PI},
            {"orientation_confidence", fit.orientation.confidence},
            {"initialisation", fit.initialisation},
            {"start", fitStartJson(fit)},
            {"inside_or_within_5mm", fit.fit.insideOrNear}}},
          {"found", segmentationSummary(seg)},
          {"pattern", pattern},
          {"pattern_error", run.patternErrorMessage},
          {"flat_pattern", flatPatternToJson(run.pattern.panels, run.pattern.flat)},
          {"placement", placementToJson(run.pattern)},
          {"drape", drapeToJson(run)},
          {"warnings", warnings},
          {"outputs",
           {{"fit",
             "fit/: body_fit.obj, body_full.obj, body.json, fit_front.png, "
             "fit_side.png"},
            {"segment", "segment/: segmentation.ply, " + garmentFileList(seg) +
                            "garments.json, boundaries.json, segment_boundaries.png, "
                            "segment_labels.png"},
            {"pattern",
             "pattern/: pattern.json (GarmentCode), pattern.svg, "
             "pattern.pdf, pattern.dxf, pattern.png, panels.obj, "
             "stitches.json, body_rest.obj, panels.json, panels_3d.obj, "
             "panels.png, flat.json, panels_flat.obj, "
             "pattern_strain.png"},
            {"drape", drapeWritten(run) ? "drape/: draped.obj, drape_compare.png" : ""}}}};
}

void writeRun(const fs::path& dir, const LoadedScan& scan, const BodyModel& model,
              const RunOutput& run, Progress& progress, const PrintOptions& print,
              EarlyWriters* early) {
  progress.begin("write outputs");
  // The folders' writers read the run and write files of their own, mostly pictures and PDFs
  // drawn on one thread each: they run side by side (on a 50k scan, 3.3 s one after another).
  // Each folder is made first, so that no two writers race to create it.
  // fit/ and segment/ are the early writers' when there are some.
  fs::create_directories(dir / "pattern");
  if (!early)
    for (const char* sub : {"fit", "segment"}) fs::create_directories(dir / sub);
  // Each writer runs as a task that keeps its own copy of what to call and where its error goes.
  const auto guarded = [](std::exception_ptr* error, std::function<void()> write) {
    return [error, write = std::move(write)] {
      try {
        write();
      } catch (const Error&) {
        *error = std::current_exception();
      }
    };
  };
  const auto fit = [&] { writeFit(dir / "fit", scan.scan, model, run.fit); };
  const auto segment = [&] { writeSegmentation(dir / "segment", scan.scan, run.segment); };
  const auto panels = [&] { writePanels(dir / "pattern", scan.scan, run.pattern.panels); };
  const auto flat = [&] {
    writeFlatPattern(dir / "pattern", scan.scan, run.pattern.panels, run.pattern.flat);
  };
  const auto files = [&] {
    writePatternFiles(dir / "pattern", scan.scan, run.pattern, print);
    writeDrape(dir / "drape", run);
  };
  std::exception_ptr fitError, segmentError, panelsError, flatError, filesError;
  tbb::task_group writers;
  if (!early) {
    writers.run(guarded(&fitError, fit));
    writers.run(guarded(&segmentError, segment));
  }
  if (!run.patternError) {
    writers.run(guarded(&panelsError, panels));
    writers.run(guarded(&flatError, flat));
    writers.run(guarded(&filesError, files));
  }
  if (early) try {
      early->commit();
    } catch (const Error&) {
      fitError = std::current_exception();
    }
  writers.wait();
  if (fitError) std::rethrow_exception(fitError);
  if (segmentError) std::rethrow_exception(segmentError);
  // A pattern file that cannot be written still leaves report.json beside fit/ and segment/.
  writeJson(dir / "report.json", runReport(scan, model, run));
  progress.end();
  for (const std::exception_ptr& e : {panelsError, flatError, filesError})
    if (e) std::rethrow_exception(e);
}

void printRun(const RunOutput& run, const fs::path& dir) {
  printFit(run.fit);
  printSegmentation(run.segment.segmentation);
  printPanels(run.pattern.panels);
  printFlatPattern(run.pattern.panels, run.pattern.flat);
  printPatternFiles(run.pattern);
  printDrape(run);
  fmt::print(
      "wrote {0}/report.json; pictures: {0}/fit/fit_front.png, {0}/fit/fit_side.png, "
      "{0}/segment/segment_boundaries.png, {0}/segment/segment_labels.png, "
      "{0}/pattern/panels.png, {0}/pattern/pattern_strain.png; the pattern: "
      "{0}/pattern/pattern.png, pattern.pdf, pattern.svg, pattern.dxf, pattern.json\n",
      dir.string());
  if (drapeWritten(run))
    fmt::print("the drape: {0}/drape/drape_compare.png, {0}/drape/draped.obj\n", dir.string());
}

}  // namespace s2p::app
