// Signed distance to the body for cloth collision: an OpenVDB narrow-band level set of the
// closed body mesh copied into a dense float grid (trilinear value + gradient in ~20 ns), with
// the exact Embree closest point behind it where the band saturates (deep inside the body).
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "core/mesh_query.h"
#include "core/tri_mesh.h"

namespace s2p {

struct BodySdfOptions {
  double voxel = 0.004;  // metres: grid spacing (the trilinear error is ≪ voxel near a smooth body)
  double exteriorBand = 0.03;  // metres of exact distance outside the surface
  double interiorBand = 0.03;  // metres inside; deeper points fall back to the exact query
  // When set, the grid covers only this box (grown by the bands) intersected with the body's:
  // the garment's reach. Empty (min > max): the whole body.
  BoundingBox region{Eigen::Vector3d::Constant(1.0), Eigen::Vector3d::Constant(-1.0)};
};

struct SdfSample {
  double distance = 0;                                // metres, negative inside the body
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();  // unit, pointing out of the body
};

class BodySdf {
 public:
  // Builds the level set (OpenVDB meshToVolume + sign flood fill) and the Embree query. Throws
  // InputError for an invalid body mesh or options.
  explicit BodySdf(const TriMesh& body, const BodySdfOptions& options = {});
  ~BodySdf();
  BodySdf(BodySdf&&) noexcept;
  BodySdf& operator=(BodySdf&&) noexcept;

  // Trilinear distance and normalised gradient at p; beyond the exterior band (or outside the
  // grid) distance = +exteriorBand and the normal is meaningless. Const, thread-safe.
  SdfSample sample(const Eigen::Vector3d& p) const;
  // Exact signed distance (Embree closest point; sign from the grid, or the winding number
  // near the surface). Slower (µs); for reports and for points deep inside.
  SdfSample exact(const Eigen::Vector3d& p) const;

  double voxel() const { return voxel_; }
  double exteriorBand() const { return exteriorBand_; }
  double interiorBand() const { return interiorBand_; }
  const MeshQuery& query() const { return query_; }

 private:
  double voxel_, exteriorBand_, interiorBand_;
  Eigen::Vector3i dims_;       // grid samples per axis
  Eigen::Vector3d origin_;     // world position of sample (0,0,0)
  std::vector<float> values_;  // dims x·y·z, x slowest, z fastest
  MeshQuery query_;
};

}  // namespace s2p
