// Sewing and draping a pattern on the body: an XPBD cloth simulator (Macklin et al. 2016, with
// the small-steps scheme of Macklin et al. 2019: many substeps, one iteration each) on the
// panels' flat rest shape, with GarmentCode's two-phase schedule: sew with gravity off until
// the seams close, then drape under gravity until the cloth is at rest.
//
// Constraints, each with a compliance (inverse stiffness) independent of the mesh resolution:
// - stretch + shear: per triangle, the strain of the deformation gradient F = Ds·Dm⁻¹ against
//   the 2D rest triangle (strain-based dynamics, Müller et al. 2014): |F·u| − 1, |F·v| − 1
//   along the pattern's x (weft) and y (warp) directions and F·u·F·v for shear;
// - bending: the isometric bending model (Bergou et al. 2006) around the flat rest state, a
//   linear vector constraint per interior edge;
// - sewing: partner vertices drawn together as the seam's limit shrinks from the start gap to 0,
//   every stitch in proportion to its start gap so that all arrive together (the widest closes
//   at sewSpeed), by at most sewPull of an edge per substep beyond where the cloth left them (a
//   pull that never runs ahead of the cloth); once they meet they are one particle;
// - body: signed distance ≥ thickness (BodySdf), Coulomb friction on the tangential motion;
// - self-collision: vertex–triangle proximity (spatial hash, found again once a vertex has
//   moved half the search's skin, side kept from the search), thickness selfThickness; between
//   panels of different layers (ClothPanel::layer) the side is the layers' order instead: the
//   outer garment's cloth is kept outside the inner one's (near an open stitch neither acts);
// - strain limiting: no edge ends a substep longer than strainLimit × its pattern length.
// Deterministic: constraints are graph-coloured once (greedy, fixed order) and each colour is
// solved in parallel on disjoint vertices; contacts are solved in a fixed order; so the result
// does not depend on the number of threads.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/progress.h"
#include "core/tri_mesh.h"
#include "drape/cloth.h"

namespace s2p {

struct DrapeOptions {
  // === Time integration
  double timeStep = 1.0 / 60;                              // seconds per step (one frame)
  int substeps = 12;                                       // XPBD substeps per step
  int iterations = 1;                                      // constraint iterations per substep
  Eigen::Vector3d gravity = Eigen::Vector3d(0, -9.81, 0);  // m/s², drape phase only
  // 1/s: velocities decay as exp(−damping·t) while draping. The drape check wants the rest
  // state, not the swing: at 10/s (half-life 69 ms) the cloth falls at most g/10 ≈ 1 m/s and
  // comes to rest without swinging past it. The demo's t-shirt + trousers (30 mm, carried to
  // 10 mm): 50 drape steps instead of 80; a rest 4.4 mm (mean) from the one at 4/s, as near the
  // scan or nearer (trousers 7.2 → 6.0 mm mean); bench/RESULTS.md "Drape VI".
  double damping = 10.0;
  double sewDamping = 8.0;  // 1/s while sewing (gravity off): the panels stop flapping
  double maxSpeed = 2.0;    // m/s: velocity clamp (self-collision margin per step)

  // === Cloth (cotton jersey-like defaults)
  double density = 0.15;            // kg/m² of rest area
  double stretchCompliance = 1e-5;  // m/N: inverse membrane stiffness along u and v
  double shearCompliance = 1e-3;    // m/N: inverse in-plane shear stiffness
  double bendingCompliance = 2e5;   // 1/(N·m): inverse bending stiffness (0: rigid)
  // × pattern length: no edge ends a substep longer (0: off). Woven cloth barely stretches: the
  // ±5 % of pattern software. At 1.1 a waistband could stretch over hips 9 % wider than it
  // (plus_size: waistband 1.086 m round, hips 1.186 m), and its trousers slid 11 cm when gravity
  // came on (lower garment 20.4 / 82.9 mm from the scan; 16.8 / 66.4 at 1.05; the other 21
  // presets' p95 within 1.7 mm of their figures at 1.1, bench/RESULTS.md).
  double strainLimit = 1.05;
  int strainLimitPasses = 8;  // Gauss–Seidel passes over the overstretched edges per substep

  // === Collision
  double bodyThickness = 0.0025;  // metres kept between the cloth and the body
  // Coulomb coefficient against the body while draping: GarmentCode's simulator's
  // fabric_friction. At 0.3 plus_size's trousers slid 36 cm down over the hips and piled up at
  // the feet, still creeping after 300 fine steps; at 0.5 they hang from the hips and settle.
  double friction = 0.5;
  double sewFriction = 0.0;  // ... while sewing: the panels slide into place over the body
  double sdfVoxel = 0.004;   // metres, body SDF grid
  bool selfCollision = true;
  double selfThickness = 0.003;  // metres between two layers of cloth
  double selfSkin = 0.005;       // metres searched beyond selfThickness; searched again once a
                                 // vertex has moved half of it (a Verlet list)
  // Metres an outer layer's panel starts further out than placed, where it overlaps (in height)
  // a panel of a lower layer: the flat panels of both garments are placed at one clearance, so
  // a shirt's hem and the trousers' waistband start through one another.
  double layerGap = 0.015;

