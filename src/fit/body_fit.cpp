#include "fit/body_fit.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <string>

#include "core/error.h"
#include "fit/pose_init.h"

namespace s2p {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// The whole energy as one Ceres cost with parameter blocks [β (when #S > 0) | θ | t], on the
// compact residuals (no rows for the ignored or unsampled vertices).
class FitCost : public ceres::CostFunction {
 public:
  FitCost(const FitEnergy& energy, const BodyModel& model) : energy_(energy), model_(model) {
    set_num_residuals(energy.numCompactResiduals());
    if (model.numShapes() > 0) mutable_parameter_block_sizes()->push_back(model.numShapes());
    mutable_parameter_block_sizes()->push_back(3 * model.numJoints());
    mutable_parameter_block_sizes()->push_back(3);
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override {
    const int ns = model_.numShapes(), nj = model_.numJoints();
    const int b0 = ns > 0 ? 1 : 0;  // block index of θ
    BodyParams p;
    p.shape = ns > 0 ? Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(parameters[0], ns))
                     : Eigen::VectorXd();
    p.pose = BodyPose::zero(nj);
    for (int j = 0; j < nj; ++j)
      for (int k = 0; k < 3; ++k) p.pose.axisAngle(j, k) = parameters[b0][3 * j + k];
    p.pose.translation = Eigen::Map<const Eigen::Vector3d>(parameters[b0 + 1]);
    const bool wantShapePose = jacobians && ((ns > 0 && jacobians[0]) || jacobians[b0]);
    Eigen::VectorXd r;
    Eigen::MatrixXd J;
    energy_.evaluateCompact(p, &r, jacobians ? &J : nullptr, wantShapePose);
    if (!r.allFinite()) return false;
    Eigen::Map<Eigen::VectorXd>(residuals, r.size()) = r;
    if (!jacobians) return true;
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
    int col = 0;
    for (int b = 0; b < static_cast<int>(parameter_block_sizes().size()); ++b) {
      const int size = parameter_block_sizes()[b];
      if (jacobians[b])
        Eigen::Map<RowMajor>(jacobians[b], r.size(), size) = J.middleCols(col, size);
      col += size;
    }
    return true;
  }

