#include "pipeline/pipeline.h"

#include <fmt/format.h>

#include <chrono>

#include "core/error.h"
#include "pipeline/limb_straightening.h"

namespace s2p {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace

PosedFeatures fittedFeatures(const BodyModel& model, const ScanFit& fit) {
  PosedFeatures out;
  out.body = fit.fullInScanFrame();
  out.features = computeFeatures(model, fit.fit.params.shape);
  out.canonical = fit.canonicalInScanFrame();
  out.model = std::shared_ptr<const BodyModel>(&model, [](const BodyModel*) {});
  out.params = fit.fit.params;
  out.toGarments = fit.toScan;
  return out;
}

PanelsInput panelsInput(const Segmentation& segmentation, const PosedFeatures& body) {
  PanelsInput in;
  for (const GarmentPiece& g : segmentation.garments) {
    GarmentKind kind = GarmentKind::Upper;
    if (g.name == "onepiece" || segmentation.layout == GarmentLayout::OnePiece)
      kind = GarmentKind::OnePiece;
    else if (g.label == Label::Lower)
      kind = GarmentKind::Lower;
    in.garments.push_back({g.name, kind, g.mesh, g.faceOrigin});
  }
  in.body = body.body;
  in.features = body.features;
  in.canonical = body.canonical;
  // No body-part constraints on the armhole yet (`panels --armhole-body-parts` only): with them
  // the synthetic striding t-shirt's right sleeve came apart (pipeline Panels.StridingTrousers).
  return in;
}

PatternResult runPattern(const PanelsInput& input, const PosedFeatures& body, const TriMesh& scan,
                         const PatternOptions& options, Progress& progress) {
  PatternResult r;
  auto t = Clock::now();
  progress.begin("seams and panels");
  r.panels = runPanels(input, options.panels);
  progress.end();
  r.stages.emplace_back("panels", secondsSince(t));
  t = Clock::now();
  progress.begin("flatten, outline and remesh the panels");
  const std::vector<PanelReshape> reshape =
      options.straightenLimbs ? straightenLimbs(r.panels, body, options.straightening)
                              : std::vector<PanelReshape>{};
  r.flat = runFlatPattern(r.panels, scan, BodyFrame(input.canonical), options.flat, reshape);
  progress.end();
  r.stages.emplace_back("flatten", secondsSince(t));
  t = Clock::now();
  progress.begin("place the panels around the rest body, stitches");
  const Placement* placement = nullptr;
  if (body.model) {
    PlacementInput pin{body.model.get(), body.params, body.toGarments, {}};
    // The full fit back in the parameters' frame, where placement unposes it.
    pin.full = body.body;
    pin.full.V = (body.toGarments.inverse() * body.body.V.transpose()).transpose();
    r.placement = placePanels(r.panels, r.flat, pin, options.placement);
    placement = &r.placement;
  }
  r.stitches = makeStitches(r.panels, r.flat, placement);
  progress.end();
  r.stages.emplace_back("placement", secondsSince(t));
  return r;
}

PipelineResult runPipeline(const Scan& scan, const BodyModel& model, const PipelineOptions& options,
                           Progress& progress) {
  PipelineResult out;
  auto t = Clock::now();
  out.fit = fitScan(scan.mesh, model, options.fit, &progress);
  out.stages.emplace_back("fit", secondsSince(t));
  if (options.onFit) options.onFit(out.fit);
  t = Clock::now();
  out.body = fittedFeatures(model, out.fit);
  // The full fit carries the features; the body fitted under the clothes gives the scan's
  // offset from the body, the segmentation's geometric cue (segment/body_offset.h).
  out.segmentation = segmentScan(scan.mesh, scan.colour, out.body.body, out.fit.fittedInScanFrame(),
                                 out.body.features, options.segment, &progress);
  out.stages.emplace_back("segment", secondsSince(t));
  if (options.onSegmentation) options.onSegmentation(out.segmentation);
  try {
    out.pattern = runPattern(panelsInput(out.segmentation, out.body), out.body, scan.mesh,
                             options.pattern, progress);
    for (const auto& s : out.pattern.stages) out.stages.push_back(s);
    if (options.drape.enabled) {
      t = Clock::now();
      try {  // its phases are stages of the progress output
        out.drape = runDrapeStage(out.pattern, out.segmentation, out.body, options.drape, &progress);
      } catch (const Error& e) {  // a pattern the simulator refuses is reported, not fatal
        out.drape = {};
        out.drape.warnings.push_back(std::string("drape: not run: ") + e.what());
      }
      progress.end();
      out.stages.emplace_back("drape", secondsSince(t));
    }
  } catch (const SolverError& e) {
    // A solver's own words (a matrix, a pivot) tell the user nothing: say where and what to do.
    progress.end();
    out.patternErrorMessage = fmt::format(
        "pattern stage: a linear system could not be solved ({}). fit/ and segment/ are "
        "written; the garments' meshes may hold near-degenerate triangles: look at "
        "segment/segment_labels.png, try `scan2pattern convert` on the scan, or report it with "
        "the scan",
        e.what());
    out.patternError = std::make_exception_ptr(SolverError(out.patternErrorMessage));
  } catch (const Error& e) {
    progress.end();
    out.patternError = std::current_exception();
    out.patternErrorMessage = e.what();
  }
  return out;
}

}  // namespace s2p
