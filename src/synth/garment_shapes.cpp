#include "synth/garment_shapes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "core/error.h"

namespace s2p {
namespace {

constexpr double kFar = 1e9;
constexpr double kStackGap = 0.004;  // metres between an inner layer and the one over it
constexpr double kPi = 3.14159265358979323846;

double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

// Polynomial smooth minimum (blend radius k, metres).
double smin(double a, double b, double k) {
  const double h = std::clamp(0.5 + 0.5 * (b - a) / k, 0.0, 1.0);
  return b + (a - b) * h - k * h * (1 - h);
}

// Approximate signed distance to an ellipse with semi-axes r (Quilez), p relative to its centre.
double ellipseDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& r) {
  const double k0 = p.cwiseQuotient(r).norm();
  const double k1 = p.cwiseQuotient(r.cwiseProduct(r)).norm();
  if (k1 < 1e-12) return -std::min(r.x(), r.y());
  return k0 * (k0 - 1) / k1;
}

Eigen::Vector3d row(const Eigen::MatrixX3d& M, Canonical c) {
  return M.row(static_cast<int>(c)).transpose();
}

}  // namespace

bool isArm(BodyPart p) { return p >= BodyPart::LeftUpperArm && p <= BodyPart::RightHand; }
bool isLeg(BodyPart p) { return p >= BodyPart::LeftThigh; }

// === RestSkeleton

RestSkeleton::RestSkeleton(const Eigen::MatrixX3d& canonical) : canonical_(canonical) {
  if (canonical.rows() != kNumCanonical || !canonical.allFinite())
    throw InputError("RestSkeleton: expected " + std::to_string(kNumCanonical) +
                     " finite canonical points, got " + std::to_string(canonical.rows()));
  using C = Canonical;
  using P = BodyPart;
  // Bones carry a typical flesh radius (metres at 1.75 m height): a point goes to the bone whose
  // SURFACE is nearest, so the side of the torso is not taken for the arm hanging next to it.
  const double scale =
      std::max(point(C::HeadTop).y() - std::min(point(C::LeftHeel).y(), point(C::RightHeel).y()),
               0.5) / 1.75;
  auto add = [&](C a, C b, P part, double radius) {
    bones_.push_back({point(a), point(b), part, radius * scale});
  };
  // Main bones first: length(part) uses the first bone of each part.
  add(C::Pelvis, C::Spine, P::Torso, 0.12);
  add(C::Spine, C::Chest, P::Torso, 0.12);
  add(C::Chest, C::Neck, P::Torso, 0.09);
  add(C::Pelvis, C::LeftHip, P::Torso, 0.09);
  add(C::Pelvis, C::RightHip, P::Torso, 0.09);
  add(C::Chest, C::LeftClavicle, P::Torso, 0.08);
  add(C::Chest, C::RightClavicle, P::Torso, 0.08);
  add(C::LeftClavicle, C::LeftShoulder, P::Torso, 0.05);
  add(C::RightClavicle, C::RightShoulder, P::Torso, 0.05);
  add(C::Neck, C::Head, P::Head, 0.06);
  add(C::Head, C::HeadTop, P::Head, 0.07);
  add(C::LeftShoulder, C::LeftElbow, P::LeftUpperArm, 0.045);
  add(C::RightShoulder, C::RightElbow, P::RightUpperArm, 0.045);
  add(C::LeftElbow, C::LeftWrist, P::LeftForearm, 0.035);
  add(C::RightElbow, C::RightWrist, P::RightForearm, 0.035);
  add(C::LeftWrist, C::LeftHandTip, P::LeftHand, 0.02);
  add(C::RightWrist, C::RightHandTip, P::RightHand, 0.02);
  add(C::LeftHip, C::LeftKnee, P::LeftThigh, 0.07);
  add(C::RightHip, C::RightKnee, P::RightThigh, 0.07);
  add(C::LeftKnee, C::LeftAnkle, P::LeftShin, 0.045);
  add(C::RightKnee, C::RightAnkle, P::RightShin, 0.045);
  add(C::LeftHeel, C::LeftToeTip, P::LeftFoot, 0.03);
  add(C::RightHeel, C::RightToeTip, P::RightFoot, 0.03);
}

