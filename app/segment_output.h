// What `segment` (and the pipeline's segmentation step) writes: segmentation.ply, the garment
// meshes with their scan-face maps, boundaries.json and the previews.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "eval/evaluation.h"
#include "io/scan.h"
#include "pipeline/pipeline.h"
#include "segment/segmentation.h"

namespace s2p::app {

// The posed body of a body JSON (bodyToJson: "source", shape, pose), moved into the normalised
// frame of `scan`, with its feature set. The posed body is in the scan file's frame, or is taken
// there by "to_scan_file" (a fit's body.json); a fit's "full_mesh" (its non-rigid fit, a file
// relative to `jsonDir`) replaces the posed body when `jsonDir` is given and the file exists.
// The body model, its parameters and their frame go with it, so that the pattern can be placed.
PosedFeatures poseBodyForScan(const nlohmann::json& bodyJson, const Scan& scan, Progress& progress,
                              const std::filesystem::path& jsonDir = {});

// The body under the clothes, for the segmentation's geometric cues (segmentScan's underBody),
// in the normalised frame of `scan`: a fit's shape-and-pose fit (body_fit.obj beside the
// body.json that names a "full_mesh", in the scan file's frame), else `body`'s own mesh (a made or
// a true body: nothing between it and the scan but the clothes).
TriMesh underBodyForScan(const nlohmann::json& bodyJson, const PosedFeatures& body,
                         const Scan& scan, const std::filesystem::path& jsonDir = {});

struct SegmentOutput {
  Segmentation segmentation;
  std::string segmenter;  // "curve" or "mrf"
};

// The paper's Fig. 14 baseline: per-vertex graph-cut labelling with the same colour model and
// the geometric cues from `underBody`, the body under the clothes (underBodyForScan).
SegmentOutput segmentWithMrf(const Scan& scan, const TriMesh& body, const TriMesh& underBody,
                             const FeatureSet& features, const SegmentationOptions& options,
                             Progress& progress);

// boundaries.json: {"boundaries": [truth.json's format, one entry per label pair, plus
// "name", "iterations", "converged", "seconds", "initial_curves", ...], "layout", ...}. All
// coordinates in the scan file's frame.
nlohmann::json segmentationToJson(const SegmentOutput& out, const Eigen::Affine3d& toInput);

// Writes everything into `dir` (created). Coordinates go back to the scan file's frame.
void writeSegmentation(const std::filesystem::path& dir, const Scan& scan,
                       const SegmentOutput& out);
// A segmentation written in `outDir` scored against a synthetic scan's truth.json (also
// written as outDir/evaluation.json); boundary figures over the boundaries found, in metres.
struct SegmentScore {
  Evaluation evaluation;
  double boundaryMean = 0, worstP95 = 0, worstRoughness = 0;
  std::string missing;  // "upper|skin lower|shoes": true boundaries with no prediction
};
SegmentScore scoreSegmentation(const std::filesystem::path& truthPath,
                               const std::filesystem::path& outDir);

void printSegmentation(const Segmentation& s);
std::string garmentFileList(const Segmentation& s);  // "upper.obj, lower.obj, "

}  // namespace s2p::app
