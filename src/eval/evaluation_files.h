// The files of an evaluation (`scan2pattern eval`): truth.json with its labelled mesh, and a
// prediction given as a labelled PLY or as a segmentation output folder.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "eval/evaluation.h"

namespace s2p {

struct EvaluationFiles {
  std::filesystem::path truth;       // truth.json
  std::filesystem::path truthMesh;   // its "labelled_mesh", resolved relative to truth.json
  std::filesystem::path prediction;  // labelled PLY
  std::filesystem::path boundaries;  // boundaries.json; empty: extract from the labels
  std::filesystem::path body;        // body.json; empty: no body metric
};

// Resolves PRED: a labelled PLY, or a folder holding segmentation.ply (and optionally
// boundaries.json and body.json beside it, used unless given explicitly). Missing files →
// IoError naming them. Reads the truth only for the labelled mesh's path (readEvaluationTruth).
EvaluationFiles resolveEvaluationFiles(const std::filesystem::path& truth,
                                       const std::filesystem::path& pred,
                                       const std::filesystem::path& boundaries = {},
                                       const std::filesystem::path& body = {});

// The truth of an evaluation and the path of its labelled mesh: a synthetic scan's truth.json;
// a truth.json of a scan made outside the generator ("preset", "labels", "onepiece", no
// "labelled_mesh", as ../shared/testscans: the labelled PLY beside it, NAME.truth.json →
// NAME.ply or PRESET.ply); or a labelled PLY itself (preset "custom", no boundaries, two-piece).
// Missing files → IoError, bad JSON → FormatError.
Truth readEvaluationTruth(const std::filesystem::path& path, std::filesystem::path* mesh = nullptr);

// A body JSON (body.json of `scan2pattern body` or the fitter): missing → IoError, not JSON →
// FormatError. Its content is checked by compareBodies.
nlohmann::json readBodyJson(const std::filesystem::path& path);
// boundaries.json: the truth's "boundaries" array, or an object holding one under
// "boundaries". Malformed → FormatError.
std::vector<TrueBoundary> readBoundaries(const std::filesystem::path& path);

// Everything evaluate() needs, read from the files; input() points into this object.
struct LoadedEvaluation {
  Truth truth;
  LabelledMesh truthMesh;
  LabelledMesh prediction;
  std::optional<std::vector<TrueBoundary>> boundaries;
  std::optional<nlohmann::json> body;
  EvaluationInput input() const;
};
LoadedEvaluation loadEvaluation(const EvaluationFiles& files);

}  // namespace s2p
