// Seam line estimation on one cut garment (paper §6.1): the body's predefined seam splines and
// paired sign points (body/features.h: upper_side, shoulder, lower_side, crotch) projected onto
// the garment from the fully fitted body as §5.1.2 projects the boundary features, with
// Appendix B's ill-projection tests, paired removal (§6.1.2: when one sign point of a pair goes,
// its partner goes too) and removal of a spline — and of a seam whose splines all go — when
// fewer than 3 of its anchors survive. Each surviving seam becomes an implicit function (the
// biharmonic of Eq. 1 with zero on the spline and the sign values, turned into a signed
// distance), is length-regularised (Eq. 4) and its zero isoline is the seam line.
//
// The removal is what tells a skirt (no crotch seam: its anchors between the legs see the legs,
// rule 2) from trousers, and a sleeveless top (no armhole seam) from a sleeved one.
#pragma once

#include <Eigen/Core>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "body/features.h"
#include "core/tri_mesh.h"
#include "pattern/body_frame.h"
#include "segment/boundary_optimizer.h"
#include "segment/isoline.h"
#include "segment/projection.h"

namespace s2p {

// The three seam functions a garment can carry; their signs name the panels.
enum class SeamKind {
  FrontBack,  // > 0 on the front: upper_side (tops), lower_side (bottoms), both (one-piece)
  Armhole,    // > 0 on the trunk, < 0 on the sleeves: shoulder
  LeftRight   // > 0 on the body's left: crotch (hip-to-belly)
};
const char* toString(SeamKind kind);

enum class GarmentKind { Upper, Lower, OnePiece };
const char* toString(GarmentKind kind);

struct SeamOptions {
  ProjectionOptions projection;  // bodyLength is set from the body's height
  // β of Eq. (4) as in the segmentation (m², √β = 5 mm); α is unused: seams have no
  // displacement (§6.1: no region points, no boundary optimisation).
  BoundaryOptions boundary;
  int regularisationSteps = 3;  // backward Euler steps of Eq. (4) on the seam's signed distance
  int minAnchors = 3;           // §6.1.2: a spline with fewer surviving anchors is removed
  // Contact anchors (a top's side and armhole seams: upper_side, shoulder): an anchor Appendix B
  // drops only because its ray meets the body again within this fraction of the body's height
  // (≈ 2 cm: an arm hanging against the trunk) is kept; the cloth is pressed between the two,
  // not hidden behind one. Only on a spline that would otherwise keep fewer than minAnchors.
  // 0: the paper's tests alone.
  double contactDistance = 0.012;
  // ... and only when the scan shows cloth within this fraction of the height of the anchor:
  // where the scan fused sleeve and side, the nearest cloth is the crease in front of or behind
  // the contact, 2–5 cm off, on either side by chance (walking: the side seam crossed the
  // armhole twice, a seam edge lost its partner). Such an anchor stays dropped.
  double contactClothDistance = 0.012;
  // An open spline with an ill-projected anchor between surviving ones farther than this
  // (fraction of the body's height, ≈ 7 cm) from the garment is removed: the garment does not
  // follow the body there (a skirt over the crotch; loose wear is ~2–5 cm away).
  double brokenSeamDistance = 0.04;
  double splineSpacing = 0.005;  // m between zero constraints along a spline
  // The armhole seam's extra constraints (§6.1.2): boundary points about this far apart (m).
  double boundaryConstraintSpacing = 0.02;
  // Beyond §6.1.2: the armhole function also holds the garment where the fitted body says which
  // part it covers. A garment vertex's body part is that of its closest body vertex whose normal
  // agrees with the garment's (n·n ≥ partNormalDot: a sleeve pressed against the torso sees the
  // torso's side under it only from outside, the arm's inner side faces the other way), within
  // partMaxDistance × the body's height. It is trunk (+1) when that vertex's arm skinning weight
  // is ≤ trunkArmWeight, sleeve (−1) when the weight of a sleeved arm is ≥ sleeveArmWeight;
  // between them (the arm root, where skinning blends) the anchors decide. Points about
  // partSpacing apart, none closer than partAnchorClearance to a surviving anchor.
  // Sleeve points are off by default (> 1): at 0.95 they pulled baked_light's left armhole
  // 36 mm down the torso's front under the arm (the mannequin's arm weights fall below 0.05 only
  // well down the torso's side, so no trunk point held the line there); the cuff holds the
  // sleeve side as the paper does.
  double partNormalDot = 0.5;
  double partMaxDistance = 0.05;  // fraction of the body's height (≈ 8.5 cm); 0: none
  double trunkArmWeight = 0.05;
  double sleeveArmWeight = 2.0;       // > 1: no sleeve points
  double partSpacing = 0.03;          // m
  double partAnchorClearance = 0.04;  // m
  // m²: regions of the seam's sign holding no sign point flip to their surroundings' side when
  // smaller than this. Any size by default: every true panel region holds sign points (pairs on
  // the torso and every limb), and a region without one is the biharmonic's extrapolation (a
  // band below dropped ankle pairs turned a shin's front into 'back').
  double minIslandArea = std::numeric_limits<double>::infinity();
  // Issue 17: a garment of more than 1.5 × this many vertices has its seams found on a
  // decimated copy of about this many (core/coarse_mesh.h) and carried back (the signed
  // distance interpolated at each vertex's closest point on the copy); 0: at full resolution.
  int coarseVertices = 100000;
  // Folds (armholeFolds): an armhole stretch lies on a fold where the cloth within creaseRadius
  // (m) on its two sides turns inwards, towards each other, by at least creaseAngle degrees.
  // Cloth over a smooth body turns ~10–25° across 3 cm (the armpit, the shoulder); a sleeve the
  // scan fused to the trunk's side meets it at ~90°.
  double creaseRadius = 0.015;
  double creaseAngle = 60;
  // A fold reaching this far down (m) is reported (panels' notes): beyond a rounded armpit.
  double creaseReportDrop = 0.03;
};

// A garment opening: one boundary loop of the cut garment, named by where it lies on the body.
struct Opening {
  std::string name;  // "neckline", "hem", "left_cuff", "left_armhole", "waistband",
                     // "left_leg_opening"
  Limb limb = Limb::Torso;
  double t = 0;               // place along the limb (0 root, 1 end): how long a sleeve or leg is
  std::vector<int> vertices;  // the garment's boundary loop (vertex ids)
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double length = 0;  // m
  // A loop on an arm: the signed number of times the arm's bones (clavicle to hand tip) pass
  // through the fan over the loop from its centroid. The arm leaves the garment through its
  // armhole or cuff (±1, in any pose); a hole the scan left in the armpit lies beside it (0).
  int armCrossings = 0;
  // A cuff the scan joined to this opening (a hand hanging against the hem): a stretch of the
  // loop past the armhole on one arm that winds at least half way round the arm's axis. The
  // sleeve logic takes it as that arm's cuff.
  struct JoinedCuff {
    Limb limb = Limb::LeftArm;
    double t = 0;               // place along the arm (mean over the stretch)
    std::vector<int> vertices;  // the stretch, in loop order
  };
  std::vector<JoinedCuff> joinedCuffs;  // only on openings not named for an arm
};

// Whether `o` is, or holds, a cuff of `arm` (an opening past the armhole on that arm).
bool hasCuff(const Opening& o, Limb arm);

// Names every boundary loop of `garment` (topology's loops, in order).
std::vector<Opening> classifyOpenings(const TriMesh& garment, const MeshTopology& topology,
                                      GarmentKind kind, const BodyFrame& frame);

struct SeamLine {
  SeamKind kind = SeamKind::FrontBack;
  std::string name;                   // "side", "armhole", "crotch"
  std::vector<std::string> features;  // the body's seam features it comes from
  bool kept = false;
  std::string removedWhy;               // when not kept
  int anchors = 0, droppedAnchors = 0;  // projected / ill-projected spline anchors
  int signs = 0, droppedSigns = 0;      // of which dropped by the tests or with their pair
  int pairedDrops = 0;                  // sign points dropped only because their partner was
  int contactAnchors = 0;  // anchors Appendix B drops that were kept as contacts (of anchors)
  int trunkPoints = 0, sleevePoints = 0;  // the armhole's body-part constraints (+1 / −1)
  int unmatchedPoints = 0;  // garment samples with no body vertex of an agreeing normal near
  std::vector<std::string> splinesKept, splinesRemoved;
  // Where the zero constraints lie on the garment (spline samples, or the anchors for the
  // armhole), #P×3: the seam's prior position.
  Eigen::MatrixX3d prior;
  Eigen::VectorXd phi;  // #V of the garment, signed distance (m); empty when not kept
  Isoline line;         // zero isoline of phi
  int islandsRemoved = 0;
  double seconds = 0;
};

// A point known to lie on one side of the armhole seam, as a position on the garment: cloth
// supplied where a contact hid it (pattern/contact_opening.h), the sleeve's underside −1 and the
// side under the arm +1. It holds the armhole function there as a sign point does.
struct ArmholeHint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double value = 0;
};

