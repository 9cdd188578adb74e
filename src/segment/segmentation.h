// The whole garment segmentation of paper §5: feature projection, the three boundaries in the
// paper's order B(U|S) → B(L|S) → B(U|L), each optimised by Algorithm 1 on what the previous
// cut left, gap-filling triangles (§5.2), the upper/lower split with one-piece and occlusion
// detection and the completion of the occluded garment (§5.3), plus what the paper does not
// do: detecting a missing upper or lower garment and reporting boundaries that did not
// converge.
//
// Sign conventions follow the feature set (body/features.h): φ > 0 on the skin side of B(U|S)
// (nose, hand tips), on the foot side of B(L|S) (toes, soles) and on the upper side of B(U|L)
// (chest).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "body/features.h"
#include "core/labels.h"
#include "core/progress.h"
#include "core/tri_mesh.h"
#include "segment/body_offset.h"
#include "segment/boundary_optimizer.h"
#include "segment/colour_model.h"
#include "segment/mrf.h"
#include "segment/non_garment.h"
#include "segment/projection.h"

namespace s2p {

enum class GarmentLayout {
  UpperLower,  // separate upper and lower garments
  OnePiece,    // one garment over upper and lower body (dress; §5.3 skips B(U|L))
  UpperOnly,   // no lower garment: the legs are bare
  LowerOnly    // no upper garment: the torso is bare
};
const char* toString(GarmentLayout layout);

// Which garment the other hides at the waist (§5.3).
enum class Occlusion { None, LowerOccluded, UpperOccluded };
const char* toString(Occlusion occlusion);

struct SegmentationOptions {
  BoundaryOptions boundary;
  // σ ≥ 5 ΔE in lightness per mixture component: colours under scan lighting vary by several
  // ΔE, and with tighter components a colour a little off the face's skin falls in the tails of
  // every mixture, where the broadest one wins whatever the hue. That spread is lightness:
  // shading, a key light and occlusion scale a surface's luminance, which moves L* by its full
  // amount but a* and b* only by the cube root of the scale (CIELAB's f(t) = t^⅓ acts on X, Y,
  // Z alike: 30 % darker shrinks a skin's chroma of ~20 by ~2). So a* and b* are floored at σ 2
  // ΔE, not 5: a beige top 8 ΔE off the skin, 5 of them in hue and chroma (close_to_skin), lay
  // within one σ of the skin in every axis at σ 5 and is told from it by its chroma at σ 2. The
  // lightness floor stays: a garment lighter on its lit side than its shaded side still holds
  // its whole range (a lightness-only floor of σ 10 took a white top's shade for skin).
  ColourModelOptions colour = [] {
    ColourModelOptions c;
    c.gmm.covarianceFloor = 25.0;
    c.gmm.chromaFloor = 4.0;
    return c;
  }();
  ProjectionOptions projection;  // bodyLength is set from the body's height
  double splineSpacing = 0.005;  // m between samples of the initial surface spline
  // §5.2: the second pass with the normal displacement (Eq. 5–6) replaces the first pass's
  // boundary when it moves it by more than this (m, 95th percentile of the distances between
  // the two, so that a gap bridged over part of a hem counts): a gap was bridged. Below, the
  // first pass stands (on a scan without gap triangles Eq. 6 only nudges the boundary over the
  // hem's riser, 2–6 mm).
  double gapMinShift = 0.01;
  // §5.2: in the second pass gap-filling triangles push off the garment whatever their colour:
  // vertices facing along the boundary's plane normal whose inward normal meets no body within
  // twice this (m), in a connected set reaching farther than this from the body (the body under
  // the clothes when given; segmentation.cpp, gapVertices). A fitted hem's riser spans its ease
  // (the generator's reach 1.9 cm at a hem); the cap closing a loose sleeve around the wrist spans
  // 3–4 cm and the one under a skirt more (5 cm missed jacket_layered's cuffs).
  double gapReach = 0.03;
  // ... and is not in the garment's colour beside it: a set whose median colour lies within
  // this ΔE00 of the garment's within gapReach of it is cloth (a collar, the surface closing a
  // thick garment's edge). 2 is CIEDE2000's just-noticeable difference, as for held objects.
  // Width alone cannot tell them apart: the outside test scans' shells close 3–4.6 cm from the
  // fitted body under the clothes, in the garment's colour, and are labelled cloth.
  double gapSameColourDeltaE = 2.0;
  bool gapFilling = true;
  // With the body under the clothes, the second pass's φ_dn (Eq. 5) counts only where the scan
  // turns away from that body: fully where its normal lies 60° or more off the body's (a riser,
  // a cap), not within 30° (segmentation.cpp, onlyWhereTurnedAway).
  bool gapOnlyWhereTurnedAway = true;
  // §5.3 and the missing-garment tests: two regions are "the same colour" when the CIEDE2000
  // difference of their mean CIELAB colours is below this; a garment is missing when its region
  // is the skin's colour in this sense and most of its points are within this of the skin's.
  double sameColourDeltaE = 10.0;
  // The person's own skin (issue 18): a region point is skin-like when it lies within
  // skinSpreadFactor × the 90th percentile of the skin region's own ΔE from its mean (the face
  // and hands of this scan: its skin under this scan's light), floored at minSkinDeltaE and
  // capped at sameColourDeltaE. A bare torso is drawn from the same skin and spreads alike; a
  // top of a skin-like tone lies outside this person's spread.
  double skinSpreadFactor = 2.0;
  double minSkinDeltaE = 3.0;
  // The step and offset cues (segment/body_offset.h), used when segmentScan is given the body
  // fitted under the clothes.
  GeometricCueOptions geometry;
  // Held objects (a bag), found with the body under the clothes and cut away before B(U|S),
  // labelled Other; hair, cut away with the skin by B(U|S), labelled Hair (segment/non_garment.h).
  bool heldObjects = true;
  HeldObjectOptions held;
  bool hair = true;
  HairOptions hairOptions;
  // §5.3: the optimised waist boundary is "close to" the initial one when its mean height
  // differs by less than this (m); otherwise the garment on the lower side is occluded.
  double occlusionShift = 0.03;
  // Regions a boundary leaves on either side that are smaller than this (m²) and hold no sign
  // point are merged into their surroundings: specks of a print, not garments (a hand is
  // ~0.03 m², a shoe ~0.05 m²).
  double minRegionArea = 0.01;
  // Issue 17: a part of the scan with more than 1.5 × this many vertices has its boundary
  // optimised on a decimated copy of about this many (core/coarse_mesh.h), and is cut
  // exactly along it on the full mesh; 0 optimises every boundary at full resolution.
  int coarseVertices = 100000;
};

// One optimised boundary.
struct BoundaryReport {
  std::string name;  // "U|S", "L|S", "U|L"
  Label garment = Label::Upper;  // the garment side's label
  Label other = Label::Skin;     // the other side's main label
  std::vector<Eigen::MatrixX3d> initialCurves, finalCurves;  // polylines, metres
  std::vector<bool> initialClosed, finalClosed;
  std::vector<Label> otherLabels;  // per final curve: the label beyond it (skin or shoes)
  int anchors = 0, droppedAnchors = 0;  // spline anchors projected, and dropped (App. B)
  int signs = 0, droppedSigns = 0;
  int iterations = 0;  // of the pass kept
  bool converged = false;
  bool vanished = false;    // the zero set disappeared: one side took the whole mesh
  bool skipped = false;     // no spline or sign point on what was left: nothing cut (a note says why)
  bool gapPass = false;     // the Eq. 6 pass was run
  bool gapApplied = false;  // ... and its boundary was kept
  double gapShift = 0;      // 95th percentile distance (m) between the two passes' boundaries
  // A second pass pushed the vertices of a colour both sides hold toward the plane of the first
  // pass's curve (B(U|L) of garments sharing a colour).
  bool planePass = false;
  // Per connected set of gap candidates reaching past gapReach: its ΔE00 from the garment beside
  // it, and whether it was taken as a gap (else cloth in the garment's colour).
  std::vector<std::pair<double, bool>> gapSetDeltaE;
  int islandsRemoved = 0;   // regions below minRegionArea merged into their surroundings
  double geometryWeight = 0;  // weight of the step field in the displacement (0: colour alone)
  double highSide = 0;        // +1: the outer garment on the positive side; −1: on the negative
  double hemContrast = -1;    // B(U|L) of one colour: median step vote (m) at it (−1: not asked)
  double seconds = 0;
  BoundaryTimings timings;
  // Vertices of the mesh Algorithm 1 ran on: the part of the scan left, or its decimated copy.
  int optimisedVertices = 0;
  double coarseSeconds = 0;  // making the copy and carrying φ back to the full mesh
};

// A cut garment: part of the scan, each face inside one scan face.
struct GarmentPiece {
  std::string name;  // "upper", "lower", "onepiece"
  Label label = Label::Upper;
  TriMesh mesh;
  Eigen::MatrixX3d colour;   // #V×3 sRGB
  Eigen::VectorXi faceOrigin;  // #F: scan face each face lies in
  bool occluded = false;     // its hidden part was completed (§5.3, Fig. 10)
  double completedArea = 0;  // m² of the hidden part added under the other garment
};

struct Segmentation {
  Eigen::VectorXi vertexLabel;  // #V of the scan, Label codes
  Eigen::VectorXi faceLabel;    // #F of the scan: the label holding most of the face's area
  std::vector<GarmentPiece> garments;
  std::vector<BoundaryReport> boundaries;
  // false from the MRF baseline: labels per vertex, no layout, occlusion or shoe decision (the
  // three fields below keep their defaults).
  bool decided = true;
  GarmentLayout layout = GarmentLayout::UpperLower;
  Occlusion occlusion = Occlusion::None;
  bool shoes = true;  // the foot region's colour differs from skin
  double upperLowerDeltaE = 0, upperSkinDeltaE = 0, lowerSkinDeltaE = 0, footSkinDeltaE = 0;
  // Fraction of the upper / lower region points within sameColourDeltaE of the skin's colour.
  double upperSkinLike = 0, lowerSkinLike = 0;
  double skinDeltaE = 0;  // the person's skin threshold used for upperSkinLike / lowerSkinLike
  // Median offset (m) of the upper / lower region points from the body under the clothes; NaN
  // without that body.
  double upperOffset = 0, lowerOffset = 0;
  double skinOffset = 0;  // ... and of the skin region points (face and hands)
  bool geometricCues = false;  // the step and offset cues were used
  std::vector<HeldObject> heldObjects;  // cut away before B(U|S), labelled Other
  double hairArea = 0;      // m² labelled Hair (cut away with the skin by B(U|S))
  double hairSeedArea = 0;  // m² of the head whose colour is not this person's skin
  int regionPoints = 0, droppedRegionPoints = 0;
  double seconds = 0;
  std::vector<std::string> notes;  // what was detected or skipped, for the report
};

// Segments `scan` (colour: #V×3 sRGB in [0, 1]) with the posed body mesh `body` that carries
// `features` (surface points on body faces; the fully fitted body of §5.1.2 or the true body).
// A spline that loses most of its anchors to Appendix B is replaced by the body's loop carried
// onto the scan, or dropped when the body's loop is far from the scan (a limb the scan lacks); a
// boundary with no spline or sign point left is skipped; each with a note. Throws InputError
// for a scan without colour or a body that does not overlap the scan; TopologyError for a scan
// the isolines cannot be traced on (non-manifold crossed edges); SolverError naming the boundary
// when a system cannot be solved.
Segmentation segmentScan(const TriMesh& scan, const Eigen::MatrixX3d& colour, const TriMesh& body,
                         const FeatureSet& features, const SegmentationOptions& options = {},
                         Progress* progress = nullptr);

// The same with `underBody`, the body fitted under the clothes (the shape-and-pose fit of §4,
// ScanFit::fittedInScanFrame(), not the full fit that follows the clothes; any mesh of the body
// surface will do): the garment boundaries also follow the steps of the scan's offset from it
// where colour cannot tell the sides apart, and a region lying off the body by more than
// options.geometry.garmentOffset is clothed whatever its colour (segment/body_offset.h). A torso
// of this person's skin colour lying nearer the body than that (bare, or a top of the wearer's
// skin tone whose ease the fit took) is decided by B(U|S) run on the geometry alone: a top when
// its boundary runs along steps of the offset (median vote ≥ geometry.hemContrast) with most of
// the chest and back on the garment side; bare otherwise (LowerOnly, the run dropped).
Segmentation segmentScan(const TriMesh& scan, const Eigen::MatrixX3d& colour, const TriMesh& body,
                         const TriMesh& underBody, const FeatureSet& features,
                         const SegmentationOptions& options = {}, Progress* progress = nullptr);

// The paper's Fig. 14 baseline: every scan vertex labelled by a multi-label graph cut
// (segment/mrf.h) with the same colour model as data term and the projected labelled regions as
// prior. Only vertexLabel, faceLabel, the region counts and notes are filled: an MRF labelling
// has no boundary curves and no exact cut. Throws as segmentScan.
Segmentation segmentScanMrf(const TriMesh& scan, const Eigen::MatrixX3d& colour,
                            const TriMesh& body, const FeatureSet& features,
                            const SegmentationOptions& options = {}, const MrfOptions& mrf = {},
                            Progress* progress = nullptr);

// The same with `underBody`, the body fitted under the clothes (as for segmentScan): the
// geometric cues join the colour in the data term (geometricLabelCost, segment/body_offset.h),
// weighed as the curve method weighs them, so that the baseline sees what the boundaries see.
// The layout decisions (a missing garment, one piece, occlusion), hair and held objects stay
// the curve method's: the baseline labels every vertex skin, upper, lower or shoes.
Segmentation segmentScanMrf(const TriMesh& scan, const Eigen::MatrixX3d& colour,
                            const TriMesh& body, const TriMesh& underBody,
                            const FeatureSet& features, const SegmentationOptions& options = {},
                            const MrfOptions& mrf = {}, Progress* progress = nullptr);

}  // namespace s2p
