#include "pattern/seam_lines.h"

#include <fmt/format.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <map>
#include <memory>
#include <optional>
#include <unordered_map>
#include <utility>

#include "core/coarse_mesh.h"
#include "core/error.h"
#include "core/mesh_query.h"
#include "core/mesh_topology.h"
#include "core/row_tree.h"
#include "segment/biharmonic.h"
#include "segment/surface_spline.h"

namespace s2p {

const char* toString(SeamKind kind) {
  switch (kind) {
    case SeamKind::FrontBack:
      return "front_back";
    case SeamKind::Armhole:
      return "armhole";
    case SeamKind::LeftRight:
      return "left_right";
  }
  return "?";
}

const char* toString(GarmentKind kind) {
  switch (kind) {
    case GarmentKind::Upper:
      return "upper";
    case GarmentKind::Lower:
      return "lower";
    case GarmentKind::OnePiece:
      return "onepiece";
  }
  return "?";
}

namespace {

using Vec3 = Eigen::Vector3d;

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Where an opening starts counting as a cuff rather than an armhole: a fifth of the way from
// the shoulder to the wrist (a sleeveless armhole sits at the shoulder joint, t ≈ 0–0.1; the
// shortest cap sleeve ends at t ≈ 0.25).
constexpr double kCuffT = 0.2;

const char* sideOf(Limb l) {
  return l == Limb::LeftArm || l == Limb::LeftLeg ? "left" : "right";
}

std::vector<std::string> featureNames(SeamKind kind, GarmentKind garment) {
  switch (kind) {
    case SeamKind::FrontBack:
      if (garment == GarmentKind::Upper) return {"upper_side"};
      if (garment == GarmentKind::Lower) return {"lower_side"};
      return {"upper_side", "lower_side"};
    case SeamKind::Armhole:
      if (garment == GarmentKind::Lower) return {};
      return {"shoulder"};
    case SeamKind::LeftRight:
      if (garment == GarmentKind::Upper) return {};
      return {"crotch"};
  }
  return {};
}

const char* seamName(SeamKind kind) {
  switch (kind) {
    case SeamKind::FrontBack:
      return "side";
    case SeamKind::Armhole:
      return "armhole";
    case SeamKind::LeftRight:
      return "crotch";
  }
  return "?";
}

// Points of a boundary polyline about `spacing` apart, as value constraints.
void addLoopConstraints(const MeshTopology& topo, const TriMesh& mesh,
                        const std::vector<int>& vertices, double spacing, double value,
                        std::vector<ValueConstraint>& out) {
  double since = spacing;
  for (size_t i = 0; i < vertices.size(); ++i) {
    const int v = vertices[i];
    if (i > 0) since += (mesh.V.row(v) - mesh.V.row(vertices[i - 1])).norm();
    if (since < spacing) continue;
    since = 0;
    out.push_back({SurfacePoint::atVertex(topo, mesh.F, v), value});
  }
}

// Garment vertices about `spacing` apart (greedy in vertex order on a grid of that cell size),
// none within `clearance` of a point of `avoid`.
std::vector<int> spacedVertices(const TriMesh& mesh, double spacing, const std::vector<Vec3>& avoid,
                                double clearance) {
  std::unordered_map<std::int64_t, std::vector<int>> grid;
  const auto cell = [&](const Vec3& p, int dx, int dy, int dz) {
    const std::int64_t x = static_cast<std::int64_t>(std::floor(p.x() / spacing)) + dx;
    const std::int64_t y = static_cast<std::int64_t>(std::floor(p.y() / spacing)) + dy;
    const std::int64_t z = static_cast<std::int64_t>(std::floor(p.z() / spacing)) + dz;
    return (x & 0x1FFFFF) | ((y & 0x1FFFFF) << 21) | ((z & 0x1FFFFF) << 42);
  };
  std::vector<int> out;
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const Vec3 p = mesh.V.row(v).transpose();
    bool free = true;
    for (const Vec3& a : avoid) free &= (a - p).norm() >= clearance;
    for (int dx = -1; dx <= 1 && free; ++dx)
      for (int dy = -1; dy <= 1 && free; ++dy)
        for (int dz = -1; dz <= 1 && free; ++dz) {
          const auto it = grid.find(cell(p, dx, dy, dz));
          if (it == grid.end()) continue;
          for (int w : it->second) free &= (mesh.V.row(w).transpose() - p).norm() >= spacing;
        }
    if (!free) continue;
    grid[cell(p, 0, 0, 0)].push_back(v);
    out.push_back(v);
  }
  return out;
}

// Beyond §6.1.2: the armhole function held where the fitted body says which part the garment
// covers (SeamOptions::partNormalDot and below). sleeved[0]: the left arm has a sleeve,
// sleeved[1]: the right. Appends to `out`; counts them in `seam`.
void addBodyPartConstraints(const TriMesh& garment, const MeshTopology& topo, const TriMesh& body,
                            const Eigen::MatrixXd& limbW, const std::array<bool, 2>& sleeved,
                            const std::vector<Vec3>& anchors, double bodyLength,
                            const SeamOptions& o, SeamLine& seam,
                            std::vector<ValueConstraint>& out) {
  const std::vector<int> samples =
      spacedVertices(garment, o.partSpacing, anchors, o.partAnchorClearance);
  if (samples.empty()) return;
  Eigen::MatrixX3d gn = vertexNormals(garment);
  const Eigen::MatrixX3d bn = vertexNormals(body);
  const RowCloud cloud{&body.V};
  const RowTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  // The garment's orientation against the body's (outward): the nearest body vertex's normal
  // agrees with most of a garment's normals when both face out.
  int agree = 0;
  for (int v : samples) {
    std::uint32_t i = 0;
    double d2 = 0;
    const Vec3 p = garment.V.row(v).transpose();  // V is column-major: rows are not contiguous
    tree.knnSearch(p.data(), 1, &i, &d2);
    agree += gn.row(v).dot(bn.row(static_cast<int>(i))) >= 0 ? 1 : -1;
  }
  if (agree < 0) gn = -gn;
  const double radius = o.partMaxDistance * bodyLength;
  const int left = static_cast<int>(Limb::LeftArm), right = static_cast<int>(Limb::RightArm);
  std::vector<std::pair<std::uint32_t, double>> hits;
  for (int v : samples) {
    const Vec3 p = garment.V.row(v).transpose();
    hits.clear();
    tree.radiusSearch(p.data(), radius * radius, hits, nanoflann::SearchParams(32, 0, true));
    int b = -1;
    for (const auto& [i, d2] : hits)
      if (gn.row(v).dot(bn.row(static_cast<int>(i))) >= o.partNormalDot) {
        b = static_cast<int>(i);
        break;
      }
    if (b < 0) {
      ++seam.unmatchedPoints;
      continue;
    }
    const double wl = limbW(b, left), wr = limbW(b, right);
    double value = 0;
    if (wl + wr <= o.trunkArmWeight) {
      value = +1;
      ++seam.trunkPoints;
    } else if ((sleeved[0] && wl >= o.sleeveArmWeight) || (sleeved[1] && wr >= o.sleeveArmWeight)) {
      value = -1;
      ++seam.sleevePoints;
    } else {
      continue;
    }
    out.push_back({SurfacePoint::atVertex(topo, garment.F, v), value});
  }
}

// A seam anchor dropped by Appendix B that is a contact, not an occlusion (SeamOptions::
// contactDistance). Rule 2 drops q when its ray meets the body before the scan: another part of
// the body stands between q and the cloth, so q's closest scan point belongs to that part. Where
// the arm hangs against the trunk, the ray from the trunk's side (or the arm's underside) meets
// the arm (the trunk) across a gap narrower than two layers of cloth: nothing stands between,
// the top's cloth covers both sides of the contact (sleeve and side, pressed together or fused
// by the scan), and the scan's surface nearest q is that cloth. Such a q is kept. Only the
// features of a top's trunk–arm contact, upper_side and shoulder: a hand hanging against the
// thigh is bare, the trousers under it are cut away with the skin, and lower_side's anchor there
// would land on the edge of that hole, not on the seam; between the legs a ray meeting the other
// leg is what tells a skirt from trousers (the crotch's anchors must go).
bool isContact(const ProjectedPoint& p, const Vec3& q, const std::string& feature,
               double contactDistance, double clothDistance) {
  if ((feature != "upper_side" && feature != "shoulder") || contactDistance <= 0) return false;
  return p.status == ProjectionStatus::HitBody && p.hitDistance <= contactDistance &&
         (p.p - q).norm() <= clothDistance;
}

// Angle (rad) that the polyline `run` winds about an arm's axis (shoulder → elbow → wrist), each
// vertex taken about its own closest axis point, in the plane across the axis there.
double windingAboutArm(const TriMesh& mesh, const std::vector<int>& run, const BodyFrame& frame,
                       Limb arm) {
  using C = Canonical;
  const bool left = arm == Limb::LeftArm;
  const std::array<Vec3, 3> chain{frame.at(left ? C::LeftShoulder : C::RightShoulder),
                                  frame.at(left ? C::LeftElbow : C::RightElbow),
                                  frame.at(left ? C::LeftWrist : C::RightWrist)};
  const auto across = [&](const Vec3& p, Vec3& dir) {
    double best = std::numeric_limits<double>::infinity();
    Vec3 out = Vec3::Zero();
    for (int i = 0; i < 2; ++i) {
      const Vec3 ab = chain[i + 1] - chain[i];
      const double u = ab.squaredNorm() > 0
                           ? std::clamp((p - chain[i]).dot(ab) / ab.squaredNorm(), 0.0, 1.0)
                           : 0.0;
      const Vec3 r = p - (chain[i] + u * ab);
      if (r.norm() < best) {
        best = r.norm();
        dir = ab.normalized();
        out = r - r.dot(dir) * dir;
      }
    }
    return out;
  };
  double winding = 0;
  for (size_t i = 0; i + 1 < run.size(); ++i) {
    Vec3 d = Vec3::Zero();  // left zero (no turn counted) when no distance is finite
    const Vec3 a = across(mesh.V.row(run[i]).transpose(), d);
    const Vec3 b = across(mesh.V.row(run[i + 1]).transpose(), d);
    winding += std::atan2(a.cross(b).dot(d), a.dot(b));
  }
  return winding;
}

// Signed number of times the arm's bone chain (clavicle → shoulder → elbow → wrist → hand tip)
// passes through the fan of triangles from `centre` over the closed loop: ±1 when the arm goes
// through the loop, whatever the pose, 0 when the loop lies beside the arm. The chain starts in
// the trunk and ends outside the garment, so it passes through the opening the arm leaves by
// (an armhole or a cuff); a hole the scan left in the armpit or on the sleeve lies on the cloth,
// away from the bones.
int armChainCrossings(const TriMesh& mesh, const std::vector<int>& loop, const Vec3& centre,
                      const BodyFrame& frame, Limb arm) {
  using C = Canonical;
  const bool left = arm == Limb::LeftArm;
  const std::array<Vec3, 5> chain{frame.at(left ? C::LeftClavicle : C::RightClavicle),
                                  frame.at(left ? C::LeftShoulder : C::RightShoulder),
                                  frame.at(left ? C::LeftElbow : C::RightElbow),
                                  frame.at(left ? C::LeftWrist : C::RightWrist),
                                  frame.at(left ? C::LeftHandTip : C::RightHandTip)};
  const auto orient = [](const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    return (b - a).cross(c - a).dot(d - a);
  };
  const auto sign = [](double x) { return (x > 0) - (x < 0); };
  int crossings = 0;
  const size_t n = loop.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec3 a = centre;
    const Vec3 b = mesh.V.row(loop[i]).transpose();
    const Vec3 c = mesh.V.row(loop[(i + 1) % n]).transpose();
    for (size_t s = 0; s + 1 < chain.size(); ++s) {
      const Vec3& p = chain[s];
      const Vec3& q = chain[s + 1];
      const int sp = sign(orient(a, b, c, p));
      const int sq = sign(orient(a, b, c, q));
      if (sp == 0 || sp == sq) continue;  // both ends on one side of the triangle's plane
      const int e0 = sign(orient(p, q, a, b));
      const int e1 = sign(orient(p, q, b, c));
      const int e2 = sign(orient(p, q, c, a));
      if (e0 == e1 && e1 == e2 && e0 != 0) crossings += sq;  // through the inside
    }
  }
  return crossings;
}

