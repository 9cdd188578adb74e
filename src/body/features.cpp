#include "body/features.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>

#include "body/plane_section.h"
#include "body/posing.h"
#include "core/error.h"
#include "core/mesh_query.h"

namespace s2p {
namespace {

using Vec3 = Eigen::Vector3d;
using C = Canonical;

// Body frame after normalisation (body_model.h): +Y up, facing +Z, the body's left on +X.
const Vec3 kUp = Vec3::UnitY();
const Vec3 kFront = Vec3::UnitZ();
const Vec3 kLeft = Vec3::UnitX();

// The component of d orthogonal to axis, normalised (zero when d is parallel to axis).
Vec3 orthogonalTo(const Vec3& d, const Vec3& axis) {
  const Vec3 a = axis.normalized();
  const Vec3 r = d - d.dot(a) * a;
  const double n = r.norm();
  return n > 1e-9 ? Vec3(r / n) : Vec3::Zero();
}

// The shaped rest body with the tools the rules need: sections, closest points, canonical
// points.
class Rules {
 public:
  Rules(const TriMesh& mesh, const Eigen::MatrixX3d& canonical)
      : mesh_(mesh), slicer_(mesh), query_(mesh), canonical_(canonical) {}

  Vec3 at(C c) const { return canonical_.row(static_cast<int>(c)).transpose(); }
  Vec3 along(C a, C b, double t) const { return at(a) + t * (at(b) - at(a)); }

  // The closed section loop around point p with plane normal n: among the loops that enclose
  // p, the one with the smallest enclosed area (the limb's own section, not the torso's).
  SectionLoop loopAround(const Vec3& p, const Vec3& n, const std::string& what) const {
    std::optional<SectionLoop> best;
    double bestArea = std::numeric_limits<double>::infinity();
    for (auto& loop : slicer_.section(p, n)) {
      if (!loop.closed || !loopEncloses(loop, p, n)) continue;
      const double area = enclosedArea(loop, n);
      if (area < bestArea) {
        bestArea = area;
        best = std::move(loop);
      }
    }
    if (!best)
      throw InputError(fmt::format(
          "feature rules: no closed body section around the {} (plane through ({:.3f}, {:.3f}, "
          "{:.3f})); the body model is missing that part or it touches another part",
          what, p.x(), p.y(), p.z()));
    return *best;
  }
  SectionLoop boneLoop(C a, C b, double t, const std::string& what) const {
    return loopAround(along(a, b, t), at(b) - at(a), what);
  }
  // Horizontal-ish torso section at fraction t of pelvis → neck, normal along the spine.
  SectionLoop torsoLoop(double t, const std::string& what) const {
    return loopAround(along(C::Pelvis, C::Neck, t), at(C::Neck) - at(C::Pelvis), what);
  }

  SurfacePoint surface(const Vec3& p) const {
    const ClosestHit hit = query_.closestPoint(p);
    return {hit.face, hit.bary};
  }

  const TriMesh& mesh() const { return mesh_; }
  const MeshSlicer& slicer() const { return slicer_; }

