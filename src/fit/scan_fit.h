// The whole body fit of a scan, as `fit` and `run` perform it (paper §4 and §5.1.2): find where
// the person faces and turn the scan to +Z, initialise the pose (geometric extremities, or 3D
// keypoints given from outside), fit shape and pose (runBodyFit), then bring the fitted body
// onto the scan surface by non-rigid ICP for the feature projection.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "body/body_model.h"
#include "core/progress.h"
#include "core/tri_mesh.h"
#include "fit/body_fit.h"
#include "fit/nonrigid_icp.h"
#include "fit/orientation.h"
#include "fit/pose_init.h"
#include "fit/pose_start.h"

namespace s2p {

struct ScanFitOptions {
  // Joint targets in the scan's normalised frame (metres, +Y up), e.g. from readKeypoints;
  // absent: the geometric pose initialisation (pose_init.h).
  std::optional<std::vector<JointTarget>> keypoints;
  // Radians: the facing direction is taken as given instead of estimated (yaw that brings the
  // scan to +Z).
  std::optional<double> yaw;
  bool nonrigid = true;  // false: no full fit (body_full = the fitted body)
  PoseInitOptions poseInit;
  // Without keypoints: a short fit from several starts, the best finished (pose_start.h).
  // false: the geometric initialisation alone, the rest pose when it fails.
  bool multiStart = true;
  GatedFitOptions gate;
  BodyFitOptions fit;
  NonrigidIcpOptions icp;
  // Issue 17: a scan of more than 1.5 × this many vertices is fitted on a decimated copy of
  // about this many (core/coarse_mesh.h; its surface within a fraction of a millimetre of the
  // scan's): the body has ~20k vertices, and the scan's BVH, winding-number tree and
  // extremity search grow with the scan. 0: the scan itself.
  int coarseVertices = 100000;
};

struct ScanFit {
  Orientation orientation;  // as estimated (or the given yaw, with confidence 1)
  // Fitting frame (the scan turned to face +Z) → the scan's normalised frame.
  Eigen::Affine3d toScan = Eigen::Affine3d::Identity();
  // "multi-start", "keypoints", or without multiStart "geometry" or "rest" (initialisation
  // failed).
  std::string initialisation;
  // The start the fit was finished from: "keypoints", "geometry", "arms down" or "rest".
  std::string start;
  double startScore = 0;                // metres: its two-sided distance (pose_start.h), 0
                                        // without multi-start
  std::vector<StartScore> startScores;  // every start tried (multi-start only)
  BodyFitResult fit;                    // params, posed body, stages: in the fitting frame
  TriMesh full;                         // the non-rigid fit (faces of the model), fitting frame
  double fullMeanDistance = 0;          // metres, full-fit vertices to the scan
  int fullIterations = 0;
  // Seconds per step: "decimated copy" (a large scan only), "orientation", "pose
  // initialisation" (not with multi-start: inside "shape and pose"), "shape and pose",
  // "non-rigid".
  std::vector<std::pair<std::string, double>> timings;
  std::vector<std::string> warnings;
  double seconds = 0;

  // The posed / full body in the scan's normalised frame.
  TriMesh fittedInScanFrame() const;
  TriMesh fullInScanFrame() const;
  Eigen::MatrixX3d canonicalInScanFrame() const;  // kNumCanonical×3
};

// Throws InputError when the scan is not a standing person (orientation.h) or the keypoints are
// unusable; SolverError when a solve fails.
ScanFit fitScan(const TriMesh& scan, const BodyModel& model, const ScanFitOptions& options = {},
                Progress* progress = nullptr);

// Landmarks for the non-rigid ICP: the main vertex of each surface canonical point (hand and
// toe tips, heels, head top, nose) pinned at its closest scan point when that lies within
// `maxDistance` of it.
std::vector<std::pair<int, Eigen::Vector3d>> surfaceLandmarks(const BodyModel& model,
                                                              const TriMesh& fitted,
                                                              const MeshQuery& scan,
                                                              double maxDistance);

}  // namespace s2p