// The cuffs the scan joined to a loop that is not itself on an arm (Opening::joinedCuffs): each
// maximal stretch of the loop whose vertices lie on one arm past the armhole, kept when it winds
// at least half way round the arm. A hem that merely passes beside a hanging forearm runs along
// its side (a small angle); a cuff fused to it goes round the wrist before returning.
std::vector<Opening::JoinedCuff> joinedCuffs(const TriMesh& mesh, const std::vector<int>& loop,
                                             const BodyFrame& frame) {
  const int n = static_cast<int>(loop.size());
  std::vector<Limb> on(static_cast<size_t>(n), Limb::Torso);
  std::vector<double> t(static_cast<size_t>(n), 0.0);
  for (int i = 0; i < n; ++i) {
    const LimbPlace place = frame.nearestLimb(mesh.V.row(loop[i]).transpose());
    if (isArm(place.limb) && place.t > kCuffT) on[i] = place.limb;
    t[i] = place.t;
  }
  int start = -1;  // a vertex off every arm's cuff part: runs are cut there
  for (int i = 0; i < n && start < 0; ++i)
    if (!isArm(on[i])) start = i;
  std::vector<Opening::JoinedCuff> out;
  if (start < 0) return out;
  int k = 1;
  while (k <= n) {  // position `start` itself is off the arms: every run ends by k = n
    if (!isArm(on[(start + k) % n])) {
      ++k;
      continue;
    }
    Opening::JoinedCuff c;
    c.limb = on[(start + k) % n];
    double tSum = 0;
    for (; k <= n && on[(start + k) % n] == c.limb; ++k) {
      c.vertices.push_back(loop[(start + k) % n]);
      tSum += t[(start + k) % n];
    }
    c.t = tSum / static_cast<double>(c.vertices.size());
    if (c.vertices.size() >= 3 &&
        std::abs(windingAboutArm(mesh, c.vertices, frame, c.limb)) >= M_PI)
      out.push_back(std::move(c));
  }
  return out;
}

}  // namespace

