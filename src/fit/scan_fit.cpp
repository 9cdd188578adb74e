#include "fit/scan_fit.h"

#include <chrono>
#include <cmath>
#include <optional>

#include "core/coarse_mesh.h"
#include "core/error.h"
#include "core/mesh_query.h"
#include "core/stage_error.h"

namespace s2p {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

// Progress lines for the steps of the fit, each timed into ScanFit::timings.
class Steps {
 public:
  Steps(ScanFit& out, Progress* progress) : out_(out), progress_(progress) {}
  template <class F>
  auto run(const std::string& name, F&& f) {
    if (progress_) progress_->begin(name);
    const auto t = Clock::now();
    struct End {
      Steps& s;
      const std::string& name;
      Clock::time_point t;
      ~End() {
        s.out_.timings.emplace_back(name, secondsSince(t));
        if (s.progress_) s.progress_->end();
      }
    } end{*this, name, t};
    try {
      return f();
    } catch (const SolverError& e) {
      throw stageSolverError(e, "body fit, " + name, "the body model and the scan",
                             "check the scan with `scan2pattern info` (pieces, holes), or give "
                             "keypoints (--keypoints) for a better start");
    }
  }

 private:
  ScanFit& out_;
  Progress* progress_;
};

TriMesh transformed(const TriMesh& m, const Eigen::Affine3d& T) {
  TriMesh out = m;
  out.V = (m.V * T.linear().transpose()).rowwise() + T.translation().transpose();
  return out;
}

// The fit from one start: the keypoints, or the geometric initialisation (the rest pose when
// it fails).
void fitFromOneStart(ScanFit& out, Steps& steps, BodyFitInput& input, const Eigen::Affine3d& toFit,
                     const BodyModel& model, const ScanFitOptions& options) {
  out.initialisation = options.keypoints ? "keypoints" : "geometry";
  input.initial = steps.run("pose initialisation", [&]() -> std::optional<BodyParams> {
    try {
      if (options.keypoints) {
        std::vector<JointTarget> targets = *options.keypoints;
        for (JointTarget& t : targets) t.position = toFit * t.position;
        return poseFromTargets(model, {}, targets, options.poseInit);
      }
      return initialisePose(input.scan, model, {}, options.poseInit);
    } catch (const InputError& e) {
      if (options.keypoints) throw;
      // No five extremities (limbs touching the body): the rest pose, centred on the scan.
      out.initialisation = "rest";
      out.warnings.push_back(std::string("pose initialisation failed, fitting from the rest "
                                         "pose: ") +
                             e.what());
      return restPoseOnScan(input.scan, model);
    }
  });

  out.fit = steps.run("shape and pose", [&] { return runBodyFit(input, options.fit); });
  out.start = out.initialisation;
}

}  // namespace

TriMesh ScanFit::fittedInScanFrame() const {
  return transformed(fit.body.mesh, toScan);
}
TriMesh ScanFit::fullInScanFrame() const {
  return transformed(full, toScan);
}
Eigen::MatrixX3d ScanFit::canonicalInScanFrame() const {
  return (fit.body.canonical * toScan.linear().transpose()).rowwise() +
         toScan.translation().transpose();
}

std::vector<std::pair<int, Eigen::Vector3d>> surfaceLandmarks(const BodyModel& model,
                                                              const TriMesh& fitted,
                                                              const MeshQuery& scan,
                                                              double maxDistance) {
  std::vector<std::pair<int, Eigen::Vector3d>> out;
  for (const CanonicalDef& def : model.canonical) {
    if (def.vertices.empty()) continue;  // a skeleton joint, inside the body
    int best = def.vertices.front().first;
    double bestWeight = -1;
    for (const auto& [v, w] : def.vertices)
      if (w > bestWeight) best = v, bestWeight = w;
    const ClosestHit hit = scan.closestPoint(fitted.V.row(best).transpose());
    if (hit.face >= 0 && hit.distance <= maxDistance) out.emplace_back(best, hit.point);
  }
  return out;
}

ScanFit fitScan(const TriMesh& scanFull, const BodyModel& model, const ScanFitOptions& options,
                Progress* progress) {
  const auto t0 = Clock::now();
  ScanFit out;
  Steps steps(out, progress);
  std::optional<CoarseMesh> copy;
  if (options.coarseVertices > 0 && scanFull.numVertices() > 1.5 * options.coarseVertices)
    steps.run("decimated copy", [&] {
      copy = decimatedCopy(scanFull, options.coarseVertices);
      return 0;
    });
  const TriMesh& scanIn = copy ? copy->mesh : scanFull;

  out.orientation = steps.run("orientation", [&] {
    if (!options.yaw) return estimateOrientation(scanIn);
    Orientation o;
    o.yaw = *options.yaw;
    o.facing = yawRotation(-o.yaw) * Eigen::Vector3d::UnitZ();
    o.confidence = 1;
    return o;
  });
  if (out.orientation.confidence < 0.2)
    out.warnings.push_back(
        "the facing direction is uncertain (confidence " +
        std::to_string(out.orientation.confidence).substr(0, 4) +
        "); if the fit looks turned, give keypoints (--keypoints) from the seven views of "
        "render-views");
  // The fitting frame: the scan turned about the vertical through its bounding-box centre.
  const Eigen::Affine3d toFit = turnAboutVertical(scanIn, out.orientation.yaw);
  out.toScan = toFit.inverse();
  BodyFitInput input;
  input.scan = transformed(scanIn, toFit);
  input.model = &model;

  if (options.keypoints || !options.multiStart) {
    fitFromOneStart(out, steps, input, toFit, model, options);
  } else {
    out.initialisation = "multi-start";
    GatedFitResult g = steps.run("shape and pose", [&] {
      return gatedFit(input, options.poseInit, options.fit, options.gate);
    });
    out.fit = std::move(g.fit);
    out.start = g.start;
    out.startScore = g.score;
    out.startScores = g.scores;
    for (const std::string& w : g.warnings) out.warnings.push_back(w);
  }
  for (const std::string& w : out.fit.warnings) out.warnings.push_back(w);
  if (out.fit.insideOrNear < 0.9)
    out.warnings.push_back("only " + std::to_string(std::lround(100 * out.fit.insideOrNear)) +
                           " % of the body lies inside the scan or within 5 mm of it");

  steps.run("non-rigid", [&] {
    if (!options.nonrigid) {
      out.full = out.fit.body.mesh;
      return 0;
    }
    const MeshQuery query(input.scan);
    const auto landmarks =
        surfaceLandmarks(model, out.fit.body.mesh, query, options.icp.maxDistance);
    const NonrigidIcpResult r =
        runNonrigidIcp(out.fit.body.mesh, input.scan, landmarks, options.icp);
    out.full = r.mesh;
    out.fullMeanDistance = r.meanDistance;
    out.fullIterations = r.iterations;
    return 0;
  });
  out.seconds = secondsSince(t0);
  return out;
}

}  // namespace s2p