RestSkeleton::Location RestSkeleton::locate(const Eigen::Vector3d& q) const {
  Location best;
  double bestD = std::numeric_limits<double>::infinity();
  for (const Bone& b : bones_) {
    const Eigen::Vector3d ab = b.b - b.a;
    const double len2 = std::max(ab.squaredNorm(), 1e-12);
    const double t = (q - b.a).dot(ab) / len2;
    const double d = (q - (b.a + std::clamp(t, 0.0, 1.0) * ab)).norm() - b.radius;
    if (d < bestD) {
      bestD = d;
      best = {b.part, t, std::sqrt(len2)};
    }
  }
  return best;
}

double RestSkeleton::length(BodyPart p) const {
  for (const Bone& b : bones_)
    if (b.part == p) return (b.b - b.a).norm();
  return 1;
}

// === GarmentLayer

double GarmentLayer::easeAt(const Eigen::Vector3d& rest) const {
  // More ease towards the hem than at the shoulders / waistband; folds grow towards the hem.
  const double h = std::clamp((yTop - rest.y()) / std::max(yTop - yBottom, 1e-3), 0.0, 1.0);
  double ripple = 0;
  for (int k = 0; k < 3; ++k) ripple += std::sin(rippleK[k].dot(rest) + ripplePhase[k]);
  return ease * (0.7 + 0.6 * h) * (1 + 0.12 * (0.3 + h) * ripple);
}

double GarmentLayer::region(const RestSkeleton& skel, const Eigen::Vector3d& q) const {
  return region(skel, skel.locate(q), q);
}

double GarmentLayer::region(const RestSkeleton& skel, const RestSkeleton::Location& loc,
                            const Eigen::Vector3d& q) const {
  const double y = q.y();
  if (type == GarmentType::Shoes) {
    if (loc.part == BodyPart::LeftFoot || loc.part == BodyPart::RightFoot) return 0.05;
    if (loc.part == BodyPart::LeftShin || loc.part == BodyPart::RightShin)
      return (loc.t - shoeT) * loc.length;
    return -0.05;
  }
  if (type == GarmentType::Hair) {
    if (loc.part != BodyPart::Head) return -0.05;
    return std::max(y - yForehead, zHead - q.z());
  }
  double r = std::min(y - yHem, yUpper - y);
  if (neckRadius > 0) {
    const double radial = Eigen::Vector2d(q.x() - neck.x(), q.z() - neck.z()).norm();
    r = std::min({y - yHem, std::max(yUpper - y, radial - neckRadius), neck.y() - y});
  }
  if (isArm(loc.part)) {
    const bool left = loc.part == BodyPart::LeftUpperArm || loc.part == BodyPart::LeftForearm ||
                      loc.part == BodyPart::LeftHand;
    const double lu = skel.length(left ? BodyPart::LeftUpperArm : BodyPart::RightUpperArm);
    const double lf = skel.length(left ? BodyPart::LeftForearm : BodyPart::RightForearm);
    double s = loc.t * loc.length;  // arc length from the shoulder joint
    if (loc.part == BodyPart::LeftForearm || loc.part == BodyPart::RightForearm) s += lu;
    if (loc.part == BodyPart::LeftHand || loc.part == BodyPart::RightHand) s += lu + lf;
    double sHem = armT < 0 ? -0.015 : armT <= 1 ? armT * lu : lu + (armT - 1) * lf;
    if (looseArmFrom >= 0) sHem = std::min(sHem, looseArmFrom * lu);
    r = std::min(r, sHem - s);
  } else if (isLeg(loc.part)) {
    const bool left = loc.part == BodyPart::LeftThigh || loc.part == BodyPart::LeftShin ||
                      loc.part == BodyPart::LeftFoot;
    const double lt = skel.length(left ? BodyPart::LeftThigh : BodyPart::RightThigh);
    const double ls = skel.length(left ? BodyPart::LeftShin : BodyPart::RightShin);
    double s = loc.t * loc.length;
    if (loc.part == BodyPart::LeftShin || loc.part == BodyPart::RightShin) s += lt;
    if (loc.part == BodyPart::LeftFoot || loc.part == BodyPart::RightFoot) s = lt + ls + 0.05;
    double sHem = legT < 0 ? 0.0 : legT <= 1 ? legT * lt : lt + (legT - 1) * ls;
    if (looseLegFrom >= 0) sHem = std::min(sHem, looseLegFrom * lt);
    r = std::min(r, sHem - s);
  } else if (loc.part == BodyPart::Head) {
    r = std::min(r, -0.01);
  }
  return r;
}

