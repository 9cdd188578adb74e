// Flattening of one disk-topology 3D panel into the plane (paper §6.2): Boundary First
// Flattening with u = 0 on the boundary (Sawhney & Crane 2018, "Boundary First Flattening",
// ACM TOG 37(1)), then a local/global refinement that minimises the warp/weft strain of woven
// fabric, then a rigid motion that puts the grain on +y.
//
// === BFF with u = 0 (what flattenBff computes)
//  1. Angles from the 3D triangles; interior angle defects K_i = 2π − Σθ, boundary geodesic
//     curvatures k_i = π − Σθ.
//  2. Cotan Laplacian A split into interior/boundary blocks A_II, A_IB; A_II is factored once.
//  3. Dirichlet-to-Neumann with u_B = 0 (flat target metric e^{2u}g: Δu = K, in weak form
//     A u = −K): A_II u_I = −K_I, then the target boundary curvature
//     k̃ = k + ∂u/∂n = k + A_IBᵀ u_I (Σk̃ = 2π by Gauss–Bonnet, since A's rows sum to zero).
//  4. Target lengths l* = e^{(u_i+u_j)/2} l = l: boundary edges keep their 3D lengths.
//  5. Tangents T_i = (cos φ_i, sin φ_i), φ_i = Σ_{j≤i} k̃_j; the curve is closed by the
//     smallest change of lengths in the norm Σ(l̃−l*)²/l (BFF's mass-matrix projection):
//     l̃ = l* − N⁻¹Tᵀ(TN⁻¹Tᵀ)⁻¹T l*, N⁻¹ = diag(l); γ = cumsum(l̃T).
//  6. Extension: BOTH coordinates of γ are extended harmonically into the interior with the
//     same factor of A_II (BFF's extension for a given target curve, not the
//     conjugate-harmonic one; one factorisation instead of two). The cotan Laplacian
//     reproduces linear functions, so a developable panel comes out exactly isometric; on a
//     curved panel the map is very nearly conformal and the refinement below takes over.
// u = 0 is BFF's "minimal area distortion" setting: among conformal flattenings it minimises
// the Dirichlet energy of the log scale u; the interior still shrinks by e^{2u} where K > 0.
//
// === Warp/weft refinement (what refineWarpWeft computes)
// Energy E(uv) = Σ_f A_f ‖J_f − T_f‖²_F with J_f the 2×2 Jacobian in the face's grain frame
// (grain_frame.h) and T_f the closest matrix whose two columns (the images of a unit warp and a
// unit weft step) have length 1 and make an angle within 90° ± maxShear. Local step: T_f per
// face (closed form); global step: L uv = Σ_f A_f T_f ∇φ with L the 3D cotan Laplacian, one
// vertex pinned, factored once. maxShear = 0 is ARAP (T_f a rotation); shear is what cloth
// does cheaply, so it is allowed up to maxShear. Starts from BFF; no step is taken that
// inverts more faces than the current iterate has: a flip-free start stays flip-free, a start
// with inverted faces (BFF on a very curved panel) can only lose them. A third term keeps boundary
// edges at their 3D lengths: Σ_e w_e ‖(q_j − q_i) − l_e d_e‖², d_e the edge's current direction
// (local step), weighted by boundaryWeight (seam lengths matter to stitching).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/tri_mesh.h"

