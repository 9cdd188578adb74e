// Spatial queries on a fixed triangle mesh: exact closest point and first ray hit (Embree 3
// BVH, distances recomputed in double) and the generalised winding number / inside test
// (hierarchical, Barill et al. 2018), robust to holes such as those of a scanned person under
// the feet and in the armpits.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "core/tri_mesh.h"

namespace s2p {

struct ClosestHit {
  int face = -1;          // row of F
  Eigen::Vector3d bary;   // barycentric coordinates in the face, non-negative, sum 1
  Eigen::Vector3d point;  // closest point = Σ bary_k V(F(face, k))
  double distance = 0;    // |point − query|
};

struct RayHit {
  int face = -1;          // row of F
  Eigen::Vector3d bary;   // barycentric coordinates of the hit in the face, sum 1
  Eigen::Vector3d point;  // hit point = Σ bary_k V(F(face, k))
  double t = 0;           // distance along the ray: point ≈ origin + t · dir / |dir|
};

struct MeshQueryOptions {
  // Fast winding number (Barill et al. 2018): far-field criterion β >= 1 and expansion order
  // 1 (dipole) to 3. The default keeps the error below 1e-3; see WindingNumberTree.
  double windingBeta = 3.0;
  int windingOrder = 3;
};

class MeshQuery {
 public:
  // Copies what the queries need (the mesh may be 1M triangles) and builds the Embree BVH.
  // The winding-number tree is built on the first winding-number query. Throws InputError for
  // an empty or invalid mesh. Movable, not copyable; a moved-from MeshQuery may only be
  // destroyed or assigned to.
  explicit MeshQuery(const TriMesh& mesh, const MeshQueryOptions& options = {});
  ~MeshQuery();
  MeshQuery(MeshQuery&&) noexcept;
  MeshQuery& operator=(MeshQuery&&) noexcept;
  MeshQuery(const MeshQuery&) = delete;
  MeshQuery& operator=(const MeshQuery&) = delete;

  // === Queries: const and thread-safe. Non-finite inputs throw InputError.

  // Exact closest point on the mesh to p (float BVH culling, exact double distances).
  ClosestHit closestPoint(const Eigen::Vector3d& p) const;
  // closestPoint for every row of P (#P×3), in parallel (TBB); result i belongs to row i.
  std::vector<ClosestHit> closestPoints(const Eigen::MatrixX3d& P) const;
  // closestPoints with a guess per point (e.g. the face found at the previous iteration of an
  // ICP; −1 or out of range: none): the search starts from that face's distance and visits far
  // fewer BVH nodes. The same distances as without hints (on a tie the face may differ). Throws
  // InputError unless there is one hint per row of P.
  std::vector<ClosestHit> closestPoints(const Eigen::MatrixX3d& P,
                                        const std::vector<int>& hintFaces) const;

  // First hit of the ray origin + t·dir/|dir| with t in [tMin, tMax] (t is a distance;
  // dir need not be unit but must be non-zero). Faces are two-sided. nullopt on a miss.
  std::optional<RayHit> rayCast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir,
                                double tMin = 0,
                                double tMax = std::numeric_limits<double>::infinity()) const;

  // Generalised winding number at p (Jacobson et al. 2013): ≈ 1 inside, ≈ 0 outside,
  // negative for an inverted orientation; smooth across holes.
  double windingNumber(const Eigen::Vector3d& p) const;
  // windingNumber(p) > 0.5.
  bool isInside(const Eigen::Vector3d& p) const;
  // windingNumber for every row of P (#P×3), in parallel; #P.
  Eigen::VectorXd windingNumbers(const Eigen::MatrixX3d& P) const;

  int numFaces() const;
  int numVertices() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  ClosestHit closestPointFrom(const Eigen::Vector3d& p, int hintFace) const;
};

}  // namespace s2p
