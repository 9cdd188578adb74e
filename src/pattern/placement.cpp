#include "pattern/placement.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <set>

#include "body/posing.h"
#include "core/error.h"
#include "core/mesh_query.h"

namespace s2p {

namespace {

bool startsWith(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// §6.3's binding: sleeves to their shoulders; the trunk to the chest; a lower garment's
// left/right panels (trousers, shorts) to their hip, its other panels (a skirt) to the pelvis;
// a one-piece garment's panels by where they lie, above or below the middle of the trunk.
Canonical bindingJoint(const Panel& panel, GarmentKind kind, const Eigen::MatrixX3d& canonical) {
  const bool left = startsWith(panel.name, "left_"), right = startsWith(panel.name, "right_");
  if (panel.name.find("sleeve") != std::string::npos)
    return left ? Canonical::LeftShoulder : Canonical::RightShoulder;
  if (kind == GarmentKind::Upper) return Canonical::Chest;
  if (kind == GarmentKind::OnePiece) {
    const Eigen::Vector3d pelvis = canonical.row(static_cast<int>(Canonical::Pelvis)).transpose();
    const Eigen::Vector3d chest = canonical.row(static_cast<int>(Canonical::Chest)).transpose();
    const Eigen::Vector3d up = (chest - pelvis).normalized();
    const Eigen::Vector3d centroid = panel.mesh.V.colwise().mean().transpose();
    if ((centroid - pelvis).dot(up) > 0.5 * (chest - pelvis).norm()) return Canonical::Chest;
  }
  if (left) return Canonical::LeftHip;
  if (right) return Canonical::RightHip;
  return Canonical::Pelvis;
}

// The joints a panel bound to `c` follows down its limb: a sleeve its shoulder, elbow and wrist, a
// trouser leg its hip, knee and ankle; any other panel only its own joint.
std::vector<Canonical> limbChain(Canonical c) {
  using C = Canonical;
  switch (c) {
    case C::LeftShoulder: return {C::LeftShoulder, C::LeftElbow, C::LeftWrist};
    case C::RightShoulder: return {C::RightShoulder, C::RightElbow, C::RightWrist};
    case C::LeftHip: return {C::LeftHip, C::LeftKnee, C::LeftAnkle};
    case C::RightHip: return {C::RightHip, C::RightKnee, C::RightAnkle};
    default: return {c};
  }
}

int jointIndex(const BodyModel& model, Canonical c) {
  const int j = model.canonical[static_cast<int>(c)].joint;
  if (j < 0 || j >= model.numJoints())
    throw InputError(fmt::format("placement: the body model's canonical '{}' is not a skeleton "
                                 "joint, so no panel can be bound to it", toString(c)));
  return j;
}

// Signed distances of a panel's vertices to the closed rest body (negative inside), while the
// panel moves out along its normal. Where the closest point lies inside a face, the side of that
// face's plane is the sign (exact on a closed surface); a closest point on an edge or a vertex
// takes a winding number. A point at distance d cannot cross the surface by moving less than d,
// so after a move by δ only the points that were within δ of it are tested again. (A 50k scan's
// eight panels, 46k vertices: 1.6 s with a winding number for every vertex at every step.)
class Clearance {
 public:
  Clearance(const MeshQuery& body, const Eigen::MatrixX3d& faceNormals)
      : body_(body), normals_(faceNormals) {}

  // Least signed distance of P, which moved by `moved` (m) since the last call (ignored on the
  // first call, when every sign is decided).
  double least(const Eigen::MatrixX3d& P, double moved) {
    const std::vector<ClosestHit> hits = body_.closestPoints(P);
    const int n = static_cast<int>(P.rows());
    const bool first = inside_.size() != static_cast<size_t>(n);
    if (first) inside_.assign(n, 0);
    std::vector<int> winding;  // points whose sign needs the winding number
    for (int i = 0; i < n; ++i) {
      if (!first && distance_[i] > moved) continue;  // cannot have crossed the surface
      const ClosestHit& h = hits[i];
      constexpr double kInsideFace = 1e-6;  // barycentric margin: the closest point is not on an edge
      if (h.bary.minCoeff() > kInsideFace)
        inside_[i] = (P.row(i).transpose() - h.point).dot(normals_.row(h.face).transpose()) < 0;
      else
        winding.push_back(i);
    }
    if (!winding.empty()) {
      Eigen::MatrixX3d Q(winding.size(), 3);
      for (size_t k = 0; k < winding.size(); ++k) Q.row(k) = P.row(winding[k]);
      const Eigen::VectorXd w = body_.windingNumbers(Q);
      for (size_t k = 0; k < winding.size(); ++k) inside_[winding[k]] = w(k) > 0.5;
    }
    distance_.resize(n);
    double least = std::numeric_limits<double>::infinity();
    for (int i = 0; i < n; ++i) {
      distance_[i] = hits[i].distance;
      least = std::min(least, inside_[i] ? -hits[i].distance : hits[i].distance);
    }
    return least;
  }

 private:
  const MeshQuery& body_;
  const Eigen::MatrixX3d& normals_;
  std::vector<char> inside_;
  std::vector<double> distance_;  // unsigned, at the last call
};

// The outward normal of the part: its area vector when the part is open enough to have one;
// a sleeve or trouser-leg panel wraps nearly all around its limb and its area vector is short,
// so then the direction from the part's centroid to the points of the flat panel's middle
// column (the middle of the panel lies opposite its cut), across the grain.
Eigen::Vector3d partNormal(const Eigen::MatrixX3d& Q, const Eigen::MatrixX2d& P2,
                           const Eigen::MatrixX3i& F, const Eigen::Vector3d& grain) {
  Eigen::Vector3d areaVector = Eigen::Vector3d::Zero();
  double area = 0;
  for (int f = 0; f < F.rows(); ++f) {
    const Eigen::Vector3d c = (Q.row(F(f, 1)) - Q.row(F(f, 0)))
                                  .transpose()
                                  .cross((Q.row(F(f, 2)) - Q.row(F(f, 0))).transpose());
    areaVector += 0.5 * c;
    area += 0.5 * c.norm();
  }
  if (areaVector.norm() >= 0.5 * area && areaVector.norm() > 0) return areaVector.normalized();
  const double xMin = P2.col(0).minCoeff(), xMax = P2.col(0).maxCoeff();
  const double xMid = 0.5 * (xMin + xMax), band = 0.1 * (xMax - xMin);
  Eigen::Vector3d middle = Eigen::Vector3d::Zero();
  int n = 0;
  for (int v = 0; v < P2.rows(); ++v)
    if (std::abs(P2(v, 0) - xMid) <= band) {
      middle += Q.row(v).transpose();
      ++n;
    }
  Eigen::Vector3d d = middle / std::max(n, 1) - Q.colwise().mean().transpose();
  d -= d.dot(grain) * grain;
  if (d.norm() > 1e-9) return d.normalized();
  return areaVector.norm() > 0 ? areaVector.normalized() : Eigen::Vector3d::UnitZ();
}

}  // namespace

Eigen::MatrixX3d moveWithNearestBone(const std::vector<Eigen::Vector3d>& joints,
                                     const std::vector<Eigen::Affine3d>& transforms,
                                     const Eigen::MatrixX3d& P) {
  if (joints.empty() || joints.size() != transforms.size())
    throw InputError(fmt::format("placement: {} joints for {} bone transforms", joints.size(),
                                 transforms.size()));
  const auto segmentDistance = [](const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b) {
    const Eigen::Vector3d ab = b - a;
    const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-12), 0.0, 1.0);
    return (p - (a + t * ab)).norm();
  };
  Eigen::MatrixX3d out(P.rows(), 3);
  for (int v = 0; v < P.rows(); ++v) {
    const Eigen::Vector3d x = P.row(v).transpose();
    size_t best = 0;
    double bestDistance = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < joints.size(); ++k) {
      const double d =
          segmentDistance(x, joints[k], k + 1 < joints.size() ? joints[k + 1] : joints[k]);
      if (d < bestDistance) bestDistance = d, best = k;
    }
    out.row(v) = (transforms[best] * x).transpose();
  }
  return out;
}

