// Placement of the flat panels around the body in a pose that suits draping (paper §6.3), and
// the stitches between them.
//
// §6.3: every garment part is bound rigidly to a joint of the fitted body (trunk panels to the
// chest, sleeves to their shoulders, lower panels to the hips: a trouser leg's panels to its
// own hip, a skirt's to the pelvis) and unposed with it. The paper unposes to SMPL's zero pose;
// ours is the drape pose (posing.h: A-pose arms, legs turned out 8°), because a zero pose of
// some body models has the arms against the torso. Beyond §6.3, the part is unposed down its
// limb (each point with the bone it lies nearest: a sleeve's upper arm with the shoulder, its
// forearm with the elbow), so that a sleeve scanned with its elbow bent is laid along the
// straight rest arm; the panel itself stays rigid. The remeshed flat panel, whose every vertex
// has its point on the 3D panel (flat_pattern.h), is then laid in the plane facing the part's
// outward normal and turned in that plane to match the part (2D Procrustes); for the trunk's
// front and back panels that is the paper's "rotate about the frontal axis". Last it is moved
// out along its normal until every vertex clears the body by `clearance`, so that no panel
// intersects the body.
//
// The rest frame is GarmentCode's: metres here (cm in pattern.json), +Y up, facing +Z, the
// feet on y = 0, the pelvis above the origin.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "body/body_model.h"
#include "core/tri_mesh.h"
#include "pattern/flat_pattern.h"
#include "pattern/panels.h"

namespace s2p {

struct PlacementInput {
  const BodyModel* model = nullptr;
  BodyParams fitted;  // the fitted shape and pose (fitting frame)
  // Fitting frame → the frame the garments and panels are in (ScanFit::toScan).
  Eigen::Affine3d toGarments = Eigen::Affine3d::Identity();
  // The non-rigid full fit in the fitting frame (the model's faces): its detail is carried to
  // the rest body by unposing. Empty: the shaped model alone.
  TriMesh full;
};

struct PlacementOptions {
  double clearance = 0.02;  // m: least distance of every placed vertex from the rest body
  double step = 0.005;      // m: the least outward move per search step
  double maxOffset = 0.6;   // m: a panel that does not clear the body by then is reported
};

struct PlacedPanel {
  bool placed = false;  // false: the panel was not flattened (see FlatPanel::error)
  Canonical joint = Canonical::Chest;  // the joint it is bound to
  // 3D = R·(x, y, 0) + t in the rest frame (m); R's third column is the panel's outward normal.
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  Eigen::MatrixX3d V;     // #V of the remeshed panel × 3: its vertices placed
  Eigen::MatrixX3d part;  // the same vertices' points on the 3D panel, unposed with the joint
  double offset = 0;          // m: moved out along the normal from the part's centroid
  double distanceToPart = 0;  // m: mean distance from V to part
  double clearance = 0;       // m: least distance of V to the rest body (all outside)
};

struct Placement {
  std::string pose;      // the drape pose, described (placePanels)
  BodyPose drapePose;    // the fitted shape's pose the pattern is placed around (drapePoseFor)
  TriMesh restBody;      // the body in the drape pose, rest frame
  // The body fitted under the clothes (fitted shape, drape pose, none of the full fit's detail)
  // in the same frame: what the pattern is sewn and draped on. restBody follows the scanned
  // clothes (the full fit is fitted onto the scan surface), so a pattern as large as the scanned
  // garment has no room on it: sewn there, a t-shirt's armpit junction stays open.
  TriMesh underBody;
  Eigen::MatrixX3d canonical;  // kNumCanonical×3, the rest body's canonical points
  std::vector<PlacedPanel> panels;  // one per FlatPatternResult panel, same order
  std::vector<std::string> warnings;
  double seconds = 0;
};

// Each point of P (#P×3) moved by the transform of the bone it lies nearest: bone k runs from
// joints[k] to joints[k+1] (the last is the point joints.back()) and moves with transforms[k].
// Placement unposes a panel's part so, down its limb (shoulder, elbow, wrist; hip, knee, ankle).
// Throws InputError when the counts differ or no joint is given.
Eigen::MatrixX3d moveWithNearestBone(const std::vector<Eigen::Vector3d>& joints,
                                     const std::vector<Eigen::Affine3d>& transforms,
                                     const Eigen::MatrixX3d& P);

// Throws InputError for a missing model or parameters that do not fit it.
Placement placePanels(const PanelsResult& panels, const FlatPatternResult& flat,
                      const PlacementInput& input, const PlacementOptions& options = {});

// === Stitches

// One stitch per pair of partner seam edges: vertex k of edge A (remeshed ids, corner to
// corner) is sewn to vertex n−1−k of edge B, since two panels of one surface run along their
// shared seam in opposite directions; that is what makes the right sides meet (GarmentCode's
// default stitch orientation).
struct Stitch {
  int panelA = -1, edgeA = -1, panelB = -1, edgeB = -1;  // indices into PanelsResult
  std::string name;                                    // "left_side", from edge A
  double lengthA = 0, lengthB = 0;                     // m, the Bézier chains' 2D lengths
  std::vector<std::pair<int, int>> vertices;  // (vertex of panel A, vertex of panel B), remeshed ids
  double scanGap = 0;  // m: mean 3D distance of the paired vertices on the scanned garment
  double restGap = 0;  // m: the same at the placement (what the sewing has to close)
  double mismatch() const { return std::abs(lengthA - lengthB); }
};

struct StitchSet {
  std::vector<Stitch> stitches;
  std::vector<std::string> warnings;  // pairs left out (a panel not flattened), odd orientations
};

// placement may be null (restGap stays 0). Every edge is in at most one stitch.
StitchSet makeStitches(const PanelsResult& panels, const FlatPatternResult& flat,
                       const Placement* placement);

}  // namespace s2p