  // === Schedule (GarmentCode's): sew, then drape
  double sewSpeed = 0.5;  // m/s: the widest stitch closes this fast, the others in proportion
  double sewPull = 0.25;  // an open stitch pulls at most this fraction of its edge per substep
  double sewTolerance = 0.001;  // metres: the seams are closed when every gap is below it
  // Cloth within this many edges of an open stitch passes through other cloth (0: never). Where
  // three or four panels meet (a crotch, a waist under a shirt's hem) the flat panels start
  // across one another, and contacts, which keep the side they were found on, hold the seam
  // open for good; once a stitch is sewn its cloth collides again.
  int sewContactRings = 2;
  int sewMaxSteps = 600;    // step budget of the sewing phase
  int sewStallSteps = 60;   // ... which ends early when, the schedule run out, no stitch was
                            // sewn in this many steps
  int sewSettleSteps = 10;  // steps sewing goes on once the seams are closed
  double restSpeed = 0.01;  // m/s: at rest when no vertex's net motion is faster than this
  int restSteps = 10;       // ... over a window of this many steps, two windows running
  int drapeMinSteps = 30;   // the drape runs at least this many steps
  int drapeMaxSteps = 900;  // step budget of the drape phase

  // === Failure detection
  double explodeSpeed = 50.0;  // m/s: a vertex faster than this (before clamping) → failed
  double explodeStrain = 3.0;  // a triangle stretched beyond this factor → failed

  double jitter = 1e-5;  // metres: seeded noise on the start positions (breaks symmetry)
  unsigned seed = 0;

  // The start is already a drape (a coarser drape carried onto this mesh, coarse_to_fine.h):
  // no panel is wrapped round its limb and vertices closer to the body than the thickness are
  // pushed out without a placement warning.
  bool startsDraped = false;
};

enum class DrapeStatus {
  Settled,     // sewn and at rest
  NotSettled,  // finished the step budget still moving (or with open seams): usable, warned
  Failed,      // unstable (NaN, explosion, cloth left the scene): positions are not a drape
};

const char* toString(DrapeStatus status);

struct DrapeResult {
  DrapeStatus status = DrapeStatus::Failed;
  std::string failure;                // why, when status == Failed
  std::vector<std::string> warnings;  // for report.json: no stitches, panel inside body, ...

  // The cloth after the drape (when Failed: the last finite state, not a drape).
  std::vector<Eigen::MatrixX3d> panels;  // per input panel, #V_p×3
  TriMesh garment;                       // all panels, vertices concatenated in panel order
  std::vector<int> panelOffset;          // #panels+1: garment vertices of panel p

  // === Figures
  int sewSteps = 0;
  int drapeSteps = 0;
  bool seamsClosed = false;   // every stitch sewn (its gap fell below sewTolerance) by the end
  bool settled = false;       // at rest before the drape budget ran out
  double maxStitchGap = 0;    // metres, at the end
  double meanStitchGap = 0;   // metres
  int sewnStitches = 0;       // stitches whose partners met and became one particle
  double maxSewStrain = 1;    // largest triangle stretch (× pattern size) while sewing
  double maxStrain = 1;       // ... over the whole run
  int bodyPenetrations = 0;   // vertices inside the body (exact distance < 0)
  double maxPenetration = 0;  // metres, deepest
  int startInsideBody = 0;    // vertices that started inside the body
  std::vector<std::string> wrappedPanels;  // sewn to themselves: wrapped round their limb
  // The drape phase's rest windows, in order: the largest net motion of a vertex over each window
  // of restSteps steps (m/s) and where that vertex is (panel, vertex, position): what kept the
  // cloth from rest, or how it came to it.
  struct RestWindow {
    int step = 0;
    double speed = 0;
    std::string where;
  };
  std::vector<RestWindow> restWindows;
  int selfIntersections = 0;       // intersecting triangle pairs not sharing a (sewn) vertex
  double seconds = 0;              // wall time of the whole run
  long long constraintSolves = 0;  // projections performed (all kinds)
  double constraintSolvesPerSecond = 0;
  int numConstraints = 0;         // stretch/shear triangles + bending edges + stitches
  int numColours = 0;             // parallel groups
  long long contactSearches = 0;  // self-collision searches (spatial hash rebuilt)
};

// Sews and drapes. Throws InputError for malformed input (sizes, indices out of range,
// non-finite coordinates, degenerate options); a simulation that becomes unstable returns
// status Failed with the reason, never a garbage drape. progress (optional): one stage per
// phase, "LABEL: sew …" and "LABEL: drape …", counting steps against the phase's budget.
DrapeResult runDrape(const DrapeInput& input, const DrapeOptions& options = {},
                     Progress* progress = nullptr, const std::string& label = "drape");

// Intersecting triangle pairs of `mesh` (#F×3) that share no vertex, where `weld` (#V, may be
// empty) maps each vertex to a representative (sewn partners share one).
int countSelfIntersections(const TriMesh& mesh, const std::vector<int>& weld = {});

}  // namespace s2p
