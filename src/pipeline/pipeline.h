// The stages in order, as a library: scan → body fit → features → segmentation → seams and
// panels → flat pattern → placement and stitches (DESIGN.md's pipeline). Computes everything
// and writes nothing; the CLI parses options, calls runPipeline and writes the files.
#pragma once

#include <exception>
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
#include "segment/segmentation.h"

namespace s2p {

// The fitted body as the segmentation and pattern stages see it, in the scan's normalised
// frame (the garments' frame).
struct PosedFeatures {
  TriMesh body;                // the fully fitted body, carrying `features`
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
  FlatPatternOptions flat;
  PlacementOptions placement;
};

// Patterns I–III on cut garments.
struct PatternResult {
  PanelsResult panels;      // seams, panels, garment types (§6.1)
  FlatPatternResult flat;   // flattened, outlined, remeshed panels (§6.2)
  Placement placement;      // around the rest body (§6.3); empty when the body has no model
  StitchSet stitches;
  std::vector<std::pair<std::string, double>> stages;  // (stage, seconds)
};

// Throws as runPanels when no garment makes panels.
PatternResult runPattern(const PanelsInput& input, const PosedFeatures& body, const TriMesh& scan,
                         const PatternOptions& options, Progress& progress);

struct PipelineOptions {
  ScanFitOptions fit;
  SegmentationOptions segment;
  PatternOptions pattern;
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
  std::vector<std::pair<std::string, double>> stages;  // (stage, seconds), in order
};

// The fit and segmentation throw their errors (bad input fails before any result exists); the
// pattern stages' are caught into patternError.
PipelineResult runPipeline(const Scan& scan, const BodyModel& model, const PipelineOptions& options,
                           Progress& progress);

}  // namespace s2p
