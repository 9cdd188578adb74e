#include "eval/evaluation_files.h"

#include <fmt/format.h>

#include <cctype>
#include <cstring>

#include "core/error.h"
#include "eval/boundary_metrics.h"
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

bool isPly(const fs::path& p) {
  std::string ext = p.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".ply";
}

// A truth.json of a scan made outside the generator (../shared/testscans: "preset", "labels",
// "onepiece", no "labelled_mesh"): its labelled scan is the PLY beside it, named after the
// preset or after the file (NAME.truth.json → NAME.ply).
bool isOutsideTruth(const nlohmann::json& j) {
  return j.is_object() && !j.contains("labelled_mesh") && j.contains("labels") &&
         j.contains("preset");
}

fs::path outsideTruthMesh(const fs::path& truth, const nlohmann::json& j) {
  const fs::path dir = truth.parent_path();
  if (j.at("preset").is_string()) {
    const fs::path byPreset = dir / (j.at("preset").get<std::string>() + ".ply");
    std::error_code ec;
    if (fs::is_regular_file(byPreset, ec)) return byPreset;
  }
  std::string stem = truth.filename().string();
  for (const char* suffix : {".truth.json", ".json"})
    if (stem.size() > std::strlen(suffix) &&
        stem.compare(stem.size() - std::strlen(suffix), std::string::npos, suffix) == 0) {
      stem.resize(stem.size() - std::strlen(suffix));
      break;
    }
  return dir / (stem + ".ply");
}

}  // namespace

Truth readEvaluationTruth(const fs::path& path, fs::path* mesh) {
  requireFile(path, "truth file");
  Truth t;
  fs::path m;
  if (isPly(path)) {
    t.preset = "custom";
    m = path;
  } else {
    const nlohmann::json j = parseJsonFile(path);
    if (!isOutsideTruth(j)) {
      t = truthFromJson(j, path.string());
      m = path.parent_path() / t.labelledMesh;
    } else {
      t.preset = j.at("preset").is_string() ? j.at("preset").get<std::string>() : "custom";
      m = outsideTruthMesh(path, j);
      if (j.value("onepiece", false)) {
        TrueGarment g;
        g.name = "onepiece";
        g.label = Label::Upper;
        g.onePiece = true;
        t.garments.push_back(g);
      }
    }
  }
  t.labelledMesh = m.filename().string();
  requireFile(m, fmt::format("labelled mesh of {}:", path.string()));
  if (mesh) *mesh = m;
  return t;
}

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
  readEvaluationTruth(truth, &f.truthMesh);
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
  e.truth = readEvaluationTruth(files.truth);
  e.truthMesh = readLabelledMesh(files.truthMesh);
  // A labelled scan without curves: its true boundaries are its label edges (a staircase at the
  // scan's resolution).
  if (e.truth.boundaries.empty()) e.truth.boundaries = extractLabelBoundaries(e.truthMesh);
  e.prediction = readLabelledMesh(files.prediction);
  if (!files.boundaries.empty()) e.boundaries = readBoundaries(files.boundaries);
  if (!files.body.empty()) e.body = readBodyJson(files.body);
  return e;
}

}  // namespace s2p
