// eval: a segmentation (and a fitted body) scored against a synthetic scan's truth.json.
#include <fmt/format.h>

#include <memory>

#include "app/commands.h"
#include "eval/evaluation_files.h"

namespace s2p::app {
namespace {

struct EvalCommand {
  std::string truth;
  std::string pred;
  std::string boundaries;
  std::string body;
  bool json = false;
};

int runEval(const EvalCommand& cmd, Progress& progress) {
  progress.begin("read truth and prediction");
  const EvaluationFiles files =
      resolveEvaluationFiles(cmd.truth, cmd.pred, cmd.boundaries, cmd.body);
  const LoadedEvaluation loaded = loadEvaluation(files);
  progress.end();
  progress.begin("evaluate");
  const Evaluation e = evaluate(loaded.input());
  progress.end();
  if (cmd.json) {
    nlohmann::json j = evaluationToJson(e);
    j["files"] = {{"truth", files.truth.string()},
                  {"truth_mesh", files.truthMesh.string()},
                  {"prediction", files.prediction.string()},
                  {"boundaries", files.boundaries.string()},
                  {"body", files.body.string()}};
    fmt::print("{}\n", j.dump(2));
  } else {
    fmt::print("truth {}\nprediction {}\n\n{}", files.truth.string(), files.prediction.string(),
               formatEvaluation(e));
  }
  return 0;
}

}  // namespace

void addEvalCommand(CLI::App& app, Commands& out) {
  auto o = std::make_shared<EvalCommand>();
  auto* cmd = app.add_subcommand(
      "eval",
      "Score a segmentation against a synthetic scan's ground truth: IoU per label, "
      "boundary distance (mm) and roughness, body joint error");
  cmd->add_option("--truth", o->truth,
                  "truth.json of a synthetic scan, NAME.truth.json of an outside scan (with "
                  "NAME.ply beside it), or a labelled PLY (boundaries from its label edges)")
      ->required();
  cmd->add_option("--pred", o->pred,
                  "Labelled PLY (face or vertex \"label\"), or a folder holding "
                  "segmentation.ply and optionally boundaries.json and body.json")
      ->required();
  cmd->add_option("--boundaries", o->boundaries,
                  "Predicted boundary curves (JSON as truth.json's \"boundaries\"); default: "
                  "boundaries.json in the PRED folder, else the label edges");
  cmd->add_option("--body", o->body,
                  "Fitted body JSON with \"canonical\" joints; default: body.json in the PRED "
                  "folder");
  cmd->add_flag("--json", o->json, "Print the metrics as JSON");
  out.push_back({cmd, [o](Progress& progress) { return runEval(*o, progress); }});
}

}  // namespace s2p::app
