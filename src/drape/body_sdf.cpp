#include "drape/body_sdf.h"

#include <openvdb/openvdb.h>
#include <openvdb/tools/Dense.h>
#include <openvdb/tools/MeshToVolume.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace s2p {

BodySdf::BodySdf(const TriMesh& body, const BodySdfOptions& options)
    : voxel_(options.voxel),
      exteriorBand_(options.exteriorBand),
      interiorBand_(options.interiorBand),
      query_((validateMesh(body, "drape body"), body)) {
  if (!(voxel_ >= 5e-4 && voxel_ <= 0.05))
    throw InputError("drape: body SDF voxel " + std::to_string(voxel_) +
                     " m is outside 0.5–50 mm; pick e.g. 0.004");
  if (!(exteriorBand_ >= 2 * voxel_) || !(interiorBand_ >= 2 * voxel_))
    throw InputError("drape: body SDF bands must be at least two voxels wide");
  openvdb::initialize();
  const auto xform = openvdb::math::Transform::createLinearTransform(voxel_);
  std::vector<openvdb::Vec3s> points(body.numVertices());
  for (int v = 0; v < body.numVertices(); ++v)
    points[v] = openvdb::Vec3s(body.V(v, 0) / voxel_, body.V(v, 1) / voxel_, body.V(v, 2) / voxel_);
  std::vector<openvdb::Vec3I> tris(body.numFaces());
  for (int f = 0; f < body.numFaces(); ++f)
    tris[f] = openvdb::Vec3I(body.F(f, 0), body.F(f, 1), body.F(f, 2));
  openvdb::tools::QuadAndTriangleDataAdapter<openvdb::Vec3s, openvdb::Vec3I> adapter(points, tris);
  openvdb::util::NullInterrupter interrupter;
  const auto grid = openvdb::tools::meshToVolume<openvdb::FloatGrid>(
      interrupter, adapter, *xform, static_cast<float>(exteriorBand_ / voxel_ + 1),
      static_cast<float>(interiorBand_ / voxel_ + 1));

  // Dense copy over the body's box grown by the exterior band (cut to the garment's region).
  BoundingBox box = boundingBox(body.V);
  box.min.array() -= exteriorBand_ + 2 * voxel_;
  box.max.array() += exteriorBand_ + 2 * voxel_;
  const BoundingBox& r = options.region;
  if ((r.min.array() <= r.max.array()).all()) {
    box.min = box.min.cwiseMax(r.min - Eigen::Vector3d::Constant(exteriorBand_ + 2 * voxel_));
    box.max = box.max.cwiseMin(r.max + Eigen::Vector3d::Constant(exteriorBand_ + 2 * voxel_));
  }
  Eigen::Vector3i lo, hi;
  for (int a = 0; a < 3; ++a) {
    lo[a] = static_cast<int>(std::floor(box.min[a] / voxel_));
    hi[a] = std::max(lo[a] + 1, static_cast<int>(std::ceil(box.max[a] / voxel_)));
  }
  dims_ = hi - lo + Eigen::Vector3i::Ones();
  origin_ = lo.cast<double>() * voxel_;
  values_.assign(static_cast<size_t>(dims_.x()) * dims_.y() * dims_.z(), 0.0f);
  const openvdb::CoordBBox bbox(openvdb::Coord(lo.x(), lo.y(), lo.z()),
                                openvdb::Coord(hi.x(), hi.y(), hi.z()));
  openvdb::tools::Dense<float, openvdb::tools::LayoutZYX> dense(bbox, values_.data());
  openvdb::tools::copyToDense(*grid, dense);
  // meshToVolume stores distances in world units (metres) already.
}

BodySdf::~BodySdf() = default;
BodySdf::BodySdf(BodySdf&&) noexcept = default;
BodySdf& BodySdf::operator=(BodySdf&&) noexcept = default;

SdfSample BodySdf::sample(const Eigen::Vector3d& p) const {
  SdfSample s;
  const Eigen::Vector3d u = (p - origin_) / voxel_;
  int i[3];
  double f[3];
  for (int a = 0; a < 3; ++a) {
    const double fl = std::floor(u[a]);
    if (!(fl >= 0 && fl < dims_[a] - 1)) {  // outside the grid (or NaN): far from the body
      s.distance = exteriorBand_;
      return s;
    }
    i[a] = static_cast<int>(fl);
    f[a] = u[a] - fl;
  }
  const size_t sz = 1, sy = dims_.z(), sx = static_cast<size_t>(dims_.y()) * dims_.z();
  const size_t o = i[0] * sx + i[1] * sy + i[2] * sz;
  const double c000 = values_[o], c001 = values_[o + sz], c010 = values_[o + sy],
               c011 = values_[o + sy + sz], c100 = values_[o + sx], c101 = values_[o + sx + sz],
               c110 = values_[o + sx + sy], c111 = values_[o + sx + sy + sz];
  const double fx = f[0], fy = f[1], fz = f[2];
  // Interpolate along z, then y, then x; the gradient is the exact derivative of the trilinear.
  const double c00 = c000 + (c001 - c000) * fz, c01 = c010 + (c011 - c010) * fz;
  const double c10 = c100 + (c101 - c100) * fz, c11 = c110 + (c111 - c110) * fz;
  const double c0 = c00 + (c01 - c00) * fy, c1 = c10 + (c11 - c10) * fy;
  s.distance = c0 + (c1 - c0) * fx;
  const double dz00 = c001 - c000, dz01 = c011 - c010, dz10 = c101 - c100, dz11 = c111 - c110;
  const double dz0 = dz00 + (dz01 - dz00) * fy, dz1 = dz10 + (dz11 - dz10) * fy;
  const Eigen::Vector3d g(c1 - c0, (c01 - c00) + ((c11 - c10) - (c01 - c00)) * fx,
                          dz0 + (dz1 - dz0) * fx);
  const double n = g.norm();
  if (n > 1e-12) s.normal = g / n;
  // Deep inside, the band saturates: the exact closest point gives distance and direction.
  if (s.distance < -interiorBand_ + voxel_) return exact(p);
  return s;
}

SdfSample BodySdf::exact(const Eigen::Vector3d& p) const {
  const ClosestHit h = query_.closestPoint(p);
  bool inside;
  const Eigen::Vector3d u = (p - origin_) / voxel_;
  bool inGrid = true;
  for (int a = 0; a < 3; ++a) inGrid = inGrid && u[a] >= 0 && u[a] < dims_[a] - 1;
  double gridValue = exteriorBand_;
  if (inGrid) {
    const size_t sx = static_cast<size_t>(dims_.y()) * dims_.z();
    gridValue = values_[static_cast<size_t>(std::lround(u[0])) * sx +
                        static_cast<size_t>(std::lround(u[1])) * dims_.z() +
                        static_cast<size_t>(std::lround(u[2]))];
  }
  if (std::abs(gridValue) > 2 * voxel_)
    inside = gridValue < 0;
  else
    inside = query_.isInside(p);
  SdfSample s;
  s.distance = inside ? -h.distance : h.distance;
  if (h.distance > 1e-12) s.normal = (inside ? h.point - p : p - h.point) / h.distance;
  return s;
}

}  // namespace s2p
