// Garments of a synthetic scan as implicit solids around the posed body (issue 4): each layer is
// a signed field whose negative side is the solid. Body-following parts are (body SDF − ease)
// clipped by hem cuts defined on the REST-pose body (the closest body point, carried to the rest
// mesh through its face and barycentric coordinates); free-hanging parts (skirts, loose sleeves
// and trouser legs, the hair curtain, the bag) are analytic shapes in the posed frame.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

#include "body/body_model.h"
#include "body/posing.h"
#include "core/tri_mesh.h"
#include "synth/outfit.h"
#include "synth/truth.h"

namespace s2p {

// Body parts by nearest bone of the rest skeleton.
enum class BodyPart : int {
  Torso, Head,
  LeftUpperArm, RightUpperArm, LeftForearm, RightForearm, LeftHand, RightHand,
  LeftThigh, RightThigh, LeftShin, RightShin, LeftFoot, RightFoot,
};
bool isArm(BodyPart p);   // upper arm, forearm or hand
bool isLeg(BodyPart p);   // thigh, shin or foot

// Bones between canonical points of the rest body; a point is located on its nearest bone.
class RestSkeleton {
 public:
  explicit RestSkeleton(const Eigen::MatrixX3d& canonical);  // kNumCanonical×3, rest pose
  struct Location {
    BodyPart part = BodyPart::Torso;
    double t = 0;       // projection parameter along the bone (0 at its proximal end)
    double length = 1;  // bone length, metres
  };
  Location locate(const Eigen::Vector3d& q) const;
  Eigen::Vector3d point(Canonical c) const { return canonical_.row(static_cast<int>(c)); }
  double length(BodyPart p) const;  // length of the part's main bone

 private:
  struct Bone {
    Eigen::Vector3d a, b;
    BodyPart part;
    double radius;  // typical flesh radius around the bone, metres
  };
  Eigen::MatrixX3d canonical_;
  std::vector<Bone> bones_;
};

// What a layer needs to know about the body at a point.
struct BodySample {
  double d = 1e9;                             // signed distance to the posed body (− inside)
  Eigen::Vector3d rest = Eigen::Vector3d::Zero();  // rest-pose body point under p
  bool hasRest = false;                       // false far from the body: body-following
                                              // parts are then outside
};

struct LayerValue {
  double value = 1e9;  // signed field, negative inside the layer's solid
  bool gap = false;    // the point lies on a free-hanging hem's closing cap (paper §5.2)
};

// One garment as an implicit solid. Built by buildGarmentLayers; evaluation is const and
// thread-safe.
struct GarmentLayer {
  int garment = -1;  // index into outfit.garments
  GarmentType type = GarmentType::TShirt;
  Label label = Label::Upper;
  double ease = 0.012;  // metres (spec)
  bool fitted = true;   // has a body-following part

  // === Body-following part: region in rest space, ease varying along the garment.
  double yTop = 0, yBottom = 0;  // rest-pose vertical extent (for the ease gradient)
  double yHem = -1e9;            // rest-pose torso hem: region y > yHem
  double yUpper = 1e9;           // rest-pose upper cut (neckline, waistband): region y < yUpper
  double neckRadius = 0;         // tops: y < yUpper OR farther than this from the neck axis
                                 // (shoulders), and always below neckTop; 0 = flat cut only
  Eigen::Vector3d neck = Eigen::Vector3d::Zero();  // rest neck joint (axis through it along y)
  double armT = -1;              // arm hem: < 0 no arm; [0,1] upper arm t; [1,2] forearm 1+t
  double legT = -1;              // leg hem: < 0 no leg; [0,1] thigh t; [1,2] shin 1+t
  // Where a loose sleeve's or trouser leg's cone takes over (fraction of the upper arm or thigh,
  // < 0: not loose): the body-following part ends a little below, hidden inside the cone. Left
  // to run on to the hem, its end face came out through the cone's cap as a ring of cloth
  // around the wrist, which no loose sleeve has.
  double looseArmFrom = -1, looseLegFrom = -1;
  bool feetOnly = false;         // shoes: foot and the shin below shoeT
  double shoeT = 0.9;            // shoes: upper cut on the shin (t from the knee)
  bool hairScalp = false;        // hair: head above the forehead and behind the ears
  double yForehead = 0, zHead = 0;
  std::array<Eigen::Vector3d, 3> rippleK;  // seeded fold wave vectors (rad/m)
  std::array<double, 3> ripplePhase{};
  std::vector<int> under;        // layers (indices into the layer list) this one lies over

