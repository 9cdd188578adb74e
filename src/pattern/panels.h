// Patterns I (paper §6.1): each cut garment cut exactly along its seam lines into panels, every
// panel a topological disk, its boundary split at corners (where a seam meets an opening or
// another seam: the points P of §6.2) into edges, each edge an opening or a seam with its
// partner edge on another panel; and the garment's type read from its panels and openings.
//
// Method. The seams' zero isolines are inserted into the garment one after another (exact cuts
// kept in one mesh, segment/mesh_cut.h), so every face knows its side of every seam. The sides
// name the panels: a sleeve is the arm side of the armhole seam, the trunk is split front/back
// by the side seam and left/right by the crotch seam. A sleeve is one panel: its front and
// back halves stay joined along the top of the arm and it opens along the underarm (the chain of
// the side seam's isoline nearest the projected underarm spline). A piece that is still not a
// disk is cut along the cheapest path between its boundary loops, where a path costs more where
// the scan's cameras see the surface (the least visible side), and the result says so.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "body/features.h"
#include "core/tri_mesh.h"
#include "pattern/contact_opening.h"
#include "pattern/inside_trim.h"
#include "pattern/seam_lines.h"

namespace s2p {

// One stretch of a panel's boundary between two corners.
struct PanelEdge {
  std::string name;           // "neckline", "hem", "left_cuff", "left_side", "left_armhole",
                              // "left_underarm", "center_front", "cut", ...
  bool opening = true;        // a garment opening; else a seam
  int partnerPanel = -1;      // seam: the panel on the other side (may be this panel)
  int partnerEdge = -1;       // seam: that panel's edge index
  std::vector<int> vertices;  // panel vertex ids from this corner to the next (both included)
  double length = 0;          // m, in 3D
};

struct Panel {
  std::string name;     // "front", "back", "left_sleeve", "left_front", ...
  std::string garment;  // the garment's name ("upper", "lower", "onepiece")
  int garmentIndex = -1;
  TriMesh mesh;                  // 3D, the garment's frame; a topological disk
  Eigen::VectorXi faceOrigin;    // #F: the scan face each face lies in
  std::vector<int> loop;         // the boundary loop (vertex ids), surface on its left
  std::vector<PanelEdge> edges;  // in loop order; edges[i].vertices.front() is corner i
  double area = 0;               // m²
  bool cutOpen = false;          // needed the fallback cut to become a disk
};

struct GarmentPanels {
  std::string name;
  GarmentKind kind = GarmentKind::Upper;
  // tshirt, long_sleeve_shirt, sleeveless_top, trousers, shorts, skirt, dress, jumpsuit
  std::string type;
  std::vector<SeamLine> seams;
  std::vector<Opening> openings;
  std::vector<int> panels;  // indices into PanelsResult::panels
  std::vector<std::string> notes;
};

struct PanelsInput {
  struct Garment {
    std::string name;  // "upper", "lower", "onepiece"
    GarmentKind kind = GarmentKind::Upper;
    TriMesh mesh;                // the cut garment (segmentation), body frame
    Eigen::VectorXi faceOrigin;  // #F: scan face of each face
  };
  std::vector<Garment> garments;
  TriMesh body;  // the posed fully fitted body, carrying `features`
  FeatureSet features;
  Eigen::MatrixX3d canonical;  // kNumCanonical×3, the posed body's canonical points
  // #V of body × 6: each body vertex's skinning weight per Limb (limbWeights); empty when the
  // body came without its model (the armhole seam then has no body-part constraints).
  Eigen::MatrixXd bodyLimbWeight;
};

struct PanelOptions {
  SeamOptions seams;
  // A connected piece of one panel label smaller than this fraction of its garment's area is
  // merged into the neighbour it shares the longest border with (a sliver between two seams).
  double minPanelFraction = 0.02;
  // Fallback cut: a path's cost per metre is 1 + visibilityWeight · (fraction of 8 horizontal
  // camera directions that see the surface there).
  double visibilityWeight = 4.0;
  // A boundary loop shorter than this fraction of the body's head-top-to-ankle height (0.06:
  // about 9 cm, half a wrist's girth) lets nothing through: it is a hole of the scan (a scrap of
  // leg left on a skirt's hem, a gap between fused fingers), filled, never an opening.
  double minOpeningFraction = 0.06;
  // Where the scan fused a sleeve to the trunk below the armpit (an arm hanging against the
  // side), open the contact and supply the cloth it hid before the seams are found
  // (pattern/contact_opening.h); false: the seams follow the crease, as the scan shows it.
  bool openFusedContacts = true;
  ContactOpeningOptions contacts;
  // Where the scan saw the garment's inside through an opening (under a skirt's hem), drop it
  // before the seams are found (pattern/inside_trim.h); false: flatten it with the rest.
  bool trimInside = true;
  InsideTrimOptions inside;
};

struct PanelsResult {
  std::vector<Panel> panels;
  std::vector<GarmentPanels> garments;
  std::vector<std::string> warnings;
  double seconds = 0;
};

// A garment without faces (InputError), with a non-manifold mesh, with no surviving seam while
// not a disk, or with a panel that even the fallback cut cannot make a disk (TopologyError) makes
// no pattern: its error, naming it, becomes a warning and the other garments go on. Throws that
// error when no garment makes a pattern, and InputError for a body whose canonical points are
// missing.
PanelsResult runPanels(const PanelsInput& input, const PanelOptions& options = {});

// Leaves out the garment's connected pieces that are closed (no boundary: a bubble, no cloth)
// or below `minFraction` of its area. Returns how many. runPanels does this first.
int dropStrayPieces(PanelsInput::Garment& garment, double minFraction);

// Fills the garment's boundary loops that are not openings with a fan around the loop's
// centroid; the new faces take the scan face of the face they border. An opening is the longest
// loop of its name among those a hand can pass (at least minOpeningFraction × the body's
// head-top-to-ankle height) and, for a name on an arm, that the arm passes through
// (Opening::armCrossings); every other loop is a hole of the scan. Returns the number of holes
// filled; `besideArm`, if given, receives how many of them were long enough for an opening but
// named for an arm that does not pass through them. runPanels does this first.
int fillScanHoles(PanelsInput::Garment& garment, const BodyFrame& frame,
                  double minOpeningFraction = 0.06, int* besideArm = nullptr);

// The second half of runPanels for garment `garment` of `input`, with its seam lines given (their
// phi on the garment's vertices) instead of estimated from the body's features; appends to
// `result`. For tests and for seams drawn by other means. Throws as runPanels.
void panelizeGarment(const PanelsInput& input, int garment, std::vector<SeamLine> seams,
                     const PanelOptions& options, PanelsResult& result);

}  // namespace s2p
