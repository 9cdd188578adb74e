// The biharmonic implicit function of §5.1.3, Eq. (1): φ_b = argmin ∫(Δu)² dA subject to
// u = 0 at the spline points and u = c at the sign points, all given as surface points
// (barycentric constraints inside faces or on edges, never snapped to vertices).
//
// Discretisation: energy uᵀ(L M⁻¹ L)u with the cotan L and the lumped (Voronoi) mass M.
// Constraints are HARD: C u = v is enforced by an augmented Lagrangian on the SPD matrix
// Q + w CᵀC (w = penaltyWeight × mean diag Q, so it is independent of mesh scale and
// resolution); a few multiplier updates on the same factor drive |Cu − v| below `tolerance`.
// Because every constraint couples vertices of one face, CᵀC lies inside the pattern of Q and
// each new set of constraints is a numeric refactorisation only.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "core/surface_point.h"
#include "core/tri_mesh.h"
#include "segment/isoline.h"

namespace s2p {

struct ValueConstraint {
  SurfacePoint point;
  double value = 0;
};

struct BiharmonicOptions {
  double penaltyWeight = 1e6;  // w relative to the mean diagonal of L M⁻¹ L
  int maxMultiplierUpdates = 30;
  double tolerance = 1e-9;  // max |Cu − v| (in units of the constraint values)
};

struct BiharmonicStats {
  int multiplierUpdates = 0;
  double maxResidual = 0;   // max |Cu − v| reached
  bool refactored = false;  // numeric refactorisation only (symbolic analysis reused)
  int unconstrainedPieces = 0;  // pieces holding no constraint: the nearest solved value
};

class Biharmonic {
 public:
  // Builds L M⁻¹ L (+ a tiny mass term, relative to its scale) and finds the mesh's pieces. Throws
  // InputError for an invalid mesh or a vertex referenced by no face.
  explicit Biharmonic(const TriMesh& mesh, const BiharmonicOptions& options = {});
  ~Biharmonic();
  Biharmonic(Biharmonic&&) noexcept;
  Biharmonic& operator=(Biharmonic&&) noexcept;

  // φ_b, #V. The pieces (connected components) holding constraints are solved; a piece holding
  // none takes the value at the nearest vertex of a solved piece (a constant: it lies on that
  // side of every curve). Throws InputError for no constraints, a face out of range or
  // non-finite or non-normalised barycentric weights; SolverError when the factorisation fails.
  Eigen::VectorXd solve(const std::vector<ValueConstraint>& constraints);
  const BiharmonicStats& lastStats() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One-shot version.
Eigen::VectorXd biharmonicFunction(const TriMesh& mesh,
                                   const std::vector<ValueConstraint>& constraints,
                                   const BiharmonicOptions& options = {});

// Zero constraints at every point of an isoline (the "fitted spline" C of Algorithm 1, line 6).
std::vector<ValueConstraint> zeroConstraints(const Isoline& isoline);

}  // namespace s2p