  // === Free-hanging frustum (skirts, dress): elliptic, vertical axis, posed frame.
  bool frustum = false;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // (x, z)
  double fTop = 0, fBottom = 0;    // y of top and hem
  Eigen::Vector2d rTop = Eigen::Vector2d::Ones(), rBottom = Eigen::Vector2d::Ones();  // (x, z)

  // === Loose limb cones (posed frame): from a to b, radius ra → rb, capped.
  struct Cone {
    Eigen::Vector3d a, b;
    double ra = 0, rb = 0;
    bool hemAtB = false;  // the cap at b is a free-hanging hem (Gap)
  };
  std::vector<Cone> cones;

  // === Rounded boxes (posed frame): hair curtain, bag.
  struct Box {
    Eigen::Vector3d centre;
    Eigen::Matrix3d axes;  // columns: unit axes
    Eigen::Vector3d half;  // half extents along the axes (rounding included)
    double rounding = 0.02;
  };
  std::vector<Box> boxes;

  // Ease at a rest point (before stacking over inner layers), metres.
  double easeAt(const Eigen::Vector3d& rest) const;
  // Signed region function at a rest point: > 0 inside the garment's region, ≈ metres to its
  // nearest cut.
  double region(const RestSkeleton& skeleton, const Eigen::Vector3d& rest) const;
  // Same with the point's bone location already known (skeleton.locate(rest)).
  double region(const RestSkeleton& skeleton, const RestSkeleton::Location& loc,
                const Eigen::Vector3d& rest) const;
  // Extent of the analytic parts (posed frame) for the level-set evaluation; empty when none.
  bool analyticBox(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const;
};

// All layers of an outfit, in stacking order (inner to outer; shoes, hair, bag last).
class GarmentLayers {
 public:
  // rest: the shaped body in its rest pose (zero pose, no translation); posed: the same body
  // posed (same faces). Throws InputError on an outfit it cannot build.
  GarmentLayers(const PosedBody& rest, const PosedBody& posed, const Outfit& outfit,
                std::uint64_t seed);

  int size() const { return static_cast<int>(layers_.size()); }
  const GarmentLayer& layer(int i) const { return layers_[i]; }
  const RestSkeleton& skeleton() const { return skeleton_; }
  // Largest body-following offset, metres (the body level set's exterior band must cover it).
  double maxEase() const { return maxEase_; }

  // Values of every layer at p (posed frame) given the body there; out has size().
  void evaluate(const Eigen::Vector3d& p, const BodySample& body, LayerValue* out) const;
  // Union of body and layers at p: min of all fields.
  double unionValue(const Eigen::Vector3d& p, const BodySample& body) const;

  // The layer that shows at p: −1 for the body (skin), else a layer index; ties go to the
  // outer layer (a hem step's riser belongs to the garment). gap is set on a hem's cap.
  int visibleLayer(const Eigen::Vector3d& p, const BodySample& body, bool* gap) const;
  Label labelAt(const Eigen::Vector3d& p, const BodySample& body) const;

 private:
  double stackedEase(int i, const Eigen::Vector3d& rest, const RestSkeleton::Location& loc,
                     std::vector<double>& cache) const;

  RestSkeleton skeleton_;
  std::vector<GarmentLayer> layers_;
  double maxEase_ = 0;
};

}  // namespace s2p
