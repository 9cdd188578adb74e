// Boundary curve optimisation, the paper's Algorithm 1 (§5.1.3–5.1.5) as written — the
// faithful path: every iteration adds the colour displacement (Eq. 3), regularises the length
// by backward Euler (Eq. 4), extracts the zero isoline, recomputes the biharmonic function with
// the isoline points as zero constraints plus the sign points (Eq. 1), and recomputes the
// signed geodesic distance from the biharmonic's zero isoline. The zero set may change
// topology (two ankle loops → one hem loop): any number of loops is handled.
//
// Units (the paper does not state them; these make the result independent of mesh resolution
// and scale). φ is a signed distance in metres (|∇φ| = 1), so adding α·φ_d with |φ_d| ≤ 1
// moves the boundary by at most α metres per iteration: α is in METRES (scale it with body
// height H; the paper's 0.01 is 1 cm for a 1.7 m person). Eq. (4) is one backward Euler step
// of heat flow for a time β: (M + βL)φ̄ = Mφ̃, β in SQUARE METRES, √β the regularisation
// length (a loop of geodesic curvature κ shrinks by ≈ βκ per iteration). Scaling the mesh by s
// with α → sα, β → s²β, tolerance → s²·tolerance gives the same boundary scaled by s.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "core/mesh_topology.h"
#include "core/surface_point.h"
#include "core/tri_mesh.h"
#include "segment/biharmonic.h"
#include "segment/geodesic.h"
#include "segment/isoline.h"

namespace s2p {

// How the signed geodesic distance φ is computed from the isoline (§5.1.3).
enum class GeodesicMethod {
  FastMarching,  // the paper's choice [KS98]; accurate everywhere (the default)
  Heat           // heat method: prefactored, but its far field is noise beyond ~50 edge lengths
};

struct BoundaryOptions {
  double alpha = 0.01;   // m of boundary motion per iteration, Eq. (3)
  double beta = 2.5e-5;  // m², length regularisation time, Eq. (4) (√β = 5 mm)
  int maxIterations = 200;
  double tolerance = 1e-6;  // m²: stop when ∫(φᵢ₊₁ − φᵢ)² dA / A falls below (1 mm RMS)
  // true: Algorithm 1 as written (biharmonic recomputed every iteration). false, the default:
  // the fast variant — the signed distance is taken from the regularised isoline directly
  // (signed by φ̄), skipping the biharmonic in the loop (φ₀ still uses it). It became the
  // default when the suite showed it reaches the same boundaries (DESIGN.md, "A faithful path
  // and a fast path"; tolerance 0.5 mm mean and 3 mm p95 per preset, measured at most 0.02 mm
  // and 0.46 mm over the 19 presets, bench/RESULTS.md), 3–4× faster.
  bool faithful = false;
  // φ₀: curves of the first biharmonic that pass next to no zero constraint are dropped and the
  // regions re-signed from the sign points (a boundary lies on its spline; stray loops are the
  // biharmonic's extrapolation). Seams keep them: a t-shirt's front/back seam also runs over the
  // shoulder, where no spline was drawn (§6.1).
  bool dropStrayCurves = true;
  GeodesicMethod geodesic = GeodesicMethod::FastMarching;
  HeatDistanceOptions heat;
  BiharmonicOptions biharmonic;
};

// Wall-clock seconds spent in each step, summed over the run.
struct BoundaryTimings {
  double setup = 0;           // operators and factorisations built once per mesh
  double regularisation = 0;  // Eq. (3) + Eq. (4) solve
  double isoline = 0;         // isoline extraction (both)
  double biharmonic = 0;      // numeric refactorisation + constrained solves
  double geodesic = 0;        // signed distance (fast marching or heat-method solves)
  double total = 0;
};

struct BoundaryResult {
  Eigen::VectorXd phi0;  // #V, φ₀: the initial signed distance (m)
  Eigen::VectorXd phi;   // #V, final signed distance (m), > 0 on the positive side
  Isoline initial;      // zero isoline of φ₀
  Isoline boundary;     // zero isoline of the final φ: the optimised boundary
  int iterations = 0;
  bool converged = false;       // change fell below tolerance within maxIterations
  bool vanished = false;        // the zero set disappeared (one side swallowed the mesh)
  std::vector<double> changes;  // per iteration, m²
  BoundaryTimings timings;
};

class BoundaryOptimizer {
 public:
  // Builds L, M, factors (M + βL) and the heat-method matrices, and L M⁻¹ L. Throws InputError
  // for an invalid mesh or options.
  BoundaryOptimizer(const TriMesh& mesh, const BoundaryOptions& options = {});
  ~BoundaryOptimizer();
  BoundaryOptimizer(BoundaryOptimizer&&) noexcept;
  BoundaryOptimizer& operator=(BoundaryOptimizer&&) noexcept;