bool GarmentLayer::analyticBox(Eigen::Vector3d& lo, Eigen::Vector3d& hi) const {
  const double inf = std::numeric_limits<double>::infinity();
  lo.setConstant(inf);
  hi.setConstant(-inf);
  if (frustum) {
    const double rx = std::max(rTop.x(), rBottom.x()), rz = std::max(rTop.y(), rBottom.y());
    lo = lo.cwiseMin(Eigen::Vector3d(centre.x() - rx, fBottom, centre.y() - rz));
    hi = hi.cwiseMax(Eigen::Vector3d(centre.x() + rx, fTop, centre.y() + rz));
  }
  for (const Cone& c : cones) {
    const double r = std::max(c.ra, c.rb);
    lo = lo.cwiseMin((c.a.cwiseMin(c.b).array() - r).matrix());
    hi = hi.cwiseMax((c.a.cwiseMax(c.b).array() + r).matrix());
  }
  for (const Box& b : boxes) {
    const Eigen::Vector3d ext = b.axes.cwiseAbs() * b.half;
    lo = lo.cwiseMin(b.centre - ext);
    hi = hi.cwiseMax(b.centre + ext);
  }
  return (lo.array() <= hi.array()).all();
}

// === GarmentLayers

namespace {

struct Levels {
  double pelvis, hip, spine, chest, neck, waist, scale;
};

// Max radial distance from the posed bone a→b of the posed vertices of `part` whose
// projection parameter is near t0.
double limbRadius(const TriMesh& posed, const std::vector<BodyPart>& parts, BodyPart part,
                  const Eigen::Vector3d& a, const Eigen::Vector3d& b, double t0) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = std::max(ab.squaredNorm(), 1e-12);
  double r = 0;
  for (int v = 0; v < posed.numVertices(); ++v) {
    if (parts[v] != part) continue;
    const Eigen::Vector3d p = posed.V.row(v).transpose();
    const double t = (p - a).dot(ab) / len2;
    if (std::abs(t - t0) > 0.1) continue;
    r = std::max(r, (p - a - t * ab).norm());
  }
  return r > 0 ? r : 0.05;
}

}  // namespace

