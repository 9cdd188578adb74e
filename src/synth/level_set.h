// Level-set machinery of the synthetic scans (OpenVDB): the posed body's signed distance with
// the closest body face of every voxel (rest-pose coordinates under any point), and the CSG
// union of body and garment layers meshed into one closed triangle surface.
#pragma once

#include <Eigen/Core>
#include <memory>

#include "core/mesh_query.h"
#include "core/progress.h"
#include "core/tri_mesh.h"
#include "synth/garment_shapes.h"

namespace s2p {

// Signed distance to the posed body on a narrow band, and the rest point under any point.
class BodyField {
 public:
  // posed and rest share faces. exteriorBand: metres of band outside the body.
  BodyField(const TriMesh& posed, const TriMesh& rest, double voxel, double exteriorBand);
  ~BodyField();
  BodyField(const BodyField&) = delete;
  BodyField& operator=(const BodyField&) = delete;

  double voxel() const { return voxel_; }
  // Exact closest point (Embree) with the sign of the level set: for vertices and curves.
  BodySample sample(const Eigen::Vector3d& p) const;
  std::vector<BodySample> samples(const Eigen::MatrixX3d& P) const;  // in parallel

  struct Grids;  // OpenVDB grids (level_set.cpp)
  const Grids& grids() const { return *grids_; }
  const TriMesh& posed() const { return posed_; }
  const TriMesh& rest() const { return rest_; }
  // Rest point of the posed surface point (face, barycentric).
  Eigen::Vector3d restPoint(int face, const Eigen::Vector3d& bary) const;

 private:
  TriMesh posed_, rest_;
  double voxel_;
  std::unique_ptr<Grids> grids_;
  MeshQuery query_;
};

struct UnionMeshStats {
  long activeVoxels = 0;      // voxels evaluated
  int removedComponents = 0;  // floating pieces dropped (level-set debris)
  int removedFaces = 0;
};

// Evaluates min(body, layers) on the body band plus the analytic shapes' boxes, meshes its zero
// level set (quads split along the shorter diagonal), keeps the largest component, orients
// faces outwards. Deterministic.
TriMesh meshUnion(const BodyField& body, const GarmentLayers& layers, UnionMeshStats* stats,
                  Progress& progress);

}  // namespace s2p
