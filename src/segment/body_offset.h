// Geometric cues for the displacement function (issue 18; the paper's §8 names geometry as the
// way past colour): how far the scan lies off the body fitted under the clothes (§4), and where
// that offset steps. A garment rides on the body by its ease and ends in a riser: across a hem
// the offset drops by the ease (a t-shirt over trousers, a sleeve over the bare arm), while
// bare skin lies on the body. The step field
//   h = S_s(o) − S_L(o)        (o: the offset, S_ℓ: implicit diffusion over ℓ metres)
// is positive on the high (outer garment) side of a step and negative on the low side, crosses
// zero on the riser and fades as exp(−x/L) with the geodesic distance x from it (the kernel of
// one backward Euler step), so a hem pulls a boundary from about 5L away and the smooth changes
// of the ease (∝ L²Δo) stay small. Where the colour models of the two sides cannot tell them
// apart, the step field takes over the displacement (combinedDisplacement), and between bare skin
// and a garment the offset itself joins it (offsetDisplacement): skin lies on the body, a garment
// off it by its ease.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/mesh_query.h"
#include "core/surface_point.h"
#include "core/tri_mesh.h"

namespace s2p {

struct GeometricCueOptions {
  bool enabled = true;  // with a body under the clothes; without one the cues are off
  // m: smoothing of the offset before the step detector, a few scanner-noise σ (1–2 mm).
  double noiseLength = 0.003;
  // m: L, the reach of a step (the diffusion length whose difference finds it): a hem pulls the
  // boundary from ≈ 5L; smooth changes of the ease give |h| ≈ L²|Δo|, small for L ≪ a limb.
  double stepReach = 0.03;
  // m: a step this high (a fabric fold and a few mm of ease) gets the full vote: |h| ≥ half of it.
  double stepHeight = 0.005;
  // m: |h| below this is no vote: the ease's own ups and downs (a t-shirt lying on the shoulders
  // and off the chest) and the fit's give |h| ≲ 0.7 mm on the suite, a hem of ≥ 5 mm ≥ 2 mm.
  double stepDeadZone = 0.001;
  // CIEDE2000 between the two sides' colours (the median ΔE of one side's region points from
  // the other's mean, the larger of the two ways: a red-and-white striped dress has a pinkish
  // mean near skin, but none of its points is skin): at or below `blindDeltaE` the colour cannot
  // tell them (the ±6 % shading of a scan moves a colour by ~3 ΔE) and the step decides alone;
  // at or above `clearDeltaE` (twice the layout's "same colour") colour decides as in the paper;
  // in between the two are blended linearly.
  double blindDeltaE = 5.0;
  double clearDeltaE = 20.0;
  // m: a region whose points lie farther than this off the fitted body (median) is clothed,
  // whatever its colour: the fit keeps the body inside the scan within ~5 mm, bare skin lies on
  // it, a garment lies off it by its ease (≥ 1 cm) plus the fabric.
  double garmentOffset = 0.006;
  // m: the median step vote (hemContrast) a waist boundary must show for upper and lower of one
  // colour to be two garments: a fifth of stepHeight, half what a hem of that height gives.
  double hemContrast = 0.001;
  // The offset itself as a displacement between bare skin and a garment (offsetDisplacement):
  // bare skin lies on the fitted body within its fit error, a garment off it by its ease. The
  // two levels are this scan's own: the median offset of the skin region points (face and
  // hands) and of the garment's region points (chest and back; hips and thighs). Used only
  // where colour cannot tell skin from the garment (scaled by the steps' weight, geometryWeight)
  // and when the garment lies at least `offsetGap` (m) farther off the body than the skin: a
  // fitted body pushed into a loose top's ease leaves 2–3 mm, a bare torso ≲ 1 mm.
  double offsetGap = 0.0015;
  // Weight of the offset term beside the colour, times the geometry weight (the steps weigh 2):
  // half the colour's at most, as the fit error on a bare arm (1–1.5 mm on the suite) reaches
  // half the gap between skin and a top; at 1 a sleeveless top's bare upper arms were taken for
  // garment (close_to_skin IoU 0.953, at 0.5 0.961, at 0.3 0.937).
  double offsetWeight = 0.5;
};

// Signed distance (m) from every vertex of `scan` to the body `underBody` (the shape-and-pose
// fit, not the full fit of §5.1.2, which follows the clothes): > 0 outside, by the normal of the
// closest face. #V. `bodyNormal`, when given, receives that face's unit normal (#V×3).
Eigen::VectorXd bodyOffset(const TriMesh& scan, const MeshQuery& underBody,
                           const TriMesh& underBodyMesh, Eigen::MatrixX3d* bodyNormal = nullptr);

// The offset (m) at each of `points` on `scan`: its nearest corner's (as a region point's
// colour is its nearest vertex's). offset: #V. Throws InputError for a point off the mesh.
std::vector<double> offsetsAt(const TriMesh& scan, const Eigen::VectorXd& offset,
                              const std::vector<SurfacePoint>& points);

// A region is clothed when the median of its points' offsets (m) exceeds garmentOffset: bare
// skin lies on the fitted body, a garment off it by its ease. false for no offsets.
bool offsetSaysClothed(const std::vector<double>& offsets, const GeometricCueOptions& options = {});

// h = S_noise(o) − S_L(o) in metres, #V (see the top). offset: #V. `smoothedOffset`, when
// given, receives S_noise(o) (#V, m): the offset without the scanner's noise.
Eigen::VectorXd stepField(const TriMesh& scan, const Eigen::VectorXd& offset,
                          const GeometricCueOptions& options = {},
                          Eigen::VectorXd* smoothedOffset = nullptr);

// The step field as a displacement in [−1, 1]: 0 for |h| ≤ stepDeadZone, rising linearly to ±1
// at |h| = stepHeight / 2, times `highSide`
// (+1 when the boundary's positive side is the outer garment: the upper garment over the lower;
// −1 when it is skin or what a garment covers: B(U|S), B(L|S), a tucked-in top).
Eigen::VectorXd stepDisplacement(const Eigen::VectorXd& step, double highSide,
                                 const GeometricCueOptions& options = {});

// The offset as a displacement between bare skin (+1) and a garment (−1): +1 at or below
// `skinLevel`, −1 at or above `garmentLevel` (m), linear between. offset: #V. Throws InputError
// when garmentLevel ≤ skinLevel.
Eigen::VectorXd offsetDisplacement(const Eigen::VectorXd& offset, double skinLevel,
                                   double garmentLevel);

// Weight of geometry for two sides whose mean colours are `deltaE` apart (CIEDE2000): 1 at or
// below blindDeltaE, 0 at or above clearDeltaE, linear between.
double geometryWeight(double deltaE, const GeometricCueOptions& options = {});

// φ_d = clamp(φ_colour + 2w·φ_step, −1, 1): colour alone at w = 0 (the paper's Eq. 2); at w = 1
// a step overrides any colour (2 > |φ_colour|) while away from the steps (φ_step ≈ 0) the colour
// still drives the boundary, however weakly it tells the sides apart.
Eigen::VectorXd combinedDisplacement(const Eigen::VectorXd& colour, const Eigen::VectorXd& step,
                                     double weight);

// Which side of the steps near the curve φ₀ = 0 is the outer one: the area-weighted mean of
// ∇o·∇φ₀ over the faces whose corners all carry a step (|h| > stepHeight / 4) within `band`
// metres of the curve. > 0: the offset grows toward φ₀'s positive side there (the positive side
// is the outer garment, e.g. a top worn over the trousers); < 0: the negative side is; 0 when no
// step lies near the curve.
double stepOrientation(const TriMesh& mesh, const Eigen::VectorXd& offset,
                       const Eigen::VectorXd& step, const Eigen::VectorXd& phi0, double band,
                       const GeometricCueOptions& options = {});

// Median step vote (m) in the band |φ| < stepReach / 2 around the zero isoline of φ (a signed
// distance): s·h on the positive half, −s·h on the negative half, s = highSide (+1: the outer
// garment on φ's positive side). A hem of height Δ gives ≈ 0.4Δ; a boundary off any hem a few
// tenths of a millimetre. A one-piece test for colours that cannot tell upper from lower.
double hemContrast(const TriMesh& mesh, const Eigen::VectorXd& phi, const Eigen::VectorXd& step,
                   double highSide, const GeometricCueOptions& options = {});

}  // namespace s2p