GarmentLayers::GarmentLayers(const PosedBody& rest, const PosedBody& posed, const Outfit& outfit,
                             std::uint64_t seed)
    : skeleton_(rest.canonical) {
  if (rest.mesh.numVertices() != posed.mesh.numVertices() ||
      rest.mesh.numFaces() != posed.mesh.numFaces())
    throw InputError("GarmentLayers: rest and posed bodies differ in size");
  using C = Canonical;
  const Eigen::MatrixX3d& rc = rest.canonical;
  const Eigen::MatrixX3d& pc = posed.canonical;
  const double pelvisY = row(rc, C::Pelvis).y();
  const double hipY = 0.5 * (row(rc, C::LeftHip).y() + row(rc, C::RightHip).y());
  const double spineY = row(rc, C::Spine).y();
  const double chestY = row(rc, C::Chest).y();
  const double neckY = row(rc, C::Neck).y();
  const double headTopY = row(rc, C::HeadTop).y();
  const double scale = std::max(headTopY - std::min(row(rc, C::LeftHeel).y(),
                                                    row(rc, C::RightHeel).y()), 0.5) / 1.75;
  const double waistY = spineY;                        // waistband of trousers and skirts
  const double hipLineY = hipY + 0.02 * scale;         // t-shirt hem, skirt flare start
  const double necklineY = neckY - 0.35 * (neckY - chestY);
  const double kneeY = 0.5 * (row(rc, C::LeftKnee).y() + row(rc, C::RightKnee).y());
  const double ankleY = 0.5 * (row(rc, C::LeftAnkle).y() + row(rc, C::RightAnkle).y());

  // Rest part of every body vertex (for the free-hanging shapes' fit around the posed body).
  std::vector<BodyPart> parts(rest.mesh.numVertices());
  for (int v = 0; v < rest.mesh.numVertices(); ++v)
    parts[v] = skeleton_.locate(rest.mesh.V.row(v).transpose()).part;
  const TriMesh& pm = posed.mesh;
  // Posed heights keep their offsets from the posed pelvis.
  const double pelvisPosedY = row(pc, C::Pelvis).y();
  auto posedY = [&](double restY) { return pelvisPosedY + (restY - pelvisY); };

  std::mt19937_64 rng(seed * 0x9E3779B97F4A7C15ull + 12345);
  std::uniform_real_distribution<double> uni(0, 1);

  // Stacking order (§5.3): tucked-in tops under the lower garments, which lie under the other
  // tops (an upper garment hangs over the lower one); then shoes, hair, bag. Within a rank the
  // outfit's inner-to-outer order.
  std::vector<int> order;
  for (int pass = 0; pass < 6; ++pass)
    for (int g = 0; g < static_cast<int>(outfit.garments.size()); ++g) {
      const GarmentSpec& s = outfit.garments[g];
      const Label label = labelOf(s.type);
      const int rank = s.type == GarmentType::Shoes  ? 3
                       : s.type == GarmentType::Hair ? 4
                       : s.type == GarmentType::Bag  ? 5
                       : label == Label::Lower       ? 1
                       : s.tuckedIn                  ? 0
                                                     : 2;
      if (rank == pass) order.push_back(g);
    }
  for (std::size_t i = 0; i < outfit.garments.size(); ++i) {
    const GarmentSpec& s = outfit.garments[i];
    if (!(s.ease >= 0 && s.ease <= 0.1) || !std::isfinite(s.looseness) || s.looseness < 0 ||
        s.looseness > 1 || !(std::abs(s.length) <= 0.5))
      throw InputError("outfit garment " + std::to_string(i) + " (" + toString(s.type) +
                       "): ease must be in [0, 0.1] m, looseness in [0, 1], |length| ≤ 0.5 m");
  }

  for (int g : order) {
    const GarmentSpec& s = outfit.garments[g];
    GarmentLayer L;
    L.garment = g;
    L.type = s.type;
    L.label = labelOf(s.type);
    L.ease = s.ease;
    for (int k = 0; k < 3; ++k) {
      // Mostly horizontal wave vectors: vertical folds, 8–16 cm wavelength.
      const double ang = 2 * kPi * uni(rng);
      const double wl = (0.08 + 0.08 * uni(rng)) * scale;
      L.rippleK[k] = (2 * kPi / wl) * Eigen::Vector3d(std::cos(ang), 0.25 * (uni(rng) - 0.5),
                                                      std::sin(ang));
      L.ripplePhase[k] = 2 * kPi * uni(rng);
    }
    const double lu = skeleton_.length(BodyPart::LeftUpperArm);
    const double lf = skeleton_.length(BodyPart::LeftForearm);
    const double lt = skeleton_.length(BodyPart::LeftThigh);
    const double ls = skeleton_.length(BodyPart::LeftShin);
    const double skirtTopY = hipLineY;
    double frustumHemY = 0;
    switch (s.type) {
      case GarmentType::TShirt:
        L.yHem = hipLineY - s.length;
        L.yUpper = necklineY;
        L.armT = std::clamp(0.55 + s.length / lu, 0.05, 1.0);  // past the armpit crease
        break;
      case GarmentType::LongSleeveShirt:
        L.yHem = hipLineY - 0.02 * scale - s.length;
        L.yUpper = necklineY + 0.01 * scale;
        L.armT = std::clamp(1.92 + s.length / lf, 1.0, 1.97);
        break;
      case GarmentType::SleevelessTop:
        L.yHem = hipLineY - s.length;
        L.yUpper = necklineY - 0.01 * scale;
        break;
      case GarmentType::Jacket:
        L.yHem = hipY - 0.07 * scale - s.length;
        L.yUpper = necklineY + 0.015 * scale;
        L.armT = std::clamp(1.9 + s.length / lf, 1.0, 1.97);
        break;
      case GarmentType::Dress:
        L.yHem = skirtTopY - 0.03 * scale;
        L.yUpper = necklineY - 0.01 * scale;
        frustumHemY = kneeY + 0.04 * scale - s.length;
        break;
      case GarmentType::Trousers:
        L.yUpper = waistY;
        L.legT = std::clamp(1.93 + s.length / ls, 1.0, 1.99);
        break;
      case GarmentType::Shorts:
        L.yUpper = waistY;
        L.legT = std::clamp(0.5 + s.length / lt, 0.05, 1.0);
        break;
      case GarmentType::KneeSkirt:
        L.yUpper = waistY;
        L.yHem = skirtTopY - 0.03 * scale;
        frustumHemY = kneeY + 0.02 * scale - s.length;
        break;
      case GarmentType::LongSkirt:
        L.yUpper = waistY;
        L.yHem = skirtTopY - 0.03 * scale;
        frustumHemY = 0.5 * (kneeY + ankleY) - s.length;
        break;
      case GarmentType::Shoes:
        L.shoeT = std::clamp(1 - (0.05 * scale + s.length) / ls, 0.5, 1.0);
        break;
      case GarmentType::Hair:
        L.yForehead = row(rc, C::Nose).y() + 0.05 * scale;
        L.zHead = row(rc, C::Head).z() + 0.01 * scale;
        break;
      case GarmentType::Bag:
        L.fitted = false;
        break;
    }
    if (L.label == Label::Upper) {
      L.neckRadius = (s.type == GarmentType::Jacket ? 0.08 : 0.075) * scale;
      L.neck = row(rc, C::Neck);
    }
    L.yTop = std::min(L.yUpper, headTopY);
    L.yBottom = std::max(L.yHem, 0.0);
    if (L.legT > 0) L.yBottom = L.legT <= 1 ? kneeY + (1 - L.legT) * (hipY - kneeY) : ankleY;
    if (L.armT > 1) L.yBottom = std::min(L.yBottom, hipY);
    if (s.type == GarmentType::Shoes) L.yTop = ankleY + 0.05 * scale, L.yBottom = 0;
    if (s.type == GarmentType::Hair) L.yTop = headTopY, L.yBottom = necklineY;

    // === Free-hanging skirt: an elliptic frustum around the pelvis hiding the legs (§5.2).
    if (isFreeHanging(s.type)) {
      L.frustum = true;
      L.fTop = posedY(skirtTopY);
      L.fBottom = posedY(frustumHemY);
      L.centre = Eigen::Vector2d(row(pc, C::Pelvis).x(), row(pc, C::Pelvis).z());
      const double e = std::max(s.ease, 0.006);
      // Top: enclose the hips at the top band.
      Eigen::Vector2d rTop(0.05, 0.05);
      std::vector<Eigen::Vector3d> pts;
      for (int v = 0; v < pm.numVertices(); ++v) {
        if (isArm(parts[v]) || parts[v] == BodyPart::Head) continue;
        const Eigen::Vector3d p = pm.V.row(v).transpose();
        if (p.y() < L.fBottom - 0.01 || p.y() > L.fTop) continue;
        pts.push_back(p);
        if (p.y() > L.fTop - 0.04 * scale)
          rTop = rTop.cwiseMax(Eigen::Vector2d(std::abs(p.x() - L.centre.x()),
                                               std::abs(p.z() - L.centre.y())));
      }
      rTop.array() += e;
      const double flare = (s.type == GarmentType::LongSkirt ? 0.15 : 0.08) + 0.3 * s.looseness;
      Eigen::Vector2d rBot = rTop * (1 + flare);
      // Grow top and bottom until every leg / hip point is inside by the ease.
      for (int it = 0; it < 200; ++it) {
        double worst = 0, worstW = 0;
        for (const Eigen::Vector3d& p : pts) {
          const double w = std::clamp((L.fTop - p.y()) / (L.fTop - L.fBottom), 0.0, 1.0);
          const Eigen::Vector2d r = (1 - w) * rTop + w * rBot;
          const Eigen::Vector2d q(p.x() - L.centre.x(), p.z() - L.centre.y());
          const double k = q.cwiseQuotient((r.array() - e).max(0.01).matrix()).norm();
          if (k > worst) worst = k, worstW = w;
        }
        if (worst <= 1) break;
        if (worstW < 0.3) rTop *= 1.02;
        rBot *= 1.02;
      }
      L.rTop = rTop;
      L.rBottom = rBot;
    }

    // === Loose sleeves and trouser legs: cones around the posed limb axes.
    if (s.looseness > 0) {
      const double widen = 0.045 * scale * s.looseness;
      auto limb = [&](C a0, C a1, BodyPart part, double tEnd, double extraA, bool hem,
                      double prevR) {
        // The loose part starts a third down the limb (above, the garment follows the body).
        const Eigen::Vector3d j0 = row(pc, a0), b1 = row(pc, a1);
        const double t0 = prevR > 0 ? 0.0 : 0.3;
        const Eigen::Vector3d a = j0 + t0 * (b1 - j0);
        const Eigen::Vector3d b = j0 + std::min(tEnd, 1.0) * (b1 - j0);
        GarmentLayer::Cone cone;
        cone.a = a;
        cone.b = b;
        cone.ra = prevR > 0 ? prevR
                            : limbRadius(pm, parts, part, j0, b1, t0 + 0.05) + s.ease + extraA;
        cone.rb = limbRadius(pm, parts, part, j0, b1, std::max(std::min(tEnd, 1.0) - 0.08, 0.1)) +
                  s.ease + widen;
        cone.rb = std::max(cone.rb, 0.9 * cone.ra);
        cone.hemAtB = hem;
        L.cones.push_back(cone);
        return cone.rb;
      };
      // The body-following part ends 0.15 of the limb inside the cone (which starts at 0.3).
      if (L.armT > 0) L.looseArmFrom = 0.45;
      if (L.legT > 0) L.looseLegFrom = 0.45;
      const bool sides[2] = {true, false};
      for (bool left : sides) {
        if (L.armT > 0) {
          const C sh = left ? C::LeftShoulder : C::RightShoulder;
          const C el = left ? C::LeftElbow : C::RightElbow;
          const C wr = left ? C::LeftWrist : C::RightWrist;
          const BodyPart ua = left ? BodyPart::LeftUpperArm : BodyPart::RightUpperArm;
          const BodyPart fa = left ? BodyPart::LeftForearm : BodyPart::RightForearm;
          const double r = limb(sh, el, ua, std::min(L.armT, 1.0), 0.005, L.armT <= 1, 0);
          if (L.armT > 1) limb(el, wr, fa, L.armT - 1, 0, true, r);
        }
        if (L.legT > 0) {
          const C hp = left ? C::LeftHip : C::RightHip;
          const C kn = left ? C::LeftKnee : C::RightKnee;
          const C an = left ? C::LeftAnkle : C::RightAnkle;
          const BodyPart th = left ? BodyPart::LeftThigh : BodyPart::RightThigh;
          const BodyPart sn = left ? BodyPart::LeftShin : BodyPart::RightShin;
          const double r = limb(hp, kn, th, std::min(L.legT, 1.0), 0.005, L.legT <= 1, 0);
          if (L.legT > 1) limb(kn, an, sn, L.legT - 1, 0, true, r);
        }
      }
    }

    // === Hair curtain over the back of the head down to the shoulders (paper case r).
    if (s.type == GarmentType::Hair) {
      const Eigen::Vector3d H = row(pc, C::Head), N = row(pc, C::Neck);
      const Eigen::Vector3d up = (H - N).normalized();
      Eigen::Vector3d fwd = row(pc, C::Nose) - H;
      fwd = (fwd - fwd.dot(up) * up).normalized();
      const Eigen::Vector3d right = up.cross(fwd);
      const double shoulderDrop =
          (H - 0.5 * (row(pc, C::LeftShoulder) + row(pc, C::RightShoulder))).dot(up) +
          0.01 * scale;
      const double top = 0.06 * scale, back = -0.125 * scale, front = 0.0;
      GarmentLayer::Box box;
      box.axes.col(0) = right;
      box.axes.col(1) = up;
      box.axes.col(2) = fwd;
      box.half = Eigen::Vector3d(0.09 * scale, 0.5 * (top + shoulderDrop), 0.5 * (front - back));
      box.centre = H + up * 0.5 * (top - shoulderDrop) + fwd * 0.5 * (front + back);
      box.rounding = 0.035 * scale;
      L.boxes.push_back(box);
    }
    // === Bag held against the right hip (paper case a).
    if (s.type == GarmentType::Bag) {
      const Eigen::Vector3d P = row(pc, C::Pelvis);
      double minX = P.x();
      for (int v = 0; v < pm.numVertices(); ++v)
        if ((parts[v] == BodyPart::Torso || isLeg(parts[v])) &&
            std::abs(pm.V(v, 1) - P.y()) < 0.06 * scale)
          minX = std::min(minX, pm.V(v, 0));
      GarmentLayer::Box box;
      box.axes.setIdentity();
      box.half = Eigen::Vector3d(0.045, 0.12, 0.15) * scale;
      box.centre = Eigen::Vector3d(minX - box.half.x() + 0.012 * scale, P.y() - 0.05 * scale,
                                   P.z());
      box.rounding = 0.025 * scale;
      L.boxes.push_back(box);
    }
    if (L.fitted) maxEase_ = std::max(maxEase_, 1.3 * 1.2 * s.ease);
    layers_.push_back(L);
  }
  // Every fitted layer lies over the fitted layers before it in the stacking order.
  for (int i = 0; i < size(); ++i)
    for (int j = 0; j < i; ++j)
      if (layers_[i].fitted && layers_[j].fitted) layers_[i].under.push_back(j);
  maxEase_ += kStackGap * size();
}