// The seams of one garment (mesh in the body's frame, consistently oriented), in the order they
// are applied: FrontBack, Armhole, LeftRight (those that do not apply to the kind are absent).
// body: the posed fully fitted body carrying `features`; bodyLimbWeight: #V of body × 6, its
// vertices' skinning weights per Limb (limbWeights), or empty: no body-part constraints on the
// armhole function; armholeHints: more of its sign points (ArmholeHint). Throws InputError for
// an empty garment, a body that does not overlap it, or a bodyLimbWeight of the wrong shape.
std::vector<SeamLine> estimateSeams(const TriMesh& garment, GarmentKind kind, const TriMesh& body,
                                    const FeatureSet& features,
                                    const std::vector<Opening>& openings,
                                    const SeamOptions& options = {},
                                    const Eigen::MatrixXd& bodyLimbWeight = Eigen::MatrixXd(),
                                    const std::vector<ArmholeHint>& armholeHints = {});

// estimateSeams one seam at a time: each seam is estimated when first asked for, on state built
// once (the projector, the garment's topology, the seam optimiser, the decimated copy). The
// panels stage asks for the armhole first and needs the other seams only when it keeps the
// garment as it is (pattern/contact_opening.h). The inputs are held by reference and must
// outlive the estimator. Throws as estimateSeams.
class SeamEstimator {
 public:
  SeamEstimator(const TriMesh& garment, GarmentKind kind, const TriMesh& body,
                const FeatureSet& features, const std::vector<Opening>& openings,
                const SeamOptions& options = {},
                const Eigen::MatrixXd& bodyLimbWeight = Eigen::MatrixXd(),
                const std::vector<ArmholeHint>& armholeHints = {});
  ~SeamEstimator();
  SeamEstimator(const SeamEstimator&) = delete;
  SeamEstimator& operator=(const SeamEstimator&) = delete;

  // The seam of `kind`, or nullptr when the garment's kind has none (a skirt's crotch seam is
  // there, maybe removed; a top has no crotch seam at all). Valid while the estimator lives.
  const SeamLine* seam(SeamKind kind);
  // Every seam of the garment's kind, in estimateSeams' order.
  std::vector<SeamLine> all();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One stretch of an armhole seam's isoline that runs along a fold (SeamOptions::creaseRadius).
struct SeamFold {
  Eigen::Vector3d a, b;  // the segment's end points (m)
};

// The segments of `seam`'s isoline that lie on a concave fold of `garment`: where an arm hangs
// against the trunk the scan joins the sleeve's cloth to the side's along a crease, the sleeve's
// underside and the side under the arm are hidden in the contact, and every curve that parts
// sleeve from trunk must follow the crease from the armpit down to where the contact ends (the
// cuff, when it reaches it). Empty for a seam not kept.
std::vector<SeamFold> armholeFolds(const TriMesh& garment, const SeamLine& seam,
                                   const SeamOptions& options = {});

}  // namespace s2p