 private:
  const TriMesh& mesh_;
  MeshSlicer slicer_;
  MeshQuery query_;
  const Eigen::MatrixX3d& canonical_;
};

Vec3 loopCentroid(const SectionLoop& loop) {
  return loop.points.colwise().mean().transpose();
}

// The loop point farthest along direction d.
Vec3 extremePoint(const SectionLoop& loop, const Vec3& d) {
  Eigen::Index best;
  (loop.points * d).maxCoeff(&best);
  return loop.points.row(best).transpose();
}

// k points equally spaced by arc length along a closed loop, starting at the point farthest
// along startDir and turning counter-clockwise about `normal`.
Eigen::MatrixX3d resampleLoop(const SectionLoop& loop, int k, const Vec3& startDir,
                              const Vec3& normal) {
  const int n = static_cast<int>(loop.points.rows());
  Eigen::MatrixX3d P = loop.points;
  // Orient counter-clockwise about the normal.
  Vec3 areaVec = Vec3::Zero();
  const Vec3 c = loopCentroid(loop);
  for (int i = 0; i < n; ++i)
    areaVec += (P.row(i).transpose() - c).cross(P.row((i + 1) % n).transpose() - c);
  if (areaVec.dot(normal) < 0) P = P.colwise().reverse().eval();
  Eigen::Index start;
  (P * startDir).maxCoeff(&start);
  std::vector<double> cum(n + 1, 0.0);
  for (int i = 0; i < n; ++i)
    cum[i + 1] = cum[i] + (P.row((start + i + 1) % n) - P.row((start + i) % n)).norm();
  Eigen::MatrixX3d out(k, 3);
  int seg = 0;
  for (int j = 0; j < k; ++j) {
    const double s = cum[n] * j / k;
    while (seg < n - 1 && cum[seg + 1] < s) ++seg;
    const double len = cum[seg + 1] - cum[seg];
    const double u = len > 0 ? (s - cum[seg]) / len : 0.0;
    out.row(j) = (1 - u) * P.row((start + seg) % n) + u * P.row((start + seg + 1) % n);
  }
  return out;
}

FeatureSpline closedSpline(const Rules& r, const std::string& name, const SectionLoop& loop,
                           const Vec3& normal, int anchors) {
  FeatureSpline s{name, {}, true};
  const Eigen::MatrixX3d P = resampleLoop(loop, anchors, kFront, normal);
  for (int i = 0; i < P.rows(); ++i) s.anchors.push_back(r.surface(P.row(i).transpose()));
  return s;
}

FeatureSpline openSpline(const Rules& r, const std::string& name, const std::vector<Vec3>& points) {
  FeatureSpline s{name, {}, false};
  for (const Vec3& p : points) s.anchors.push_back(r.surface(p));
  return s;
}

void addSign(const Rules& r, CurveFeatures& f, const std::string& name, const Vec3& p,
             double value) {
  f.signs.push_back({name, r.surface(p), value, -1});
}

// A front (+1) / back (−1) pair of sign points on a section loop.
void addFrontBackPair(const Rules& r, CurveFeatures& f, const std::string& name,
                      const SectionLoop& loop, const Vec3& front) {
  const int i = static_cast<int>(f.signs.size());
  f.signs.push_back({name + "_front", r.surface(extremePoint(loop, front)), +1.0, i + 1});
  f.signs.push_back({name + "_back", r.surface(extremePoint(loop, -front)), -1.0, i});
}

struct Side {
  const char* name;
  double sign;  // +1 left (+X), −1 right
  C clavicle, shoulder, elbow, wrist, handTip, hip, knee, ankle, toeTip, heel;
};
const Side kSides[2] = {
    {"left", +1, C::LeftClavicle, C::LeftShoulder, C::LeftElbow, C::LeftWrist, C::LeftHandTip,
     C::LeftHip, C::LeftKnee, C::LeftAnkle, C::LeftToeTip, C::LeftHeel},
    {"right", -1, C::RightClavicle, C::RightShoulder, C::RightElbow, C::RightWrist, C::RightHandTip,
     C::RightHip, C::RightKnee, C::RightAnkle, C::RightToeTip, C::RightHeel}};

// A place on a bone: fraction t of the way from joint a to joint b.
struct BonePlace {
  C a, b;
  double t;
};

// Front (+) / back (−) sign pairs on the limb sections at the given places (§6.1.1).
void addLimbPairs(const Rules& r, CurveFeatures& f, const Side& s, const char* limb,
                  std::initializer_list<BonePlace> places) {
  for (const BonePlace& p : places) {
    const Vec3 bone = r.at(p.b) - r.at(p.a);
    addFrontBackPair(r, f, fmt::format("{}_{}_{}_{:.2f}", s.name, limb, toString(p.a), p.t),
                     r.boneLoop(p.a, p.b, p.t, fmt::format("{} {}", s.name, limb)),
                     orthogonalTo(kFront, bone));
  }
}

// Rule parameters (fractions along bones), named once here.
constexpr double kNeckLoopT = 0.3;    // neck → head: lower neck, where a collar sits
constexpr double kAnkleLoopT = 0.12;  // ankle → knee: just above the ankle bone
constexpr double kWaistT = 0.22;      // pelvis → neck: navel height
constexpr double kChestT = 0.62;      // pelvis → neck: chest (front/back sign points)
constexpr double kHipT = 0.04;        // pelvis → neck: hip section above the crotch
constexpr double kArmholeT = 0.12;    // shoulder → elbow: armhole just outside the joint
constexpr double kUnderArmT = 0.55;   // pelvis → neck: the torso's side a hand below the armpit

void boundaryFeatures(const Rules& r, const FeatureOptions& opt, FeatureSet& fs) {
  // B(U|S): loops around the neck and both wrists; + nose, hand tips; − chest front/back.
  CurveFeatures& us = fs.upperSkin;
  us.name = "U|S";
  const Vec3 neckAxis = r.at(C::Head) - r.at(C::Neck);
  us.splines.push_back(closedSpline(r, "neck", r.boneLoop(C::Neck, C::Head, kNeckLoopT, "neck"),
                                    neckAxis, opt.loopAnchors));
  for (const Side& s : kSides) {
    const Vec3 axis = r.at(s.wrist) - r.at(s.elbow);
    us.splines.push_back(closedSpline(
        r, fmt::format("{}_wrist", s.name),
        r.loopAround(r.at(s.wrist), axis, fmt::format("{} wrist", s.name)), axis, opt.loopAnchors));
  }
  const SectionLoop chest = r.torsoLoop(kChestT, "chest");
  addSign(r, us, "nose", r.at(C::Nose), +1);
  for (const Side& s : kSides)
    addSign(r, us, fmt::format("{}_hand_tip", s.name), r.at(s.handTip), +1);
  addSign(r, us, "chest_front", extremePoint(chest, kFront), -1);
  addSign(r, us, "chest_back", extremePoint(chest, -kFront), -1);

  // B(L|S): loops around both ankles; + toe tips and soles.
  CurveFeatures& ls = fs.lowerSkin;
  ls.name = "L|S";
  for (const Side& s : kSides) {
    const Vec3 axis = r.at(s.knee) - r.at(s.ankle);
    ls.splines.push_back(
        closedSpline(r, fmt::format("{}_ankle", s.name),
                     r.boneLoop(s.ankle, s.knee, kAnkleLoopT, fmt::format("{} ankle", s.name)),
                     axis, opt.loopAnchors));
  }
  for (const Side& s : kSides) {
    addSign(r, ls, fmt::format("{}_toe_tip", s.name), r.at(s.toeTip), +1);
    const SectionLoop midFoot = r.boneLoop(s.heel, s.toeTip, 0.5, fmt::format("{} foot", s.name));
    addSign(r, ls, fmt::format("{}_sole", s.name), extremePoint(midFoot, -kUp), +1);
  }

  // B(U|L): loop around the waist at the navel; + chest front and back.
  CurveFeatures& ul = fs.upperLower;
  ul.name = "U|L";
  const Vec3 spine = r.at(C::Neck) - r.at(C::Pelvis);
  ul.splines.push_back(
      closedSpline(r, "waist", r.torsoLoop(kWaistT, "waist"), spine, opt.loopAnchors));
  addSign(r, ul, "chest_front", extremePoint(chest, kFront), +1);
  addSign(r, ul, "chest_back", extremePoint(chest, -kFront), +1);
}

void regionFeatures(const Rules& r, const FeatureOptions& opt, FeatureSet& fs) {
  auto addLoop = [&](const SectionLoop& loop, const Vec3& normal, RegionLabel label,
                     const std::optional<Vec3>& halfSpace = std::nullopt) {
    const Eigen::MatrixX3d P = resampleLoop(loop, opt.regionLoopPoints, kFront, normal);
    const Vec3 c = loopCentroid(loop);
    for (int i = 0; i < P.rows(); ++i) {
      const Vec3 p = P.row(i).transpose();
      if (halfSpace && (p - c).dot(*halfSpace) <= 0) continue;
      fs.regions.push_back({r.surface(p), label});
    }
  };
  // Each region samples only where its label is on every outfit the method covers, so that its
  // colour model is not a mixture with another label: the face and hands are skin under any
  // sleeve; the chest is covered by any upper garment (the shoulders are not, with a sleeveless
  // top); the hips and the top of the thighs by any lower garment (shorts and mini skirts leave
  // mid-thigh bare).
  // Skin: the face (front half of head sections) and hands.
  const Vec3 headAxis = r.at(C::HeadTop) - r.at(C::Neck);
  for (double t : {0.45, 0.6, 0.75})
    addLoop(r.boneLoop(C::Neck, C::HeadTop, t, "head"), headAxis, RegionLabel::Skin, kFront);
  for (const Side& s : kSides) {
    const Vec3 hand = r.at(s.handTip) - r.at(s.wrist);
    for (double t : {0.35, 0.65})
      addLoop(r.boneLoop(s.wrist, s.handTip, t, fmt::format("{} hand", s.name)), hand,
              RegionLabel::Skin);
  }
  // Upper: chest and back.
  const Vec3 spine = r.at(C::Neck) - r.at(C::Pelvis);
  for (double t : {0.5, 0.62, 0.74}) addLoop(r.torsoLoop(t, "chest"), spine, RegionLabel::Upper);
  // Lower: hips and the top of the thighs.
  addLoop(r.torsoLoop(kHipT, "hips"), spine, RegionLabel::Lower);
  for (const Side& s : kSides) {
    const Vec3 thigh = r.at(s.knee) - r.at(s.hip);
    for (double t : {0.1, 0.18})
      addLoop(r.boneLoop(s.hip, s.knee, t, fmt::format("{} thigh", s.name)), thigh,
              RegionLabel::Lower);
  }
  // Foot: around the mid and front foot.
  for (const Side& s : kSides) {
    const Vec3 foot = r.at(s.toeTip) - r.at(s.heel);
    for (double t : {0.45, 0.7})
      addLoop(r.boneLoop(s.heel, s.toeTip, t, fmt::format("{} foot", s.name)), foot,
              RegionLabel::Foot);
  }
}

void seamFeatures(const Rules& r, const FeatureOptions& opt, FeatureSet& fs) {
  // Upper side seams (Fig. 11, first): along the underside of each arm from the wrist to the
  // armpit, then down the side of the torso. 13 front (+) / 13 back (−) paired sign points.
  CurveFeatures upper{"upper_side", {}, {}};
  for (const Side& s : kSides) {
    const Vec3 lateral = s.sign * kLeft;
    std::vector<Vec3> pts;
    auto armPoint = [&](C a, C b, double t) {
      const Vec3 bone = r.at(b) - r.at(a);
      Vec3 under = orthogonalTo(-kUp - 0.5 * lateral, bone);
      const SectionLoop loop = r.boneLoop(a, b, t, fmt::format("{} arm", s.name));
      pts.push_back(extremePoint(loop, under));
    };
    armPoint(s.elbow, s.wrist, 1.0);
    armPoint(s.elbow, s.wrist, 0.5);
    armPoint(s.shoulder, s.elbow, 1.0);
    armPoint(s.shoulder, s.elbow, 0.5);
    armPoint(s.shoulder, s.elbow, 0.2);
    for (double t : {0.7, kUnderArmT, 0.4, 0.25, kHipT}) {
      const SectionLoop loop = r.torsoLoop(t, "torso side");
      pts.push_back(extremePoint(loop, lateral));
    }
    upper.splines.push_back(openSpline(r, fmt::format("{}_upper_side", s.name), pts));
  }
  for (double t : {0.15, 0.3, 0.45, 0.6, 0.7})
    addFrontBackPair(r, upper, fmt::format("torso_{:.2f}", t), r.torsoLoop(t, "torso"), kFront);
  for (const Side& s : kSides)
    addLimbPairs(r, upper, s, "arm",
                 {{s.shoulder, s.elbow, 0.35},
                  {s.shoulder, s.elbow, 0.7},
                  {s.elbow, s.wrist, 0.3},
                  {s.elbow, s.wrist, 0.7}});
  fs.seams.push_back(std::move(upper));

  // Shoulder (armhole) seams: a closed loop around each arm root, in the plane halfway between
  // the upper-arm direction and the body's lateral axis. + chest front, back and sides.
  CurveFeatures shoulder{"shoulder", {}, {}};
  for (const Side& s : kSides) {
    const Vec3 n = ((r.at(s.elbow) - r.at(s.shoulder)).normalized() + s.sign * kLeft).normalized();
    shoulder.splines.push_back(closedSpline(
        r, fmt::format("{}_armhole", s.name),
        r.loopAround(r.along(s.shoulder, s.elbow, kArmholeT), n, fmt::format("{} armhole", s.name)),
        n, opt.loopAnchors));
  }
  const SectionLoop chest = r.torsoLoop(kChestT, "chest");
  addSign(r, shoulder, "chest_front", extremePoint(chest, kFront), +1);
  addSign(r, shoulder, "chest_back", extremePoint(chest, -kFront), +1);
  // The trunk under each arm (beyond the paper's two points): with the arms down the sleeve's
  // cuff hangs a few cm from the torso's side, nearer than the neck, hem and chest points, and
  // the sleeve's side of the armhole function crept down the torso's side and round to its front
  // and back (arms_down, walking: 21–24 cm below the armpit). The torso below the chest, at its
  // side and 45° to the front and back, is trunk in any arm pose; higher up a lowered arm
  // presses into the posed torso and the points there see the arm (Appendix B, rule 2).
  for (double t : {kUnderArmT, 0.4}) {
    const SectionLoop loop = r.torsoLoop(t, "torso side");
    for (const Side& s : kSides)
      for (double f : {-1.0, 0.0, 1.0})
        addSign(r, shoulder, fmt::format("torso_{:.2f}_{}_{:+.0f}", t, s.name, f),
                extremePoint(loop, (s.sign * kLeft + f * kFront).normalized()), +1);
  }
  // The sleeve along the arm (beyond the paper's cuff): − on the arm's outer side (lateral and
  // 45° to the front and back, away from the trunk) at the middle of the upper arm and of the
  // forearm. Where the arm hangs against the trunk the scan joins sleeve and side, and the cuff's
  // −1 alone (far down a long sleeve, beside the hem's +1) let the trunk's + spread over the
  // whole upper sleeve (studio_relaxed). A bare arm leaves these points without cloth (Appendix
  // B drops them), so they hold only a sleeve that is there.
  for (const Side& s : kSides)
    for (const BonePlace& b :
         {BonePlace{s.shoulder, s.elbow, 0.5}, BonePlace{s.elbow, s.wrist, 0.5}}) {
      const Vec3 bone = r.at(b.b) - r.at(b.a);
      const SectionLoop loop = r.boneLoop(b.a, b.b, b.t, fmt::format("{} arm", s.name));
      for (double f : {-1.0, 0.0, 1.0})
        addSign(r, shoulder, fmt::format("arm_{}_{:.2f}_{}_{:+.0f}", toString(b.a), b.t, s.name, f),
                extremePoint(loop, orthogonalTo(s.sign * kLeft + f * kFront, bone).normalized()),
                -1);
    }
  fs.seams.push_back(std::move(shoulder));

  // Lower side seams: outer (ankle → hip → waist) and inner (ankle → crotch) per leg.
  // 11 front (+) / 11 back (−) paired sign points.
  CurveFeatures lower{"lower_side", {}, {}};
  for (const Side& s : kSides) {
    const Vec3 lateral = s.sign * kLeft;
    std::vector<Vec3> outer, inner;
    for (auto [a, b, t] : {std::tuple{s.ankle, s.knee, kAnkleLoopT},
                           std::tuple{s.ankle, s.knee, 0.5}, std::tuple{s.knee, s.hip, 0.0},
                           std::tuple{s.knee, s.hip, 0.4}, std::tuple{s.knee, s.hip, 0.75}}) {
      const Vec3 bone = r.at(b) - r.at(a);
      const SectionLoop loop = r.boneLoop(a, b, t, fmt::format("{} leg", s.name));
      outer.push_back(extremePoint(loop, orthogonalTo(lateral, bone)));
      inner.push_back(extremePoint(loop, orthogonalTo(-lateral, bone)));
    }
    for (double t : {kHipT, 0.12, kWaistT}) {
      const SectionLoop loop = r.torsoLoop(t, "hip side");
      outer.push_back(extremePoint(loop, lateral));
    }
    lower.splines.push_back(openSpline(r, fmt::format("{}_outer_leg", s.name), outer));
    lower.splines.push_back(openSpline(r, fmt::format("{}_inner_leg", s.name), inner));
  }
  for (const Side& s : kSides)
    addLimbPairs(r, lower, s, "leg",
                 {{s.ankle, s.knee, 0.3},
                  {s.ankle, s.knee, 0.7},
                  {s.knee, s.hip, 0.3},
                  {s.knee, s.hip, 0.6}});
  for (double t : {kHipT, 0.12, kWaistT})
    addFrontBackPair(r, lower, fmt::format("hip_{:.2f}", t), r.torsoLoop(t, "hip"), kFront);
  fs.seams.push_back(std::move(lower));

  // Crotch (hip-to-belly) seam: the body's midline from the front waist under the crotch to
  // the back waist, from the sagittal section through the pelvis. 10 left (+) / 10 right (−)
  // (the paper has 4 / 4): hips, and the outer and inner side of each thigh and shin.
  CurveFeatures crotch{"crotch", {}, {}};
  {
    const SectionLoop mid = r.loopAround(r.at(C::Pelvis), kLeft, "body midline");
    const double waistY = r.along(C::Pelvis, C::Neck, kWaistT).dot(kUp);
    // Walk the loop from its front-most point at waist height, keeping points below it.
    std::vector<Vec3> below;
    const int n = static_cast<int>(mid.points.rows());
    Eigen::Index lowest;
    (mid.points * -kUp).maxCoeff(&lowest);  // the crotch
    // From the crotch, walk both ways until the waist height; front half first.
    auto walk = [&](int dir) {
      std::vector<Vec3> pts;
      for (int k = 0; k < n; ++k) {
        const Vec3 p = mid.points.row(((lowest + dir * k) % n + n) % n).transpose();
        if (p.dot(kUp) > waistY) break;
        pts.push_back(p);
      }
      return pts;
    };
    std::vector<Vec3> a = walk(+1), b = walk(-1);
    // `a` goes to the front when its last point has the larger z.
    if (!a.empty() && !b.empty() && a.back().dot(kFront) < b.back().dot(kFront)) std::swap(a, b);
    std::vector<Vec3> path(a.rbegin(), a.rend());
    path.insert(path.end(), b.begin() + 1, b.end());
    if (path.size() < 3)
      throw InputError("feature rules: no crotch below the waist on the body midline");
    // 7 anchors equally spaced by arc length.
    std::vector<double> cum(path.size(), 0.0);
    for (size_t i = 1; i < path.size(); ++i) cum[i] = cum[i - 1] + (path[i] - path[i - 1]).norm();
    std::vector<Vec3> anchors;
    constexpr int kAnchors = 7;
    size_t seg = 0;
    for (int j = 0; j < kAnchors; ++j) {
      const double s = cum.back() * j / (kAnchors - 1);
      while (seg + 2 < path.size() && cum[seg + 1] < s) ++seg;
      const double len = cum[seg + 1] - cum[seg];
      const double u = len > 0 ? std::clamp((s - cum[seg]) / len, 0.0, 1.0) : 0.0;
      anchors.push_back((1 - u) * path[seg] + u * path[seg + 1]);
    }
    crotch.splines.push_back(openSpline(r, "crotch", anchors));
  }
  for (double t : {kHipT, 0.12}) {
    const SectionLoop loop = r.torsoLoop(t, "hip");
    const int i = static_cast<int>(crotch.signs.size());
    crotch.signs.push_back(
        {fmt::format("hip_{:.2f}_left", t), r.surface(extremePoint(loop, kLeft)), +1, i + 1});
    crotch.signs.push_back(
        {fmt::format("hip_{:.2f}_right", t), r.surface(extremePoint(loop, -kLeft)), -1, i});
  }
  // Down each leg, on its outer and its inner side: the thighs, and the shins too, as a biharmonic
  // is held only near its constraints and from the thighs alone it swung across a striding leg
  // (walking: the left/right line ran diagonally over both shins). The inner points hold the
  // inner thighs: from the crotch down between the legs the left/right function is held by no
  // point and its zero line ran down an inner thigh, leaving a tongue of the other side there
  // (walking, patterns). On shorts the shin points find no garment and go with their pairs
  // (§6.1.2); between thighs that touch the inner points see the other leg and go the same way.
  struct LegPlace {
    const char* part;
    C left0, left1, right0, right1;
    double t;
  };
  const double midline = r.at(C::Pelvis).dot(kLeft);
  // The loop point farthest towards the midline among those on the leg's own side of it (a
  // section through touching thighs is one loop around both).
  const auto innerPoint = [&](const SectionLoop& loop, double side) {
    Eigen::Index best = -1;
    for (Eigen::Index i = 0; i < loop.points.rows(); ++i) {
      const double x = side * (loop.points.row(i).dot(kLeft) - midline);
      if (x > 0 && (best < 0 || x < side * (loop.points.row(best).dot(kLeft) - midline))) best = i;
    }
    return best < 0 ? extremePoint(loop, -side * kLeft) : Vec3(loop.points.row(best).transpose());
  };
  for (const bool inner : {false, true})
    for (const LegPlace& g :
         {LegPlace{"thigh", C::LeftHip, C::LeftKnee, C::RightHip, C::RightKnee, 0.3},
          LegPlace{"thigh", C::LeftHip, C::LeftKnee, C::RightHip, C::RightKnee, 0.5},
          LegPlace{"shin", C::LeftKnee, C::LeftAnkle, C::RightKnee, C::RightAnkle, 0.3},
          LegPlace{"shin", C::LeftKnee, C::LeftAnkle, C::RightKnee, C::RightAnkle, 0.7}}) {
      const int i = static_cast<int>(crotch.signs.size());
      const SectionLoop left = r.boneLoop(g.left0, g.left1, g.t, fmt::format("left {}", g.part));
      const SectionLoop right =
          r.boneLoop(g.right0, g.right1, g.t, fmt::format("right {}", g.part));
      const Vec3 pl = inner ? innerPoint(left, +1) : extremePoint(left, kLeft);
      const Vec3 pr = inner ? innerPoint(right, -1) : extremePoint(right, -kLeft);
      const char* where = inner ? "inner_" : "";
      crotch.signs.push_back(
          {fmt::format("{}{}_{:.2f}_left", where, g.part, g.t), r.surface(pl), +1, i + 1});
      crotch.signs.push_back(
          {fmt::format("{}{}_{:.2f}_right", where, g.part, g.t), r.surface(pr), -1, i});
    }
  fs.seams.push_back(std::move(crotch));
}

nlohmann::json pointJson(const SurfacePoint& p, const TriMesh& mesh) {
  const Vec3 x = p.position(mesh);
  return {{"face", p.face},
          {"bary", {p.bary.x(), p.bary.y(), p.bary.z()}},
          {"position", {x.x(), x.y(), x.z()}}};
}

SurfacePoint pointFromJson(const nlohmann::json& j) {
  return {j.at("face").get<int>(),
          Vec3(j.at("bary")[0].get<double>(), j.at("bary")[1].get<double>(),
               j.at("bary")[2].get<double>())};
}

nlohmann::json curveJson(const CurveFeatures& c, const TriMesh& mesh) {
  nlohmann::json splines = nlohmann::json::array(), signs = nlohmann::json::array();
  for (const auto& s : c.splines) {
    nlohmann::json anchors = nlohmann::json::array();
    for (const auto& a : s.anchors) anchors.push_back(pointJson(a, mesh));
    splines.push_back({{"name", s.name}, {"closed", s.closed}, {"anchors", anchors}});
  }
  for (const auto& s : c.signs) {
    nlohmann::json p = pointJson(s.point, mesh);
    p["name"] = s.name;
    p["value"] = s.value;
    p["pair"] = s.pair;
    signs.push_back(p);
  }
  return {{"name", c.name}, {"splines", splines}, {"signs", signs}};
}

CurveFeatures curveFromJson(const nlohmann::json& j) {
  CurveFeatures c;
  c.name = j.at("name").get<std::string>();
  for (const auto& s : j.at("splines")) {
    FeatureSpline sp{s.at("name").get<std::string>(), {}, s.at("closed").get<bool>()};
    for (const auto& a : s.at("anchors")) sp.anchors.push_back(pointFromJson(a));
    c.splines.push_back(std::move(sp));
  }
  for (const auto& s : j.at("signs"))
    c.signs.push_back({s.at("name").get<std::string>(), pointFromJson(s),
                       s.at("value").get<double>(), s.at("pair").get<int>()});
  return c;
}

}  // namespace

const char* toString(RegionLabel label) {
  switch (label) {
    case RegionLabel::Skin:
      return "skin";
    case RegionLabel::Upper:
      return "upper";
    case RegionLabel::Lower:
      return "lower";
    case RegionLabel::Foot:
      return "foot";
  }
  return "skin";
}

const CurveFeatures* FeatureSet::seam(const std::string& name) const {
  for (const auto& s : seams)
    if (s.name == name) return &s;
  return nullptr;
}

FeatureSet computeFeatures(const BodyModel& model, const Eigen::VectorXd& shape,
                           const FeatureOptions& options) {
  BodyParams params;
  params.shape = shape;
  params.pose = BodyPose::zero(model.numJoints());
  const PosedBody rest = poseBody(model, params);
  const Rules rules(rest.mesh, rest.canonical);
  FeatureSet fs;
  boundaryFeatures(rules, options, fs);
  regionFeatures(rules, options, fs);
  seamFeatures(rules, options, fs);
  return fs;
}

nlohmann::json featuresToJson(const FeatureSet& fs, const TriMesh& mesh) {
  nlohmann::json seams = nlohmann::json::array();
  for (const auto& s : fs.seams) seams.push_back(curveJson(s, mesh));
  nlohmann::json regions = nlohmann::json::array();
  for (const auto& r : fs.regions) {
    nlohmann::json p = pointJson(r.point, mesh);
    p["label"] = toString(r.label);
    regions.push_back(p);
  }
  return {{"boundaries",
           {curveJson(fs.upperSkin, mesh), curveJson(fs.lowerSkin, mesh),
            curveJson(fs.upperLower, mesh)}},
          {"seams", seams},
          {"regions", regions}};
}

FeatureSet featuresFromJson(const nlohmann::json& j) {
  FeatureSet fs;
  const auto& b = j.at("boundaries");
  fs.upperSkin = curveFromJson(b.at(0));
  fs.lowerSkin = curveFromJson(b.at(1));
  fs.upperLower = curveFromJson(b.at(2));
  for (const auto& s : j.at("seams")) fs.seams.push_back(curveFromJson(s));
  for (const auto& r : j.at("regions")) {
    const std::string l = r.at("label").get<std::string>();
    const RegionLabel label = l == "upper"   ? RegionLabel::Upper
                              : l == "lower" ? RegionLabel::Lower
                              : l == "foot"  ? RegionLabel::Foot
                                             : RegionLabel::Skin;
    fs.regions.push_back({pointFromJson(r), label});
  }
  return fs;
}

}  // namespace s2p