namespace s2p {

struct FlattenOptions {
  bool refine = true;         // run the warp/weft local/global pass after BFF
  int refineIterations = 20;  // at most this many local/global iterations
  double tolerance = 1e-4;  // stop when an iteration lowers the energy by less than this (relative)
  double maxShear = 0.35;   // rad (≈ 20°): allowed deviation of the warp–weft angle from 90°
  // Weight of the boundary edges' lengths in the refinement (dimensionless: 1 weighs the
  // boundary at strain ε like the whole area at strain ε). The sheared warp/weft fit of a
  // doubly curved panel shortens edges oblique to the grain (a 20° spherical cap: boundary
  // −1.5 %, a 40° cap −6 %); the term pulls them back but slowly and at a cost in strain (20°
  // cap, weight 0.3: boundary −1.0 %, warp p95 0.15 % → 0.74 %). Off by default: strain is
  // what the fabric feels; uvBff keeps the exact seam lengths.
  double boundaryWeight = 0.0;
  bool alignGrain = true;  // rotate so that the mean image of the grain is +y
};

struct PanelFlattening {
  Eigen::MatrixX2d uv;              // #V×2, metres: the result (refined when options.refine)
  Eigen::MatrixX2d uvBff;           // #V×2, metres: BFF (folds repaired), same frame conventions
  Eigen::VectorXd logScale;         // #V: BFF's conformal log scale factor u (0 on the boundary)
  std::vector<int> boundary;        // the boundary loop, vertex indices, counter-clockwise in uv
  double energyBff = 0.0;           // warp/weft energy Σ A‖J − T‖² of uvBff (m²)
  double energy = 0.0;              // same for uv
  int iterations = 0;               // local/global iterations run
  int rejectedIterations = 0;       // steps discarded because they inverted faces
  bool refinementReverted = false;  // the refined boundary overlapped itself: uv = uvBff
  int bffInvertedFaces = 0;         // faces BFF folded, before their repair (flip_repair.h)
  int boundarySpikes = 0;  // boundary vertices of slivers thrown out and put back (BFF + refined)
  double seconds = 0.0;             // wall time of flattenPanel
};

// Flattens a disk-topology panel. grain: the 3D direction that becomes the pattern's +y (the
// garment's vertical; need not be unit). name: the panel's name for error messages.
// uv is counter-clockwise (faces keep their orientation), its area centroid at the origin, the
// area-weighted mean image of the unit warp step along +y (alignGrain).
// Throws InputError for an empty mesh, non-finite coordinates, out-of-range indices, a vertex
// no face uses, a zero-area face or a bad grain; TopologyError for a non-manifold mesh, more
// than one piece, inconsistent orientation, no boundary, more than one boundary loop or
// Euler characteristic ≠ 1; SolverError if a factorisation fails.
PanelFlattening flattenPanel(const TriMesh& panel, const Eigen::Vector3d& grain,
                             const std::string& name, const FlattenOptions& options = {});

// One panel of a batch for flattenPanels.
struct PanelToFlatten {
  const TriMesh* mesh = nullptr;  // the 3D panel (not owned)
  Eigen::Vector3d grain = Eigen::Vector3d::UnitY();
  std::string name;
};

// Outcome of one panel in flattenPanels: the flattening, or the error that stopped it.
struct PanelFlatteningOutcome {
  std::optional<PanelFlattening> flattening;  // set when the panel flattened
  std::string error;                          // the s2p::Error's message otherwise
  ExitCode errorCode = ExitCode::Ok;          // and its exit code (Input, Topology, Solver)
};

// Flattens every panel (in parallel, TBB); a panel that throws an s2p::Error gets its message
// in the outcome and the others are still flattened. Outcomes in the order of panels.
std::vector<PanelFlatteningOutcome> flattenPanels(const std::vector<PanelToFlatten>& panels,
                                                  const FlattenOptions& options = {});

// Where two seam lines meet, the cut can leave slivers a fraction of a millimetre across at the
// boundary, and a flattening can throw such a sliver's free corner centimetres out: its area
// weighs next to nothing in the energies. A boundary vertex whose 2D edges are more than 4 times,
// and 2 mm longer than, its 3D edges is put back where its faces place it: each face laid out
// from its other two corners with its 3D shape (scaled to their 2D distance), averaged over its
// faces. Returns how many vertices moved. flattenPanel does this to BFF's and the refined result.
int pullInBoundarySpikes(const TriMesh& panel, const std::vector<int>& boundary,
                         Eigen::MatrixX2d& uv);

// The input checks of flattenPanel alone (throws as documented there); returns the boundary
// loop (vertex indices, in the orientation of the faces).
std::vector<int> checkFlattenablePanel(const TriMesh& panel, const std::string& name);

// BFF with u = 0 on the boundary (steps 1–6 above), no rotation or centring. logScale: #V,
// optional output. Same checks and errors as flattenPanel.
Eigen::MatrixX2d flattenBff(const TriMesh& panel, const std::string& name,
                            Eigen::VectorXd* logScale = nullptr);

// Result of refineWarpWeft.
struct WarpWeftRefinement {
  Eigen::MatrixX2d uv;         // #V×2, metres
  double energyStart = 0.0;    // warp/weft (area) energy of the start (m²)
  double energyEnd = 0.0;      // of uv (the boundary term is not included)
  int iterations = 0;          // local/global iterations run
  int rejectedIterations = 0;  // steps discarded because they inverted faces
};

// Warp/weft local/global refinement (above) of a start uv0 (#V×2, best flip-free) of the
// checked panel. options.refineIterations, tolerance, maxShear and boundaryWeight apply.
WarpWeftRefinement refineWarpWeft(const TriMesh& panel, const Eigen::Vector3d& grain,
                                  const Eigen::MatrixX2d& uv0, const FlattenOptions& options = {});

// === Seam truing
// A pattern maker "trues" a seam: the two edges that are sewn together must have the same
// length, or one of them has to be eased in. Two panels are flattened independently and their
// strain fits shorten oblique edges differently (a few mm on a side seam), so each pair is
// given a common length (the caller's choice, e.g. the mean of the two) and every panel is
// moved to it: the same local/global iteration, with the boundary term on the target chains
// only, each of their edges asking for its current length × target/current chain length. The
// change asked for is small (millimetres), so a strong weight costs little strain.

struct BoundaryLengthTarget {
  std::vector<int> vertices;  // a chain of boundary vertices, in order
  double length = 0.0;        // its 2D length to reach (m)
};

struct SeamTruing {
  double weight = 50.0;      // of the chains' edges, as FlattenOptions::boundaryWeight
  int rounds = 4;            // targets re-scaled from the current lengths each round
  int iterations = 4;        // local/global iterations per round
  double tolerance = 2e-4;   // m: stop when every chain is this close to its target
};

// uv0: a flip-free flattening of the checked panel. Returns the trued uv (no face inverted
// that was not inverted in uv0; the same rigid frame up to the pinned vertex's drift).
Eigen::MatrixX2d trueBoundaryLengths(const TriMesh& panel, const Eigen::Vector3d& grain,
                                     const Eigen::MatrixX2d& uv0,
                                     const std::vector<BoundaryLengthTarget>& targets,
                                     const FlattenOptions& options = {},
                                     const SeamTruing& truing = {});

// Warp/weft energy Σ_f A_f ‖J_f − T_f‖²_F of uv (m²), T_f as in the local step.
double warpWeftEnergy(const TriMesh& panel, const Eigen::Vector3d& grain,
                      const Eigen::MatrixX2d& uv, double maxShear);

// Rotates uv about its area centroid so that the area-weighted mean image of the unit warp
// step points along +y, and moves the centroid to the origin.
Eigen::MatrixX2d alignToGrain(const TriMesh& panel, const Eigen::Vector3d& grain,
                              const Eigen::MatrixX2d& uv);

}  // namespace s2p
