// Signed geodesic distance from a curve on a triangle mesh by the heat method (Crane, Weischedel
// and Wardetzky 2013), the paper's signed geodesic function φ (§5.1.3; the paper uses fast
// marching). The curve enters as a source distribution on the crossed edges (not snapped to
// vertices); the two matrices (M + tL) and L are factored once per mesh and reused for every
// curve.
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>

#include "core/spd_solver.h"
#include "core/tri_mesh.h"
#include "segment/isoline.h"

namespace s2p {

struct HeatDistanceOptions {
  double timeFactor = 1.0;  // heat time t = timeFactor · (mean edge length)² (Crane et al.: 1)
};

class HeatDistance {
 public:
  // Builds the operators and factors (M + tL) and (L + εM) (ε = 1e-8/diag², diag the bounding
  // box diagonal, only to remove L's constant null space). Throws InputError for an invalid
  // mesh or a vertex referenced by no face, SolverError when a factorisation fails.
  explicit HeatDistance(const TriMesh& mesh, const HeatDistanceOptions& options = {});
  ~HeatDistance();
  HeatDistance(HeatDistance&&) noexcept;
  HeatDistance& operator=(HeatDistance&&) noexcept;

  // Geodesic distance (metres, ≥ 0 up to discretisation error) from the curve, #V. The curve
  // must come from this mesh (edge ids of its topology). Vertices in connected components the
  // curve does not touch get +∞. Throws InputError for a curve of zero length.
  Eigen::VectorXd distance(const Isoline& curve) const;
  // distance(curve) with the sign of `sign` (#V; ≥ 0 → +), e.g. the biharmonic field φ_b.
  Eigen::VectorXd signedDistance(const Isoline& curve, const Eigen::VectorXd& sign) const;

  double heatTime() const;  // t, m²
  int numVertices() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One-shot signed distance from the zero isoline of `field` (#V), signed by `field` itself.
Eigen::VectorXd signedDistanceFromZeroSet(const TriMesh& mesh, const Eigen::VectorXd& field,
                                          const HeatDistanceOptions& options = {});

}  // namespace s2p

namespace s2p {

// Geodesic distance from a curve by fast marching on the triangle mesh (Kimmel and Sethian
// 1998, the paper's [KS98]). The vertices of every face the curve crosses start with their exact
// in-face distance to the curve's segment; the front then advances in order of distance, each
// vertex taking the smallest of its triangle updates (the planar wave through two accepted
// corners, when it enters the triangle through their edge) and edge updates. Unlike the heat
// method it has no far-field underflow: on a 1.7 m body the heat kernel with t = h² vanishes
// beyond ~50 edge lengths, where the heat method's distance becomes noise.
class FastMarchingDistance {
 public:
  // Throws InputError for an invalid mesh.
  explicit FastMarchingDistance(const TriMesh& mesh);
  ~FastMarchingDistance();
  FastMarchingDistance(FastMarchingDistance&&) noexcept;
  FastMarchingDistance& operator=(FastMarchingDistance&&) noexcept;

  // As HeatDistance::distance / signedDistance (+∞ on components the curve misses).
  Eigen::VectorXd distance(const Isoline& curve) const;
  Eigen::VectorXd signedDistance(const Isoline& curve, const Eigen::VectorXd& sign) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace s2p