Placement placePanels(const PanelsResult& panels, const FlatPatternResult& flat,
                      const PlacementInput& input, const PlacementOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!input.model) throw InputError("placement: no body model given");
  const BodyModel& model = *input.model;
  if (flat.panels.size() != panels.panels.size())
    throw InputError(fmt::format("placement: {} flat panels for {} panels",
                                 flat.panels.size(), panels.panels.size()));
  const PosedBody fitted = poseBody(model, input.fitted);
  const Eigen::VectorXd& shape = input.fitted.shape;
  // The person's shape at rest: the full fit unposed (its detail kept), or the shaped model.
  const Eigen::MatrixX3d restShape =
      input.full.numVertices() == model.numVertices()
          ? unposeSkinned(fitted, model.weights, input.full.V)
          : shapedTemplate(model, shape);
  Placement out;
  const DrapePoseChoice choice = drapePoseFor(model, shape, fitted);
  out.drapePose = choice.pose;
  out.pose = fmt::format(
      "drape pose: arms {:.0f}° (left) and {:.0f}° (right) below horizontal ({:.0f}° unless the "
      "scan raised them higher), legs 8° apart, knees and elbows straight",
      choice.downLeft * 180 / std::numbers::pi, choice.downRight * 180 / std::numbers::pi,
      kDrapeArmDown * 180 / std::numbers::pi);
  const PosedBody drape = poseBody(model, {shape, out.drapePose});

  const Eigen::Vector3d pelvis = drape.canonical.row(static_cast<int>(Canonical::Pelvis)).transpose();
  Eigen::MatrixX3d bodyV = poseSkinned(drape, model.weights, restShape);
  // GarmentCode's frame: the feet on y = 0, the pelvis above the origin.
  const Eigen::Vector3d shift(-pelvis.x(), -bodyV.col(1).minCoeff(), -pelvis.z());
  bodyV.rowwise() += shift.transpose();
  out.restBody = TriMesh(bodyV, model.rest.F);
  Eigen::MatrixX3d underV = drape.mesh.V;
  underV.rowwise() += shift.transpose();
  out.underBody = TriMesh(underV, drape.mesh.F);
  out.canonical = drape.canonical.rowwise() + shift.transpose();
  const MeshQuery bodyQuery(out.restBody);
  const Eigen::MatrixX3d bodyNormals = faceNormals(out.restBody);

  // Garment frame → rest frame for a point bound to joint j.
  auto jointTransform = [&](Canonical c) {
    const int j = jointIndex(model, c);
    const Eigen::Affine3d toRest = Eigen::Translation3d(shift) * drape.skinning[j];
    return Eigen::Affine3d(toRest * (input.toGarments * fitted.skinning[j]).inverse());
  };
  const Eigen::MatrixX3d garmentCanonical = [&] {
    Eigen::MatrixX3d C = fitted.canonical;
    for (int i = 0; i < C.rows(); ++i) C.row(i) = (input.toGarments * C.row(i).transpose()).transpose();
    return C;
  }();

  out.panels.resize(panels.panels.size());
  std::vector<std::string> warnings(panels.panels.size());  // per panel: they run side by side
  tbb::parallel_for(size_t{0}, panels.panels.size(), [&](size_t p) {
    const Panel& panel = panels.panels[p];
    const FlatPanel& fp = flat.panels[p];
    PlacedPanel& pp = out.panels[p];
    if (!fp.error.empty() || fp.remeshed.V.rows() == 0) return;
    const GarmentKind kind = panels.garments[panel.garmentIndex].kind;
    pp.joint = bindingJoint(panel, kind, garmentCanonical);
    const Eigen::Affine3d M = jointTransform(pp.joint);
    const int n = static_cast<int>(fp.position.rows());
    // The part unposed: each point with the bone of its limb it lies nearest (the panel's own
    // joint's bone from it to the next joint, then the next), so that a sleeve scanned with its
    // elbow bent, or a trouser leg in a stride, is straightened with the limb it covers; bound
    // to the shoulder alone, a bent sleeve's forearm half stays bent across the straight rest
    // arm and the plane and turn fitted to it lay the panel twisted round the arm (bent_arm: the
    // underarm seam 115 mm open after sewing). The panel itself stays rigid (§6.3).
    std::vector<Eigen::Vector3d> joints;
    std::vector<Eigen::Affine3d> bones;
    for (Canonical c : limbChain(pp.joint)) {
      joints.push_back(garmentCanonical.row(static_cast<int>(c)).transpose());
      bones.push_back(jointTransform(c));
    }
    pp.part = moveWithNearestBone(joints, bones, fp.position);

    // The plane: normal = the part's outward normal, "up" = the part's grain.
    const Eigen::MatrixX2d& P2 = fp.remeshed.V;
    const Eigen::Vector3d grain = (M.linear() * fp.grain).normalized();
    const Eigen::Vector3d normal = partNormal(pp.part, P2, fp.remeshed.F, grain);
    Eigen::Vector3d b2 = grain - grain.dot(normal) * normal;
    if (b2.norm() < 1e-6) b2 = normal.unitOrthogonal();
    b2.normalize();
    const Eigen::Vector3d b1 = b2.cross(normal);
    // In-plane turn: 2D Procrustes of the flat panel onto the part projected into the plane.
    const Eigen::Vector3d cQ = pp.part.colwise().mean().transpose();
    const Eigen::Vector2d cP = P2.colwise().mean().transpose();
    double dotSum = 0, crossSum = 0;
    for (int v = 0; v < n; ++v) {
      const Eigen::Vector2d a = P2.row(v).transpose() - cP;
      const Eigen::Vector3d d = pp.part.row(v).transpose() - cQ;
      const Eigen::Vector2d b(d.dot(b1), d.dot(b2));
      dotSum += a.dot(b);
      crossSum += a.x() * b.y() - a.y() * b.x();
    }
    const double angle = std::atan2(crossSum, dotSum);
    Eigen::Matrix3d frame;
    frame << b1, b2, normal;
    pp.R = frame * Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d t = cQ - pp.R * Eigen::Vector3d(cP.x(), cP.y(), 0.0);
    Eigen::MatrixX3d flat3(n, 3);
    for (int v = 0; v < n; ++v)
      flat3.row(v) = (pp.R * Eigen::Vector3d(P2(v, 0), P2(v, 1), 0.0) + t).transpose();
    // Out along the normal until every vertex clears the body. A signed distance changes by at
    // most d when a point moves by d, so a shortfall of δ needs at least δ more: the search
    // jumps by max(step, δ) and takes a handful of queries.
    double s = 0, moved = 0;
    Clearance clearance(bodyQuery, bodyNormals);
    while (true) {
      pp.V = flat3.rowwise() + (s * normal).transpose();
      pp.clearance = clearance.least(pp.V, moved);
      if (pp.clearance >= options.clearance || s > options.maxOffset) break;
      moved = std::max(options.step, options.clearance - pp.clearance);
      s += moved;
    }
    if (pp.clearance < options.clearance)
      warnings[p] = fmt::format(
          "panel '{}' of {}: {:.0f} cm out along its normal it still comes within {:.1f} cm "
          "of the rest body",
          panel.name, panel.garment, 100 * options.maxOffset, 100 * pp.clearance);
    pp.offset = s;
    pp.t = t + s * normal;
    pp.distanceToPart = (pp.V - pp.part).rowwise().norm().mean();
    pp.placed = true;
  });
  for (std::string& w : warnings)
    if (!w.empty()) out.warnings.push_back(std::move(w));
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