double GarmentLayers::stackedEase(int i, const Eigen::Vector3d& rest,
                                  const RestSkeleton::Location& loc,
                                  std::vector<double>& cache) const {
  if (cache[i] >= 0) return cache[i];
  const GarmentLayer& L = layers_[i];
  double e = L.easeAt(rest);
  for (int j : L.under) {
    const double w = smoothstep(-0.03, 0.0, layers_[j].region(skeleton_, loc, rest));
    if (w > 0) e = std::max(e, w * (stackedEase(j, rest, loc, cache) + kStackGap));
  }
  cache[i] = e;
  return e;
}

void GarmentLayers::evaluate(const Eigen::Vector3d& p, const BodySample& body,
                             LayerValue* out) const {
  thread_local std::vector<double> cache;
  cache.assign(layers_.size(), -1.0);
  RestSkeleton::Location loc;
  if (body.hasRest) loc = skeleton_.locate(body.rest);  // shared by every layer
  for (int i = 0; i < size(); ++i) {
    const GarmentLayer& L = layers_[i];
    LayerValue v;
    if (L.fitted) {
      if (body.hasRest)
        v.value = std::max(body.d - stackedEase(i, body.rest, loc, cache),
                           -L.region(skeleton_, loc, body.rest));
      else
        v.value = body.d > 0 ? kFar : body.d;
    }
    if (L.frustum) {
      const double w = std::clamp((L.fTop - p.y()) / (L.fTop - L.fBottom), 0.0, 1.0);
      const Eigen::Vector2d r = (1 - w) * L.rTop + w * L.rBottom;
      const double side =
          ellipseDistance(Eigen::Vector2d(p.x() - L.centre.x(), p.z() - L.centre.y()), r);
      const double top = p.y() - L.fTop, bottom = L.fBottom - p.y();
      const double f = std::max({side, top, bottom});
      if (f < v.value) v.gap = bottom >= side && bottom >= top;
      v.value = L.fitted ? smin(v.value, f, 0.02) : std::min(v.value, f);
    }
    for (const GarmentLayer::Cone& c : L.cones) {
      const Eigen::Vector3d ab = c.b - c.a;
      const double len = std::max(ab.norm(), 1e-9);
      const Eigen::Vector3d dir = ab / len;
      const double u = (p - c.a).dot(dir);
      const double radial = (p - c.a - u * dir).norm();
      const double s = std::clamp(u / len, 0.0, 1.0);
      const double side = radial - ((1 - s) * c.ra + s * c.rb);
      const double capB = u - len;
      const double f = std::max({side, -u, capB});
      if (f < v.value) {
        v.value = f;
        v.gap = c.hemAtB && capB >= side && capB >= -u;
      }
    }
    for (const GarmentLayer::Box& b : L.boxes) {
      const Eigen::Vector3d local = b.axes.transpose() * (p - b.centre);
      const Eigen::Vector3d q =
          local.cwiseAbs() - (b.half.array() - b.rounding).max(0.0).matrix();
      const double f = q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0) - b.rounding;
      if (f < v.value) v.value = f, v.gap = false;
    }
    out[i] = v;
  }
}

double GarmentLayers::unionValue(const Eigen::Vector3d& p, const BodySample& body) const {
  thread_local std::vector<LayerValue> values;
  values.resize(layers_.size());
  evaluate(p, body, values.data());
  double u = body.d;
  for (const LayerValue& v : values) u = std::min(u, v.value);
  return u;
}

int GarmentLayers::visibleLayer(const Eigen::Vector3d& p, const BodySample& body,
                                bool* gap) const {
  thread_local std::vector<LayerValue> values;
  values.resize(layers_.size());
  evaluate(p, body, values.data());
  int best = -1;
  double bestValue = body.d;
  bool bestGap = false;
  for (int i = 0; i < size(); ++i)
    if (values[i].value <= bestValue) {  // ties: the outer layer
      best = i;
      bestValue = values[i].value;
      bestGap = values[i].gap;
    }
  if (gap) *gap = bestGap;
  return best;
}

Label GarmentLayers::labelAt(const Eigen::Vector3d& p, const BodySample& body) const {
  bool gap = false;
  const int i = visibleLayer(p, body, &gap);
  if (i < 0) return Label::Skin;
  return gap ? Label::Gap : layers_[i].label;
}

}  // namespace s2p
