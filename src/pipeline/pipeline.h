// The stages in order, as a library: scan → body fit → features → segmentation → seams and
// panels → flat pattern → placement and stitches (DESIGN.md's pipeline). Computes everything
// and writes nothing; the CLI parses options, calls runPipeline and writes the files.
#pragma once

#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "body/body_model.h"
#include "body/features.h"
#include "core/progress.h"
#include "fit/scan_fit.h"
#include "io/scan.h"
#include "pattern/flat_pattern.h"
#include "pattern/panels.h"
#include "pattern/placement.h"
#include "pipeline/drape_stage.h"
#include "pipeline/limb_straightening.h"
#include "segment/segmentation.h"

namespace s2p {

// The fitted body as the segmentation and pattern stages see it, in the scan's normalised
// frame (the garments' frame).
struct PosedFeatures {
  TriMesh body;  // the fully fitted body, carrying `features`
  FeatureSet features;
  Eigen::MatrixX3d canonical;  // kNumCanonical×3, the posed body's canonical points
  // What placement needs to unpose: the model, its fitted parameters and the map from the
  // parameters' frame to this one. model is null when the body came without them.
  std::shared_ptr<const BodyModel> model;
  BodyParams params;
  Eigen::Affine3d toGarments = Eigen::Affine3d::Identity();
};

// The full fit's body, features and canonical points in the scan frame. `model` must outlive
// the result (it is referenced, not copied).
PosedFeatures fittedFeatures(const BodyModel& model, const ScanFit& fit);

// The segmentation's garments with the posed body, its features and canonical points.
PanelsInput panelsInput(const Segmentation& segmentation, const PosedFeatures& body);

struct PatternOptions {
  PanelOptions panels;
  // Sleeves and legs on a bent elbow or knee flattened as for a straight limb
  // (limb_straightening.h); false: every panel flattened as scanned.
  bool straightenLimbs = true;
  LimbStraighteningOptions straightening;
  FlatPatternOptions flat;
  PlacementOptions placement;
};

// Patterns I–III on cut garments.
struct PatternResult {
  PanelsResult panels;     // seams, panels, garment types (§6.1)
  FlatPatternResult flat;  // flattened, outlined, remeshed panels (§6.2)
  Placement placement;     // around the rest body (§6.3); empty when the body has no model
  StitchSet stitches;
  std::vector<std::pair<std::string, double>> stages;  // (stage, seconds)
};

// Throws as runPanels when no garment makes panels.
PatternResult runPattern(const PanelsInput& input, const PosedFeatures& body, const TriMesh& scan,
                         const PatternOptions& options, Progress& progress);

// === The drape check (issue 19)

// The simulator's input from a placed pattern: one cloth panel per flattened, placed panel (rest
// shape = the remeshed flat panel, start = its placement), every stitch's vertex pairs, the rest
// body. panelOf (may be null) receives each cloth panel's PatternResult panel.
DrapeInput drapeInput(const PatternResult& pattern, std::vector<int>* panelOf = nullptr);
// The same cloth with every panel remeshed at `edge` metres (pattern/flat_pattern.h's
// remeshOutlines), placed by the same rigid placement and stitched along the same seams. Empty
// (no panels) when a panel of `fine`'s cannot be remeshed so; `why` says which.
DrapeInput coarseDrapeInput(const PatternResult& pattern, const std::vector<int>& panelOf,
                            double edge, std::string* why = nullptr);

// Points of the garments' (scan) frame moved to the drape pose of placement's rest frame by
// linear blend skinning: each point takes the skinning weights of its closest point on the
// fitted body, is unposed with the fitted pose and posed in the drape pose (as placement carries
// the full fit's detail to the rest body). Throws InputError when the body has no model.
Eigen::MatrixX3d toDrapePose(const Eigen::MatrixX3d& P, const PosedFeatures& body,
                             const Placement& placement);

// Drapes the pattern and compares each garment. Never throws for a simulation that fails: the
// failure is in warnings (and drape.status); throws InputError only for inconsistent input.
// progress (optional): each phase of the drape, then the comparison, as stages of their own.
DrapeStage runDrapeStage(const PatternResult& pattern, const Segmentation& segmentation,
                         const PosedFeatures& body, const DrapeStageOptions& options,
                         Progress* progress = nullptr);

struct PipelineOptions {
  ScanFitOptions fit;
  SegmentationOptions segment;
  PatternOptions pattern;
  DrapeStageOptions drape;
  // Called on the pipeline's thread as soon as the fit / the segmentation is final, so that a
  // caller can write them while the later stages run. Optional; must not keep the reference.
  std::function<void(const ScanFit&)> onFit;
  std::function<void(const Segmentation&)> onSegmentation;
};

struct PipelineResult {
  ScanFit fit;
  PosedFeatures body;
  Segmentation segmentation;
  PatternResult pattern;
  // The pattern stage's failure, if any: the fit and segmentation are still there (to write
  // and look at); the caller rethrows it for its exit code.
  std::exception_ptr patternError;
  std::string patternErrorMessage;
  DrapeStage drape;  // after a pattern; ran = false when disabled or the pattern failed
  std::vector<std::pair<std::string, double>> stages;  // (stage, seconds), in order
};

// The fit and segmentation throw their errors (bad input fails before any result exists); the
// pattern stages' are caught into patternError. The drape never throws: its failure is a
// warning in drape.warnings.
PipelineResult runPipeline(const Scan& scan, const BodyModel& model, const PipelineOptions& options,
                           Progress& progress);

}  // namespace s2p