StitchSet makeStitches(const PanelsResult& panels, const FlatPatternResult& flat,
                       const Placement* placement) {
  StitchSet out;
  std::set<std::pair<int, int>> used;
  auto meanGap = [](const Eigen::MatrixX3d& A, const Eigen::MatrixX3d& B,
                    const std::vector<std::pair<int, int>>& pairs) {
    double sum = 0;
    for (const auto& [a, b] : pairs) sum += (A.row(a) - B.row(b)).norm();
    return pairs.empty() ? 0.0 : sum / static_cast<double>(pairs.size());
  };
  for (const SeamPair& s : flat.seams) {
    const Panel& pa = panels.panels[s.panelA];
    const Panel& pb = panels.panels[s.panelB];
    const FlatPanel& fa = flat.panels[s.panelA];
    const FlatPanel& fb = flat.panels[s.panelB];
    const std::string name = pa.edges[s.edgeA].name;
    if (!fa.error.empty() || !fb.error.empty()) {
      out.warnings.push_back(fmt::format("seam '{}' between {} {} and {} {} has no stitch: a "
                                         "panel of it was not flattened",
                                         name, pa.garment, pa.name, pb.garment, pb.name));
      continue;
    }
    if (!used.insert({s.panelA, s.edgeA}).second || !used.insert({s.panelB, s.edgeB}).second) {
      out.warnings.push_back(fmt::format("seam '{}' of {} {}: an edge already in a stitch",
                                         name, pa.garment, pa.name));
      continue;
    }
    const std::vector<int>& ea = fa.edges[s.edgeA].vertices;
    const std::vector<int>& eb = fb.edges[s.edgeB].vertices;
    if (ea.size() != eb.size() || ea.empty()) {
      out.warnings.push_back(fmt::format("seam '{}' of {} {}: its edges have {} and {} vertices "
                                         "after remeshing; no stitch",
                                         name, pa.garment, pa.name, ea.size(), eb.size()));
      continue;
    }
    Stitch st{s.panelA, s.edgeA, s.panelB, s.edgeB, name, s.lengthA, s.lengthB, {}, 0, 0};
    std::vector<std::pair<int, int>> straight;
    const size_t n = ea.size();
    for (size_t k = 0; k < n; ++k) {
      st.vertices.emplace_back(ea[k], eb[n - 1 - k]);
      straight.emplace_back(ea[k], eb[k]);
    }
    st.scanGap = meanGap(fa.position, fb.position, st.vertices);
    if (meanGap(fa.position, fb.position, straight) < st.scanGap)
      out.warnings.push_back(fmt::format(
          "seam '{}' of {} {}: its edges run the same way on the scan (a panel turned inside "
          "out?); stitched opposite as always",
          name, pa.garment, pa.name));
    if (placement && placement->panels[s.panelA].placed && placement->panels[s.panelB].placed)
      st.restGap = meanGap(placement->panels[s.panelA].V, placement->panels[s.panelB].V,
                           st.vertices);
    out.stitches.push_back(std::move(st));
  }
  return out;
}

}  // namespace s2p