bool hasCuff(const Opening& o, Limb arm) {
  if (o.limb == arm && o.t > kCuffT) return true;
  for (const Opening::JoinedCuff& c : o.joinedCuffs)
    if (c.limb == arm) return true;
  return false;
}

std::vector<Opening> classifyOpenings(const TriMesh& garment, const MeshTopology& topology,
                                      GarmentKind kind, const BodyFrame& frame) {
  using C = Canonical;
  const double shoulderH =
      0.5 * (frame.height(frame.at(C::LeftShoulder)) + frame.height(frame.at(C::RightShoulder)));
  const double hipH =
      0.5 * (frame.height(frame.at(C::LeftHip)) + frame.height(frame.at(C::RightHip)));
  const double hipHalf =
      0.5 * std::abs(frame.lateral(frame.at(C::LeftHip)) - frame.lateral(frame.at(C::RightHip)));
  std::vector<Opening> out;
  for (const std::vector<int>& loop : topology.boundaryLoops()) {
    Opening o;
    o.vertices = loop;
    Vec3 sum = Vec3::Zero();
    for (size_t i = 0; i < loop.size(); ++i) {
      const Vec3 a = garment.V.row(loop[i]).transpose();
      const Vec3 b = garment.V.row(loop[(i + 1) % loop.size()]).transpose();
      const double len = (b - a).norm();
      sum += 0.5 * len * (a + b);
      o.length += len;
    }
    o.centroid = o.length > 0 ? Vec3(sum / o.length) : Vec3(garment.V.row(loop[0]).transpose());
    const LimbPlace place = frame.nearestLimb(o.centroid);
    o.limb = place.limb;
    o.t = place.t;
    const double h = frame.height(o.centroid);
    if (isArm(place.limb)) {
      o.name = fmt::format("{}_{}", sideOf(place.limb), place.t > kCuffT ? "cuff" : "armhole");
      o.armCrossings = armChainCrossings(garment, loop, o.centroid, frame, place.limb);
    } else if (place.limb == Limb::Neck || (place.limb == Limb::Torso && h > 0.5 * shoulderH)) {
      o.name = "neckline";
    } else if (isLeg(place.limb) && std::abs(frame.lateral(o.centroid)) > 0.5 * hipHalf &&
               h < hipH - 0.05) {
      o.name = fmt::format("{}_leg_opening", sideOf(place.limb));
    } else if (kind == GarmentKind::Lower && h > hipH - 0.05) {
      o.name = "waistband";
    } else {
      o.name = "hem";  // around the trunk, or around both legs (a skirt's hem)
    }
    if (!isArm(place.limb) && kind != GarmentKind::Lower)
      o.joinedCuffs = joinedCuffs(garment, loop, frame);
    out.push_back(std::move(o));
  }
  return out;
}