 private:
  const FitEnergy& energy_;
  const BodyModel& model_;
};

// About `count` template vertices spread evenly over the surface: one per occupied cell of a
// grid whose cell area is the surface area / count. Empty when the template is small enough.
std::vector<int> sampleVertices(const TriMesh& rest, int count) {
  if (count <= 0 || rest.numVertices() <= count) return {};
  double cell = std::sqrt(surfaceArea(rest) / count);
  std::vector<int> chosen;
  for (int attempt = 0; attempt < 8; ++attempt) {
    std::map<std::array<long, 3>, int> cells;
    for (int v = 0; v < rest.numVertices(); ++v) {
      const std::array<long, 3> key = {std::lround(std::floor(rest.V(v, 0) / cell)),
                                       std::lround(std::floor(rest.V(v, 1) / cell)),
                                       std::lround(std::floor(rest.V(v, 2) / cell))};
      cells.emplace(key, v);
    }
    chosen.clear();
    for (const auto& [key, v] : cells) chosen.push_back(v);
    if (static_cast<int>(chosen.size()) <= 1.3 * count) break;
    cell *= 1.15;
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

}  // namespace

double BodyFitResult::secondsByStage(const std::string& name) const {
  double s = 0;
  for (const auto& st : stages)
    if (st.name == name) s += st.seconds;
  return s;
}

double insideOrNearFraction(const ScanTarget& scan, const TriMesh& body, double tolerance) {
  if (body.numVertices() == 0) return 0;
  const std::vector<ClosestHit> hits = scan.query().closestPoints(body.V);
  const Eigen::VectorXd wn = scan.query().windingNumbers(body.V);
  int n = 0;
  for (int i = 0; i < body.numVertices(); ++i) n += wn[i] > 0.5 || hits[i].distance <= tolerance;
  return static_cast<double>(n) / body.numVertices();
}

BodyFitResult runBodyFit(const BodyFitInput& input, const BodyFitOptions& options) {
  const auto t0 = Clock::now();
  if (!input.model) throw InputError("body fit: no body model given");
  const BodyModel& model = *input.model;
  if (input.scan.numVertices() < 100)
    throw InputError("body fit: the scan has " + std::to_string(input.scan.numVertices()) +
                     " vertices, far too few for a person; give a full-body scan");
  validateMesh(input.scan, "body fit: scan");
  if (options.cycles < 1 || options.icpStepsPerStage < 1 || options.maxIterations < 1)
    throw InputError("body fit: cycles, ICP steps and iterations must be at least 1");

  const int ns = model.numShapes(), nj = model.numJoints();
  BodyParams params;
  if (input.initial) {
    params = *input.initial;
    if (params.shape.size() == 0) params.shape = Eigen::VectorXd::Zero(ns);
    if (params.shape.size() != ns || params.pose.axisAngle.rows() != nj)
      throw InputError("body fit: the initial parameters have " +
                       std::to_string(params.shape.size()) + " shapes and " +
                       std::to_string(params.pose.axisAngle.rows()) + " joints, the model " +
                       model.source + " has " + std::to_string(ns) + " and " + std::to_string(nj));
    if (!params.shape.allFinite() || !params.pose.axisAngle.allFinite() ||
        !params.pose.translation.allFinite())
      throw InputError("body fit: the initial parameters are not finite");
  } else {
    params.shape = Eigen::VectorXd::Zero(ns);
    params.pose = BodyPose::zero(nj);
  }

  const Poser poser(model);
  const ScanTarget target(input.scan);
  BodyFitResult result;
  if (!input.initial) {
    try {
      params = initialisePose(input.scan, model, params.shape);
    } catch (const InputError& e) {
      // No five extremities (limbs touching the body): BSE's translateTo, the rest body's
      // centroid onto the scan's.
      result.warnings.push_back(
          std::string("pose initialisation failed, fitting from the rest pose: ") + e.what());
      params = restPoseOnScan(input.scan, model, params.shape);
    }
  }
  const std::vector<int> subset = sampleVertices(model.rest, options.maxFitVertices);
  FitEnergy energy(poser, target, params, options.weights, defaultJointLimits(model));

  Eigen::VectorXd beta = params.shape;
  Eigen::VectorXd theta(3 * nj);
  for (int j = 0; j < nj; ++j) theta.segment<3>(3 * j) = params.pose.axisAngle.row(j).transpose();
  Eigen::Vector3d t = params.pose.translation;
  auto current = [&] {
    BodyParams p;
    p.shape = beta;
    p.pose = BodyPose::zero(nj);
    for (int j = 0; j < nj; ++j) p.pose.axisAngle.row(j) = theta.segment<3>(3 * j).transpose();
    p.pose.translation = t;
    return p;
  };

  enum class Stage { Translation, Shape, Pose, All };
  std::vector<std::pair<Stage, int>> schedule;  // (stage, cycle)
  for (int cycle = 0; cycle < options.cycles; ++cycle)
    for (Stage stage : {Stage::Translation, Stage::Shape, Stage::Pose})
      if (stage != Stage::Shape || (options.fitShape && ns > 0))
        schedule.emplace_back(stage, cycle);
  if (options.finalSteps > 0) schedule.emplace_back(Stage::All, options.cycles);
  for (const auto& [stage, cycle] : schedule) {
    {
      FitStageReport report;
      report.name = stage == Stage::Translation ? "translation"
                    : stage == Stage::Shape     ? "shape"
                    : stage == Stage::Pose      ? "pose"
                                                : "all";
      report.cycle = cycle;
      const auto ts = Clock::now();
      const int steps = stage == Stage::All ? options.finalSteps : options.icpStepsPerStage;
      for (int step = 0; step < steps; ++step) {
        CorrespondenceOptions co;
        if (stage == Stage::Shape) co.pruneOutside = options.shapePruneOutside;
        energy.setCorrespondences(findCorrespondences(target, poser.pose(current()).mesh, co,
                                                      subset.empty() ? nullptr : &subset));

        ceres::Problem::Options po;
        po.cost_function_ownership = ceres::TAKE_OWNERSHIP;
        ceres::Problem problem(po);
        std::vector<double*> blocks;
        if (ns > 0) blocks.push_back(beta.data());
        blocks.push_back(theta.data());
        blocks.push_back(t.data());
        problem.AddResidualBlock(new FitCost(energy, model), nullptr, blocks);
        const bool fitBeta = stage == Stage::Shape || (stage == Stage::All && options.fitShape);
        if (ns > 0 && !fitBeta) problem.SetParameterBlockConstant(beta.data());
        if (ns > 0 && fitBeta)
          for (int s = 0; s < ns && s < static_cast<int>(model.shapeParams.size()); ++s) {
            // The model's stated range, widened to include the start.
            problem.SetParameterLowerBound(beta.data(), s,
                                           std::min(model.shapeParams[s].min, beta[s]));
            problem.SetParameterUpperBound(beta.data(), s,
                                           std::max(model.shapeParams[s].max, beta[s]));
          }
        if (stage != Stage::Pose && stage != Stage::All)
          problem.SetParameterBlockConstant(theta.data());
        if (stage != Stage::Translation && stage != Stage::All)
          problem.SetParameterBlockConstant(t.data());

        ceres::Solver::Options so;
        so.minimizer_type = ceres::TRUST_REGION;
        so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
        so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
        so.max_num_iterations = options.maxIterations;
        so.function_tolerance = options.functionTolerance;
        so.num_threads = std::max(1, options.threads);
        so.logging_type = ceres::SILENT;
        so.minimizer_progress_to_stdout = false;
        ceres::Solver::Summary summary;
        ceres::Solve(so, &problem, &summary);
        if (summary.termination_type == ceres::FAILURE)
          throw SolverError("body fit: Levenberg-Marquardt failed in the " + report.name +
                            " stage: " + summary.message);
        if (step == 0) report.costBefore = summary.initial_cost;
        report.costAfter = summary.final_cost;
        report.iterations += static_cast<int>(summary.iterations.size()) - 1;
      }
      report.seconds = secondsSince(ts);
      result.stages.push_back(report);
    }
  }

  result.params = current();
  result.body = poser.pose(result.params);
  energy.setCorrespondences(findCorrespondences(target, result.body.mesh));
  result.energy = energy.terms(result.params);
  // insideOrNearFraction from the closest points and winding numbers just found.
  const Correspondences& last = energy.correspondences();
  int insideOrNear = 0;
  for (int i = 0; i < result.body.mesh.numVertices(); ++i)
    insideOrNear += last.winding[i] > 0.5 || last.distance[i] <= 0.005;
  result.insideOrNear =
      static_cast<double>(insideOrNear) / std::max(1, result.body.mesh.numVertices());
  result.seconds = secondsSince(t0);
  return result;
}

}  // namespace s2p
