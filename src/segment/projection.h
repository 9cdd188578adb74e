// Feature point projection from the fitted body to the scan (§5.1.2) and the removal of
// ill-projected points (Appendix B). For a feature point q on the body B, p is its closest point
// on the scan S; a ray from q along +n(q) and −n(q) gives r, the nearest hit on B or S. p is
// discarded when (1) there is no r, (2) r is on B, (3) n(p)·n(r) < −0.5 (the formula of
// Appendix B; normals are the scan's interpolated vertex normals), or (4) |p − r| > 0.4 L with L
// the body length (height).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/surface_point.h"
#include "core/tri_mesh.h"

namespace s2p {

enum class ProjectionStatus {
  Ok,
  NoHit,            // rule 1: neither ray meets B or S
  HitBody,          // rule 2: the nearest hit is on the body itself
  OppositeNormals,  // rule 3: n(p)·n(r) < oppositeNormalDot
  TooFar            // rule 4: |p − r| > maxDistanceFraction · L
};
const char* toString(ProjectionStatus status);

struct ProjectionOptions {
  double bodyLength = 1.75;          // L, metres (the fitted body's height)
  double oppositeNormalDot = -0.5;   // rule 3 threshold
  double maxDistanceFraction = 0.4;  // rule 4: fraction of L
  double selfHitDistance = 1e-4;     // rays ignore body hits closer than this × L (q itself)
};

struct ProjectedPoint {
  ProjectionStatus status = ProjectionStatus::NoHit;
  SurfacePoint point;  // p on the scan (valid whatever the status)
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  Eigen::Vector3d r = Eigen::Vector3d::Zero();                   // nearest ray hit (when any)
  double hitDistance = std::numeric_limits<double>::infinity();  // |q − r| along the ray (m)
  bool ok() const { return status == ProjectionStatus::Ok; }
};

class FeatureProjector {
 public:
  // body: the posed (fully fitted) body mesh the features live on; scan: the scan. Throws
  // InputError for an invalid mesh or options, or when the bounding boxes of body and scan are
  // disjoint even when grown by maxDistanceFraction·L (a body fitted to another scan).
  FeatureProjector(const TriMesh& body, const TriMesh& scan, const ProjectionOptions& options = {});
  ~FeatureProjector();
  FeatureProjector(FeatureProjector&&) noexcept;
  FeatureProjector& operator=(FeatureProjector&&) noexcept;

  // Projects one body surface point. Throws InputError when q's face is not a body face.
  ProjectedPoint project(const SurfacePoint& q) const;
  std::vector<ProjectedPoint> project(const std::vector<SurfacePoint>& q) const;

  // The surviving anchors of a spline, in their order (a closed spline stays closed through the
  // remaining anchors). Throws InputError naming the spline when fewer than `minAnchors`
  // survive.
  std::vector<SurfacePoint> projectSpline(const std::vector<SurfacePoint>& anchors,
                                          const std::string& name, int minAnchors = 1) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace s2p