namespace {

ProjectionOptions projectionOptions(const SeamOptions& options, const TriMesh& body) {
  ProjectionOptions popt = options.projection;
  const BoundingBox bb = boundingBox(body.V);
  popt.bodyLength = std::max(bb.extent().maxCoeff(), 1e-3);
  return popt;
}

// The seams of estimateSeams on `garment` itself (the garment or its decimated copy), each
// estimated when first asked for. The seam optimiser is built once, with the mesh's other state.
class SeamsOnMesh {
 public:
  SeamsOnMesh(const TriMesh& garment, GarmentKind kind, const TriMesh& body,
              const FeatureSet& features, std::vector<Opening> openings,
              const SeamOptions& options, const Eigen::MatrixXd& bodyLimbWeight,
              std::vector<ArmholeHint> armholeHints)
      : garment(garment),
        kind(kind),
        body(body),
        features(features),
        openings(std::move(openings)),
        options(options),
        bodyLimbWeight(bodyLimbWeight),
        armholeHints(std::move(armholeHints)),
        popt(projectionOptions(options, body)),
        spacing(std::max(options.splineSpacing, meanEdgeLength(garment))),
        noDisplacement(Eigen::VectorXd::Zero(garment.numVertices())),
        contactDistance(options.contactDistance * popt.bodyLength),
        clothDistance(options.contactClothDistance * popt.bodyLength) {
    BoundaryOptions bopt = options.boundary;
    bopt.maxIterations = std::max(1, options.regularisationSteps);
    bopt.dropStrayCurves = false;
    // The seam optimiser is built beside the projector: nearly every garment keeps a seam. An
    // error building it is raised where the first kept seam needs it, as when it was built
    // there: an InputError is that seam's reason for having no line, any other error goes up.
    tbb::parallel_invoke(
        [&] {
          projector.emplace(body, garment, popt);
          query.emplace(garment);
          topo.emplace(garment.F, garment.numVertices());
        },
        [&] {
          try {
            optimizer.emplace(garment, bopt);
          } catch (const Error&) {
            optimizerError = std::current_exception();
          }
        });
  }

