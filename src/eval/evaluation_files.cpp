#include "eval/evaluation_files.h"

#include <fmt/format.h>

#include "core/error.h"
#include "io/read_ply.h"

namespace fs = std::filesystem;

namespace s2p {
namespace {

void requireFile(const fs::path& p, const std::string& role) {
  std::error_code ec;
  if (!fs::is_regular_file(p, ec))
    throw IoError(fmt::format("{} {} does not exist or is not a file", role, p.string()));
}

nlohmann::json parseJsonFile(const fs::path& path) {
  const std::string bytes = readFileBytes(path);
  try {
    return nlohmann::json::parse(bytes);
  } catch (const nlohmann::json::exception& e) {
    throw FormatError(fmt::format("{} is not JSON: {}", path.string(), e.what()));
  }
}

}  // namespace

nlohmann::json readBodyJson(const fs::path& path) {
  return parseJsonFile(path);
}

std::vector<TrueBoundary> readBoundaries(const fs::path& path) {
  const nlohmann::json j = parseJsonFile(path);
  if (j.is_object() && j.contains("boundaries"))
    return boundariesFromJson(j.at("boundaries"), path.string());
  return boundariesFromJson(j, path.string());
}

EvaluationFiles resolveEvaluationFiles(const fs::path& truth, const fs::path& pred,
                                       const fs::path& boundaries, const fs::path& body) {
  EvaluationFiles f;
  f.truth = truth;
  requireFile(truth, "truth file");
  const Truth t = readTruth(truth);
  f.truthMesh = truth.parent_path() / t.labelledMesh;
  requireFile(f.truthMesh, fmt::format("labelled mesh of {}:", truth.string()));
  std::error_code ec;
  if (fs::is_directory(pred, ec)) {
    f.prediction = pred / "segmentation.ply";
    requireFile(f.prediction, "prediction");
    if (fs::is_regular_file(pred / "boundaries.json", ec)) f.boundaries = pred / "boundaries.json";
    if (fs::is_regular_file(pred / "body.json", ec)) f.body = pred / "body.json";
  } else {
    f.prediction = pred;
    requireFile(f.prediction, "prediction");
  }
  if (!boundaries.empty()) {
    requireFile(boundaries, "boundaries file");
    f.boundaries = boundaries;
  }
  if (!body.empty()) {
    requireFile(body, "body file");
    f.body = body;
  }
  return f;
}

EvaluationInput LoadedEvaluation::input() const {
  EvaluationInput in;
  in.truth = &truth;
  in.truthMesh = &truthMesh;
  in.prediction = &prediction;
  if (boundaries) in.predictedBoundaries = &*boundaries;
  if (body) in.predictedBody = &*body;
  return in;
}

LoadedEvaluation loadEvaluation(const EvaluationFiles& files) {
  LoadedEvaluation e;
  e.truth = readTruth(files.truth);
  e.truthMesh = readLabelledMesh(files.truthMesh);
  e.prediction = readLabelledMesh(files.prediction);
  if (!files.boundaries.empty()) e.boundaries = readBoundaries(files.boundaries);
  if (!files.body.empty()) e.body = readBodyJson(files.body);
  return e;
}

}  // namespace s2p
