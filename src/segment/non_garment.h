// What a scan holds besides the person's skin and garments (issue 18; the paper's §8 names hair
// over the neck, case r, and a held bag, case a, among its failures): a held object lies far off
// the body fitted under the clothes, farther than any garment's ease, on one side of the body;
// hair lies on the head and hangs over the neck and shoulders in a colour that is not this
// person's skin. Both are cut away like skin, so that neither becomes a garment: the object
// before B(U|S) (labelled Other), the hair with the skin B(U|S) cuts away (labelled Hair, its
// edge with the top a boundary upper|hair).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <vector>

#include "core/tri_mesh.h"
#include "segment/colour_model.h"

namespace s2p {

// === Held objects

struct HeldObjectOptions {
  // m: a seed of a held object is scan lying this far off the body under the clothes (the
  // offset, segment/body_offset.h): a loose top or trouser leg stands ≲ 4 cm off the body, a
  // bag held at the hip 6–10 cm.
  double seedOffset = 0.05;
  double minSeedArea = 0.002;  // m²: smaller seeds are a fold or the fit's error, not an object
  // Degrees: an object (its seeds grown to the edge level, those that grow into each other
  // joined) reaching further than this around the body's vertical axis is a garment hanging
  // free all around (a skirt, the cap under its hem), not an object at one side.
  double maxSpan = 150;
  // m: the object's edge is where its offset falls to the garments' own level (the median
  // offset of their region points) plus this: a fitted garment's ease varies by a few mm.
  double edgeMargin = 0.008;
  // m: the object grows from its seed over scan above the edge level at most this far (a loose
  // trouser leg beside a bag stays a garment).
  double reach = 0.12;
  // m: the garment within this of the object gives the level its sides stand on.
  double besideBand = 0.03;
  // CIEDE2000: an object whose median colour lies within this of the median colour of the scan
  // beside it is a lump or fold of the garment it stands on (a cuff where the scan's shell folded,
  // a sleeve the fit's arm left far behind), not something held: no visible difference (CIEDE2000's
  // just-noticeable difference is about 1–2). A black bag on a navy shirt under the same light is
  // 5.8 apart; f2's folded cuff 0.4. Only with colours given.
  double sameColourDeltaE = 2.0;
};

// One object found.
struct HeldObject {
  double area = 0;                                     // m², of the scan above the edge level
  double maxOffset = 0;                                // m, off the body under the clothes
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // area-weighted, metres
  double span = 0;                                     // degrees around the body's vertical axis
  double besideLevel = 0;  // m: median offset of the garment beside it (within besideBand)
  double lowered = 0;      // m: its edge moved down its sides from the edge level to that
  // CIEDE2000 between its median colour and the scan's beside it (NaN without colours).
  double besideDeltaE = std::numeric_limits<double>::quiet_NaN();
};

struct HeldObjects {
  // #V, m: > 0 on the objects, < 0 elsewhere, a signed geodesic distance near their edge: the
  // zero isoline is the objects' edge (where the offset leaves the garment's level beside it),
  // the cut that takes them away.
  Eigen::VectorXd field;
  std::vector<HeldObject> objects;
  int rejectedSeeds = 0;  // grown seeds spanning more than maxSpan (free-hanging garments)
  int headSeeds = 0;      // seeds reaching above the ceiling (hair)
  int footSeeds = 0;      // seeds reaching below the floor (shoes)
  // Candidates in the colour of the scan beside them (lumps of a garment), with their ΔE.
  std::vector<double> garmentColoured;
};

// Held objects on `mesh` (the scan, or a part of it): offset #V (m, off the body under the
// clothes, smoothed over the scanner's noise), `axis` a point on the body's vertical axis (the
// span of a seed is measured around it in the horizontal plane), `garmentLevel` the garments'
// median offset (m). A seed reaching above `ceiling` (m, the chin: the lowest of the face's
// region points) is the head's own volume — hair, a hat — not a held object; one reaching below
// `floor` (m, the top of the feet's region points) is the feet's — a shoe's heel where the fit's
// foot is short (tall_slim: heels 5 cm off a foot fitted 5 cm short, taken for a held object).
// With `lab` (#V×3 CIELAB), a candidate in the colour of the scan beside it is a lump of that
// garment and is left (options.sameColourDeltaE). Throws InputError for an offset or colours of
// the wrong size.
HeldObjects findHeldObjects(const TriMesh& mesh, const Eigen::VectorXd& offset,
                            const Eigen::Vector3d& axis, double garmentLevel,
                            const HeldObjectOptions& options = {},
                            double ceiling = std::numeric_limits<double>::infinity(),
                            double floor = -std::numeric_limits<double>::infinity(),
                            const Eigen::MatrixX3d* lab = nullptr);

// === Hair

struct HairOptions {
  // m: hair seeds lie within this of the head's vertical axis (through the face's region
  // points) in the horizontal plane, above the lowest face point: the scalp, not a collar.
  double headRadius = 0.15;
  // m²: fewer seeds than this area are eyebrows or shading: no hair model.
  double minSeedArea = 0.004;
  // m: hair is labelled within this of the head's centre (the hair over the shoulders, not the
  // hands).
  double reach = 0.45;
  double smoothing = 0.005;  // m: smoothing of the hair/skin indicator before it is cut
};

// Vertices of `mesh` on the head (above the lowest of `facePoints`, within headRadius of their
// vertical axis) whose colour (lab: #V×3 CIELAB) lies outside this person's skin (`skin`,
// fitted on the face and hands). Empty when they cover less than minSeedArea.
std::vector<int> hairSeeds(const TriMesh& mesh, const Eigen::MatrixX3d& lab,
                           const std::vector<Eigen::Vector3d>& facePoints, const SkinModel& skin,
                           const HairOptions& options = {});

// Hair against skin on the skin side of B(U|S) (`mesh`, lab #V×3): a vertex within `reach` of
// `headCentre` whose colour is nearer a component of `hair` than of `skin` (CIEDE2000) is hair;
// the ±1 indicator smoothed over options.smoothing. #V, > 0 on hair, its zero isoline the
// hair's edge.
Eigen::VectorXd hairField(const TriMesh& mesh, const Eigen::MatrixX3d& lab,
                          const GaussianMixture& hair, const GaussianMixture& skin,
                          const Eigen::Vector3d& headCentre, const HairOptions& options = {});

}  // namespace s2p
