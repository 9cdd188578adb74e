#include "fit/pose_start.h"

#include <fmt/format.h>

#include <limits>
#include <optional>

#include "body/posing.h"
#include "core/error.h"
#include "core/mesh_query.h"

namespace s2p {
namespace {

double meanDistance(const MeshQuery& to, const Eigen::MatrixX3d& points) {
  if (points.rows() == 0) return 0;
  double sum = 0;
  for (const ClosestHit& h : to.closestPoints(points)) sum += h.distance;
  return sum / static_cast<double>(points.rows());
}

// twoSidedDistance with the queries built by the caller (the scan's is shared by every start).
double twoSided(const TriMesh& body, const MeshQuery& bodyQuery, const TriMesh& scan,
                const MeshQuery& scanQuery) {
  return 0.5 * (meanDistance(bodyQuery, scan.V) + meanDistance(scanQuery, body.V));
}

// A body fit starting from `start` (a copy of input with it as the initial parameters).
BodyFitResult fitFrom(const BodyFitInput& input, const BodyParams& start,
                      const BodyFitOptions& options) {
  BodyFitInput in{input.scan, input.model, start};
  return runBodyFit(in, options);
}

}  // namespace

double twoSidedDistance(const TriMesh& body, const TriMesh& scan) {
  return twoSided(body, MeshQuery(body), scan, MeshQuery(scan));
}

GatedFitResult gatedFit(const BodyFitInput& input, const PoseInitOptions& poseInit,
                        const BodyFitOptions& fit, const GatedFitOptions& options) {
  if (!input.model) throw InputError("body fit: no body model given");
  const BodyModel& model = *input.model;
  GatedFitResult out;

  struct Start {
    std::string name;
    BodyParams params;
  };
  std::vector<Start> starts;
  try {
    starts.push_back({"geometry", initialisePose(input.scan, model, {}, poseInit)});
  } catch (const InputError& e) {
    out.warnings.push_back(std::string("geometric pose initialisation failed (") + e.what() +
                           "); fitting from the arms-down and rest poses");
  }
  starts.push_back({"arms down", poseOnScan(input.scan, model, armsDownPose(model, {}))});
  starts.push_back({"rest", restPoseOnScan(input.scan, model)});

  BodyFitOptions brief = fit;
  brief.cycles = options.shortCycles;
  brief.finalSteps = options.shortFinalSteps;
  brief.maxIterations = options.shortMaxIterations;
  brief.maxFitVertices = options.shortFitVertices;
  const MeshQuery scanQuery(input.scan);
  int best = -1;
  double bestScore = std::numeric_limits<double>::infinity();
  for (int i = 0; i < static_cast<int>(starts.size()); ++i) {
    const BodyFitResult r = fitFrom(input, starts[i].params, brief);
    const double score = twoSided(r.body.mesh, MeshQuery(r.body.mesh), input.scan, scanQuery);
    out.scores.push_back({starts[i].name, score});
    // The geometric start (first when found) is replaced only by a clearly better one.
    const double margin = best == 0 && starts[0].name == "geometry" ? options.geometryMargin : 0;
    if (score < bestScore - margin) best = i, bestScore = score;
  }
  out.start = starts[best].name;
  out.score = bestScore;
  if (starts[0].name == "geometry" && best != 0)
    out.warnings.push_back(fmt::format(
        "the fit from the geometric pose initialisation lies {:.1f} mm from the scan, from the {} "
        "start {:.1f} mm: the extremities were probably misread (hands touching the thighs or "
        "hips); fitting from the {} start",
        1000 * out.scores[0].score, out.start, 1000 * bestScore, out.start));
  out.fit = fitFrom(input, starts[best].params, fit);
  return out;
}

}  // namespace s2p