  // The seam of kind_; nullopt when the garment's kind has none of that kind.
  std::optional<SeamLine> estimate(SeamKind kind_);

 private:
  const TriMesh& garment;
  const GarmentKind kind;
  const TriMesh& body;
  const FeatureSet& features;
  const std::vector<Opening> openings;
  const SeamOptions options;
  const Eigen::MatrixXd& bodyLimbWeight;
  const std::vector<ArmholeHint> armholeHints;
  const ProjectionOptions popt;
  const double spacing;
  const Eigen::VectorXd noDisplacement;
  const double contactDistance, clothDistance;
  std::optional<FeatureProjector> projector;
  std::optional<MeshQuery> query;
  std::optional<MeshTopology> topo;
  std::optional<BoundaryOptimizer> optimizer;
  std::exception_ptr optimizerError;  // why it could not be built
};

std::optional<SeamLine> SeamsOnMesh::estimate(SeamKind kind_) {
  const std::vector<std::string> names = featureNames(kind_, kind);
  if (names.empty()) return std::nullopt;
  const auto t0 = std::chrono::steady_clock::now();
  SeamLine seam;
  seam.kind = kind_;
  seam.name = seamName(kind_);
  seam.features = names;
  std::vector<std::vector<SurfacePoint>> zeros;
  std::vector<ValueConstraint> signs;
  std::vector<Vec3> prior;
  std::array<bool, 2> sleeved{false, false};  // left, right arm: its armhole spline kept
  for (const std::string& fname : names) {
    const CurveFeatures* f = features.seam(fname);
    if (!f)
      throw InputError(
          fmt::format("pattern: the feature set has no seam '{}' (a features.json "
                      "from an older version? rerun `fit`)",
                      fname));
    for (const FeatureSpline& s : f->splines) {
      std::vector<ProjectedPoint> p = projector->project(s.anchors);
      // Contacts are taken back only for a spline Appendix B would remove (fewer than
      // minAnchors left): a contact anchor is placed less surely than one the scan shows
      // plainly, and on a spline that keeps enough anchors it only moves the seam (arms_down:
      // the side seam's end left the sleeve's underarm, whose cut then split the armhole).
      int plain = 0;
      for (const ProjectedPoint& q : p) plain += q.ok();
      const bool needsContacts = plain < options.minAnchors;
      for (size_t i = 0; i < p.size(); ++i) {
        const bool contact = needsContacts && isContact(p[i], s.anchors[i].position(body), fname,
                                                        contactDistance, clothDistance);
        if (std::getenv("S2P_DEBUG_SEAMS"))
          fmt::print(stderr, "  {} anchor {}: {}{} hit {:.1f} mm, |p−q| {:.1f} mm\n", s.name, i,
                     toString(p[i].status), contact ? " (contact, kept)" : "",
                     1000 * p[i].hitDistance,
                     1000 * (p[i].p - s.anchors[i].position(body)).norm());
        if (contact) {
          p[i].status = ProjectionStatus::Ok;
          ++seam.contactAnchors;
        }
      }
      std::vector<ProjectedPoint> kept;
      for (const ProjectedPoint& q : p)
        if (q.ok()) kept.push_back(q);
      seam.anchors += static_cast<int>(p.size());
      seam.droppedAnchors += static_cast<int>(p.size() - kept.size());
      std::string why;
      // An open spline is broken where an ill-projected anchor between surviving ones lies far
      // from the garment: across the middle of the seam the garment leaves the body (a skirt
      // over the crotch, where trousers' seam runs between the legs). An anchor dropped close
      // to the garment (the armpit, where its rays meet the torso) does not break it.
      int first = -1, last = -1;
      for (int i = 0; i < static_cast<int>(p.size()); ++i)
        if (p[i].ok()) {
          if (first < 0) first = i;
          last = i;
        }
      int gap = 0;
      for (int i = first + 1; i < last; ++i)
        if (!p[i].ok() && (p[i].p - s.anchors[i].position(body)).norm() >
                              options.brokenSeamDistance * popt.bodyLength)
          ++gap;
      if (!s.closed && gap > 0)
        why = fmt::format(
            "{} anchor(s) between surviving ones lie more than {:.0f} mm from the "
            "garment: it leaves the body across the middle of the seam",
            gap, 1000 * options.brokenSeamDistance * popt.bodyLength);
      else if (static_cast<int>(kept.size()) < options.minAnchors)
        why = fmt::format("{} of {} anchors survived the ill-projection tests, {} needed",
                          kept.size(), p.size(), options.minAnchors);
      // A sleeve exists only where the garment has an opening on that arm beyond the
      // armhole (a cuff): the arm-side value of §6.1.2 has nowhere to go on a sleeveless top.
      std::optional<Limb> arm;
      if (kind_ == SeamKind::Armhole) {
        arm = s.name.rfind("left", 0) == 0 ? Limb::LeftArm : Limb::RightArm;
        bool cuff = false;
        for (const Opening& o : openings) cuff |= hasCuff(o, *arm);
        if (!cuff && why.empty()) why = "the garment has no opening on that arm (no sleeve)";
      }
      if (!why.empty()) {
        seam.splinesRemoved.push_back(fmt::format("{}: {}", s.name, why));
        continue;
      }
      seam.splinesKept.push_back(s.name);
      if (kind_ == SeamKind::Armhole) {
        sleeved[*arm == Limb::LeftArm ? 0 : 1] = true;
        // §6.1.2: zero on the projected anchors only, not on a spline through them.
        std::vector<SurfacePoint> pts;
        for (const ProjectedPoint& q : kept) {
          pts.push_back(q.point);
          prior.push_back(q.p);
        }
        zeros.push_back(std::move(pts));
        for (const Opening& o : openings) {
          if (o.limb == *arm && o.t > kCuffT)
            addLoopConstraints(*topo, garment, o.vertices, options.boundaryConstraintSpacing, -1.0,
                               signs);
          for (const Opening::JoinedCuff& c : o.joinedCuffs)
            if (c.limb == *arm)
              addLoopConstraints(*topo, garment, c.vertices, options.boundaryConstraintSpacing,
                                 -1.0, signs);
        }
      } else {
        Eigen::MatrixX3d A(static_cast<int>(kept.size()), 3);
        for (size_t i = 0; i < kept.size(); ++i)
          A.row(static_cast<int>(i)) = kept[i].p.transpose();
        std::vector<SurfacePoint> pts = surfaceSpline(*query, A, s.closed, spacing);
        for (const SurfacePoint& q : pts) prior.push_back(q.position(garment));
        zeros.push_back(std::move(pts));
      }
    }
    // Sign points, with paired removal (§6.1.2).
    std::vector<ProjectedPoint> q;
    for (const SignPoint& s : f->signs) q.push_back(projector->project(s.point));
    for (size_t i = 0; i < f->signs.size(); ++i) {
      const SignPoint& s = f->signs[i];
      ++seam.signs;
      const bool partnerOk = s.pair < 0 || q[s.pair].ok();
      if (!q[i].ok() || !partnerOk) {
        ++seam.droppedSigns;
        if (q[i].ok()) ++seam.pairedDrops;
        continue;
      }
      signs.push_back({q[i].point, s.value});
    }
  }
  if (kind_ == SeamKind::Armhole && !zeros.empty())
    for (const Opening& o : openings)
      if (o.name == "neckline" || o.name == "hem") {
        // A cuff joined to the hem is the sleeve's (−1 above), not the trunk's.
        std::vector<int> trunkPart;
        for (int v : o.vertices) {
          bool cuff = false;
          for (const Opening::JoinedCuff& c : o.joinedCuffs)
            cuff |= std::find(c.vertices.begin(), c.vertices.end(), v) != c.vertices.end();
          if (!cuff) trunkPart.push_back(v);
        }
        addLoopConstraints(*topo, garment, trunkPart, options.boundaryConstraintSpacing, +1.0,
                           signs);
      }
  if (kind_ == SeamKind::Armhole && !zeros.empty())
    for (const ArmholeHint& h : armholeHints) {
      const ClosestHit c = query->closestPoint(h.position);
      signs.push_back({SurfacePoint{c.face, c.bary}, h.value});
    }
  if (kind_ == SeamKind::Armhole && !zeros.empty() && bodyLimbWeight.rows() > 0 &&
      options.partMaxDistance > 0)
    addBodyPartConstraints(garment, *topo, body, bodyLimbWeight, sleeved, prior, popt.bodyLength,
                           options, seam, signs);
  seam.prior.resize(static_cast<int>(prior.size()), 3);
  for (size_t i = 0; i < prior.size(); ++i)
    seam.prior.row(static_cast<int>(i)) = prior[i].transpose();

  int pos = 0, neg = 0;
  for (const ValueConstraint& c : signs) (c.value > 0 ? pos : neg)++;
  if (zeros.empty()) {
    seam.removedWhy = fmt::format("every spline removed ({} of {} anchors ill-projected)",
                                  seam.droppedAnchors, seam.anchors);
  } else if (pos == 0 || neg == 0) {
    seam.removedWhy = fmt::format(
        "sign points of one sign only survived ({} positive, {} "
        "negative)",
        pos, neg);
  } else {
    try {
      if (!optimizer) std::rethrow_exception(optimizerError);
      const Eigen::VectorXd phi0 = optimizer->initialImplicit(zeros, signs);
      if (std::getenv("S2P_DEBUG_SEAMS")) {
        const Isoline iso0 = extractIsoline(garment, *topo, phi0);
        fmt::print(stderr, "seam {}: {} trunk and {} sleeve body-part points\n", seam.name,
                   seam.trunkPoints, seam.sleevePoints);
        fmt::print(stderr,
                   "seam {}: {} zero sets, {} signs (+{} −{}), phi0 [{:.3f}, {:.3f}], {} curves, "
                   "length {:.3f}\n",
                   seam.name, zeros.size(), signs.size(), pos, neg, phi0.minCoeff(),
                   phi0.maxCoeff(), iso0.curves.size(), iso0.length());
        std::vector<ValueConstraint> all = signs;
        for (const auto& z : zeros)
          for (const auto& q : z) all.push_back({q, 0.0});
        const Eigen::VectorXd b = biharmonicFunction(garment, all);
        const Isoline ib = extractIsoline(garment, *topo, b);
        fmt::print(stderr, "  biharmonic [{:.3f}, {:.3f}], {} curves, length {:.3f};",
                   b.minCoeff(), b.maxCoeff(), ib.curves.size(), ib.length());
        for (const auto& c : signs)
          fmt::print(stderr, " {:+.0f}:{:.2f}", c.value, c.point.interpolate(garment.F, b));
        fmt::print(stderr, "\n");
      }
      BoundaryResult r = optimizer->iterate(phi0, signs, noDisplacement);
      if (r.vanished) {
        seam.removedWhy = "its zero set vanished under the length regularisation";
      } else {
        seam.phi = std::move(r.phi);
        seam.islandsRemoved = removeIslands(garment, seam.phi, options.minIslandArea, signs);
        seam.line = extractIsoline(garment, *topo, seam.phi);
        seam.kept = !seam.line.curves.empty();
        if (!seam.kept)
          seam.removedWhy = "its implicit function has no zero isoline on the garment";
      }
    } catch (const InputError& e) {
      seam.removedWhy = std::string("no seam line: ") + e.what();
    }
  }
  if (!seam.kept) seam.phi.resize(0);
  seam.seconds = secondsSince(t0);
  return seam;
}

// The openings of a garment on its decimated copy: the loops' vertices the copy kept.
std::vector<Opening> openingsOnCopy(const std::vector<Opening>& openings, const CoarseMesh& copy,
                                    int fineVertices) {
  std::vector<int> coarseOf(static_cast<size_t>(fineVertices), -1);
  for (int v = 0; v < copy.fineVertex.size(); ++v) coarseOf[copy.fineVertex[v]] = v;
  std::vector<Opening> out = openings;
  for (Opening& o : out) {
    std::vector<int> kept;
    for (int v : o.vertices)
      if (coarseOf[v] >= 0) kept.push_back(coarseOf[v]);
    o.vertices = std::move(kept);
  }
  return out;
}

}  // namespace