  // φ₀: biharmonic with zero at the spline points and the sign values, then the signed distance
  // from its zero isoline (Algorithm 1, line 2).
  Eigen::VectorXd initialImplicit(const std::vector<std::vector<SurfacePoint>>& splines,
                                  const std::vector<ValueConstraint>& signs);
  // One implicit-function recomputation (Algorithm 1, lines 6–7) from any field whose zero
  // isoline is the current curve. Empty result when the field has no zero crossing.
  Eigen::VectorXd recomputeImplicit(const Eigen::VectorXd& field,
                                    const std::vector<ValueConstraint>& signs);

  // Algorithm 1. splines: the initial curves as surface points (any number); signs: sign
  // points with their values (±1); phiD: #V displacement in [−1, 1], positive where the
  // positive side should grow. Throws InputError for empty splines and signs, wrong sizes,
  // or no sign point with a non-zero value.
  BoundaryResult run(const std::vector<std::vector<SurfacePoint>>& splines,
                     const std::vector<ValueConstraint>& signs, const Eigen::VectorXd& phiD);
  // Algorithm 1 from lines 3–8 with a given φ₀ (a signed distance, e.g. a previous run's φ):
  // the second pass of §5.2 (Eq. 6). tolerance: m², 0 for the options'; a pass where only part
  // of the mesh can move measures its change over that part (tolerance × its area share). Throws
  // as run, and for a φ₀ of the wrong size or a negative tolerance.
  BoundaryResult iterate(const Eigen::VectorXd& phi0, const std::vector<ValueConstraint>& signs,
                         const Eigen::VectorXd& phiD, double tolerance = 0);

 private:
  void checkInputs(const std::vector<ValueConstraint>& signs, const Eigen::VectorXd& phiD) const;
  BoundaryResult iterateFrom(const Eigen::VectorXd& phi0,
                             const std::vector<ValueConstraint>& signs,
                             const Eigen::VectorXd& phiD, double tolerance);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// ±1 per vertex, or φ_b's own value where it agrees: the regions between the curves of `iso`
// (flood fill over the edges no curve crosses) take the sign of the sign points they hold
// (constraints with a non-zero value), else the sign of the non-zero `votes` over most of their
// area (area: #V lumped mass). How the iteration signs the distance from φ_b's zero set
// (§5.1.3).
Eigen::VectorXd regionSigns(const TriMesh& mesh, const MeshTopology& topology,
                            const Eigen::VectorXd& area, const Isoline& iso,
                            const Eigen::VectorXd& phiB,
                            const std::vector<ValueConstraint>& constraints,
                            const Eigen::VectorXd& votes);

// Regions of either sign with less than `minArea` (m²) that hold no sign point take the sign of
// their surroundings (φ → −φ there): specks of a garment's print that look like the other side
// (a yellow dot on a shirt above khaki trousers) survive the length regularisation as small
// loops. Nested ones take the side of the region they lie in, outward from the regions that keep
// theirs, so that an island inside an island leaves no loop. Returns the number of regions
// flipped.
int removeIslands(const TriMesh& mesh, Eigen::VectorXd& phi, double minArea,
                  const std::vector<ValueConstraint>& signs);

// A labelled region point (the body's face, hands, chest, hips, feet: RegionPoint) located on
// the mesh, with the side of a boundary its label belongs on (+1 or −1).
struct SideVote {
  SurfacePoint point;
  double side = 1;
};

// What sidePiecesByVotes found on one piece that no curve crosses.
struct PieceSide {
  int piece = 0;       // connected component of the mesh
  int vertices = 0;
  int positiveVotes = 0, negativeVotes = 0;
  bool flipped = false;  // its side changed
};

// A connected piece of the mesh that holds none of the boundary's zero constraints (`anchors`: no
// spline lies on it) and that φ's zero isoline does not cross lies wholly on one side, and which
// one is decided by nothing but the balance of the displacement over it: a knife edge when the
// two sides' colours are alike (a beige knee skirt whose legs are a piece of their own: 2 mm of
// fit round-off once sent it to the skin side). Such a piece takes the side the labelled region
// points on it vote for, when at least `minVotes` lie on it and a share of at least `minShare`
// agree; φ there changes sign (magnitude kept). Returns one record per such piece.
std::vector<PieceSide> sidePiecesByVotes(const TriMesh& mesh, Eigen::VectorXd& phi,
                                         const std::vector<SurfacePoint>& anchors,
                                         const std::vector<SideVote>& votes, int minVotes = 4,
                                         double minShare = 0.75);

// One-shot version.
BoundaryResult optimizeBoundary(const TriMesh& mesh,
                                const std::vector<std::vector<SurfacePoint>>& splines,
                                const std::vector<ValueConstraint>& signs,
                                const Eigen::VectorXd& phiD, const BoundaryOptions& options = {});

}  // namespace s2p
