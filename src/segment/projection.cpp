#include "segment/projection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "core/error.h"
#include "core/mesh_query.h"

namespace s2p {

const char* toString(ProjectionStatus status) {
  switch (status) {
    case ProjectionStatus::Ok:
      return "ok";
    case ProjectionStatus::NoHit:
      return "no ray hit";
    case ProjectionStatus::HitBody:
      return "ray hits the body first";
    case ProjectionStatus::OppositeNormals:
      return "opposite normals";
    case ProjectionStatus::TooFar:
      return "projection too far";
  }
  return "?";
}

struct FeatureProjector::Impl {
  TriMesh body, scan;
  ProjectionOptions options;
  Eigen::MatrixX3d bodyNormals, scanNormals;  // #V×3 angle-weighted vertex normals
  MeshQuery bodyQuery, scanQuery;
  Impl(const TriMesh& b, const TriMesh& s, const ProjectionOptions& o)
      : body(b), scan(s), options(o), bodyQuery(b), scanQuery(s) {}

  Eigen::Vector3d scanNormal(int face, const Eigen::Vector3d& bary) const {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) n += bary[k] * scanNormals.row(scan.F(face, k)).transpose();
    return n.normalized();
  }
};

FeatureProjector::FeatureProjector(const TriMesh& body, const TriMesh& scan,
                                   const ProjectionOptions& options) {
  validateMesh(body, "body mesh");
  validateMesh(scan, "scan");
  if (!(options.bodyLength > 0) || !(options.maxDistanceFraction > 0) ||
      !(options.selfHitDistance >= 0))
    throw InputError("feature projection: bodyLength and maxDistanceFraction must be positive");
  // Boxes disjoint even when grown by the rule-4 distance: the body belongs to another scan.
  const BoundingBox bb = boundingBox(body.V), sb = boundingBox(scan.V);
  const double margin = options.maxDistanceFraction * options.bodyLength;
  if ((bb.min.array() > sb.max.array() + margin).any() ||
      (sb.min.array() > bb.max.array() + margin).any())
    throw InputError("feature projection: the body does not overlap the scan (body box " +
                     std::to_string(bb.centre().x()) + ", " + std::to_string(bb.centre().y()) +
                     ", " + std::to_string(bb.centre().z()) + "); fit the body to this scan first");
  impl_ = std::make_unique<Impl>(body, scan, options);
  impl_->bodyNormals = vertexNormals(body);
  impl_->scanNormals = vertexNormals(scan);
}

FeatureProjector::~FeatureProjector() = default;
FeatureProjector::FeatureProjector(FeatureProjector&&) noexcept = default;
FeatureProjector& FeatureProjector::operator=(FeatureProjector&&) noexcept = default;

ProjectedPoint FeatureProjector::project(const SurfacePoint& q) const {
  const Impl& d = *impl_;
  if (q.face < 0 || q.face >= d.body.numFaces())
    throw InputError("feature projection: feature point on face " + std::to_string(q.face) +
                     ", outside the body's " + std::to_string(d.body.numFaces()) + " faces");
  const Eigen::Vector3d qp = q.position(d.body);
  Eigen::Vector3d nq = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k) nq += q.bary[k] * d.bodyNormals.row(d.body.F(q.face, k)).transpose();
  nq.normalize();

  ProjectedPoint out;
  const ClosestHit c = d.scanQuery.closestPoint(qp);
  out.point = {c.face, c.bary};
  out.p = c.point;
  if (!nq.allFinite()) return out;  // degenerate body normal: no ray, rule 1

  // Nearest hit of the two rays on the body (beyond q itself) or the scan.
  const double selfHit = d.options.selfHitDistance * d.options.bodyLength;
  double best = std::numeric_limits<double>::infinity();
  bool onBody = false;
  std::optional<RayHit> scanHit;
  for (const double s : {1.0, -1.0}) {
    if (const auto h = d.scanQuery.rayCast(qp, s * nq, 0.0); h && h->t < best) {
      best = h->t;
      onBody = false;
      scanHit = h;
    }
    if (const auto h = d.bodyQuery.rayCast(qp, s * nq, selfHit); h && h->t < best) {
      best = h->t;
      onBody = true;
      out.r = h->point;
    }
  }
  if (!std::isfinite(best)) return out;  // rule 1
  out.hitDistance = best;
  if (onBody) {
    out.status = ProjectionStatus::HitBody;  // rule 2
    return out;
  }
  out.r = scanHit->point;
  const Eigen::Vector3d np = d.scanNormal(c.face, c.bary);
  const Eigen::Vector3d nr = d.scanNormal(scanHit->face, scanHit->bary);
  if (np.dot(nr) < d.options.oppositeNormalDot) {
    out.status = ProjectionStatus::OppositeNormals;  // rule 3
    return out;
  }
  if ((out.p - out.r).norm() > d.options.maxDistanceFraction * d.options.bodyLength) {
    out.status = ProjectionStatus::TooFar;  // rule 4
    return out;
  }
  out.status = ProjectionStatus::Ok;
  return out;
}

std::vector<ProjectedPoint> FeatureProjector::project(const std::vector<SurfacePoint>& q) const {
  std::vector<ProjectedPoint> out;
  out.reserve(q.size());
  for (const auto& s : q) out.push_back(project(s));
  return out;
}

std::vector<SurfacePoint> FeatureProjector::projectSpline(const std::vector<SurfacePoint>& anchors,
                                                          const std::string& name,
                                                          int minAnchors) const {
  std::vector<SurfacePoint> kept;
  for (const auto& p : project(anchors))
    if (p.ok()) kept.push_back(p.point);
  if (static_cast<int>(kept.size()) < std::max(1, minAnchors))
    throw InputError(
        "feature projection: spline '" + name + "' keeps " + std::to_string(kept.size()) + " of " +
        std::to_string(anchors.size()) + " anchors after removing ill-projected points (at least " +
        std::to_string(std::max(1, minAnchors)) + " needed); check the body fit against the scan");
  return kept;
}

}  // namespace s2p