struct SeamEstimator::Impl {
  const TriMesh& garment;
  std::optional<CoarseMesh> copy;
  std::unique_ptr<SeamsOnMesh> onMesh;
  std::unique_ptr<CoarseToFine> carry;      // copy → garment, built for the first seam kept
  std::unique_ptr<MeshTopology> fineTopo;   // of the garment, with it
  std::map<SeamKind, std::optional<SeamLine>> done;
};

SeamEstimator::SeamEstimator(const TriMesh& garment, GarmentKind kind, const TriMesh& body,
                             const FeatureSet& features, const std::vector<Opening>& openings,
                             const SeamOptions& options, const Eigen::MatrixXd& bodyLimbWeight,
                             const std::vector<ArmholeHint>& armholeHints) {
  validateMesh(garment, "garment");
  if (bodyLimbWeight.rows() > 0 && (bodyLimbWeight.rows() != body.numVertices() ||
                                    bodyLimbWeight.cols() != 6 || !bodyLimbWeight.allFinite()))
    throw InputError(
        fmt::format("pattern: the body's limb weights are {}×{}, {}×6 finite values "
                    "expected (one row per body vertex: limbWeights of its model)",
                    bodyLimbWeight.rows(), bodyLimbWeight.cols(), body.numVertices()));
  impl_ = std::make_unique<Impl>(Impl{garment, std::nullopt, nullptr, nullptr, nullptr, {}});
  if (options.coarseVertices > 0) impl_->copy = decimatedCopy(garment, options.coarseVertices);
  if (impl_->copy)
    impl_->onMesh = std::make_unique<SeamsOnMesh>(
        impl_->copy->mesh, kind, body, features,
        openingsOnCopy(openings, *impl_->copy, garment.numVertices()), options, bodyLimbWeight,
        armholeHints);
  else
    impl_->onMesh = std::make_unique<SeamsOnMesh>(garment, kind, body, features, openings,
                                                  options, bodyLimbWeight, armholeHints);
}

SeamEstimator::~SeamEstimator() = default;

const SeamLine* SeamEstimator::seam(SeamKind kind) {
  Impl& m = *impl_;
  auto it = m.done.find(kind);
  if (it == m.done.end()) {
    std::optional<SeamLine> seam = m.onMesh->estimate(kind);
    if (seam && seam->kept && m.copy) {
      if (!m.carry) {
        m.carry = std::make_unique<CoarseToFine>(m.copy->mesh, m.garment);
        m.fineTopo = std::make_unique<MeshTopology>(m.garment.F, m.garment.numVertices());
      }
      seam->phi = m.carry->carry(seam->phi);
      seam->line = extractIsoline(m.garment, *m.fineTopo, seam->phi);
      seam->kept = !seam->line.curves.empty();
      if (!seam->kept) {
        seam->removedWhy = "its zero isoline vanished when carried from the decimated copy";
        seam->phi.resize(0);
      }
    }
    it = m.done.emplace(kind, std::move(seam)).first;
  }
  return it->second ? &*it->second : nullptr;
}

std::vector<SeamLine> SeamEstimator::all() {
  std::vector<SeamLine> out;
  for (SeamKind kind : {SeamKind::FrontBack, SeamKind::Armhole, SeamKind::LeftRight})
    if (const SeamLine* s = seam(kind)) out.push_back(*s);
  return out;
}

std::vector<SeamLine> estimateSeams(const TriMesh& garment, GarmentKind kind, const TriMesh& body,
                                    const FeatureSet& features,
                                    const std::vector<Opening>& openings,
                                    const SeamOptions& options,
                                    const Eigen::MatrixXd& bodyLimbWeight,
                                    const std::vector<ArmholeHint>& armholeHints) {
  return SeamEstimator(garment, kind, body, features, openings, options, bodyLimbWeight,
                       armholeHints)
      .all();
}

std::vector<SeamFold> armholeFolds(const TriMesh& garment, const SeamLine& seam,
                                   const SeamOptions& options) {
  std::vector<SeamFold> out;
  if (!seam.kept || seam.phi.size() != garment.numVertices()) return out;
  const Eigen::MatrixX3d n = faceNormals(garment);
  const Eigen::VectorXd area = faceAreas(garment);
  Eigen::MatrixX3d centroid(garment.numFaces(), 3);
  for (int f = 0; f < garment.numFaces(); ++f)
    centroid.row(f) = (garment.V.row(garment.F(f, 0)) + garment.V.row(garment.F(f, 1)) +
                       garment.V.row(garment.F(f, 2))) /
                      3.0;
  // Outward: a garment wraps the body, so most of its area faces away from its centre.
  const Eigen::RowVector3d centre = garment.V.colwise().mean();
  double facing = 0;
  for (int f = 0; f < garment.numFaces(); ++f)
    facing += area[f] * n.row(f).dot(centroid.row(f) - centre);
  const double outward = facing >= 0 ? 1.0 : -1.0;
  const RowCloud cloud{&centroid};
  const RowTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  const double r2 = options.creaseRadius * options.creaseRadius;
  const double minCos = std::cos(options.creaseAngle * M_PI / 180);
  std::vector<std::pair<std::uint32_t, double>> hits;
  forEachSegment(seam.line, [&](const Vec3& a, const Vec3& b) {
    const Vec3 mid = 0.5 * (a + b);
    hits.clear();
    tree.radiusSearch(mid.data(), r2, hits, nanoflann::SearchParams(32, 0, false));
    // The cloth on each side of the seam within the radius: area-weighted normal and centre.
    Vec3 nSide[2] = {Vec3::Zero(), Vec3::Zero()}, cSide[2] = {Vec3::Zero(), Vec3::Zero()};
    double wSide[2] = {0, 0};
    for (const auto& [f, d2] : hits) {
      double phi = 0;
      for (int k = 0; k < 3; ++k) phi += seam.phi[garment.F(static_cast<int>(f), k)];
      if (phi == 0) continue;
      const int s = phi > 0 ? 1 : 0;
      const double w = area[static_cast<int>(f)];
      nSide[s] += w * outward * n.row(static_cast<int>(f)).transpose();
      cSide[s] += w * centroid.row(static_cast<int>(f)).transpose();
      wSide[s] += w;
    }
    if (wSide[0] <= 0 || wSide[1] <= 0 || nSide[0].norm() == 0 || nSide[1].norm() == 0) return;
    const Vec3 n0 = nSide[0].normalized(), n1 = nSide[1].normalized();
    const Vec3 c0 = cSide[0] / wSide[0], c1 = cSide[1] / wSide[1];
    // Concave: each side's cloth lies on the outer side of the other's tangent plane.
    if (n0.dot(n1) <= minCos && (c1 - c0).dot(n0) > 0 && (c0 - c1).dot(n1) > 0)
      out.push_back({a, b});
  });
  return out;
}

}  // namespace s2p
