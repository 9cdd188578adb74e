#include "segment/segmentation.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <type_traits>

#include "core/coarse_mesh.h"
#include "core/colour.h"
#include "core/error.h"
#include "core/laplacian.h"
#include "core/mesh_query.h"
#include "core/mesh_topology.h"
#include "core/polyline.h"
#include "core/row_tree.h"
#include "core/stage_error.h"
#include "segment/garment_completion.h"
#include "segment/hem_plane.h"
#include "segment/mesh_cut.h"
#include "segment/surface_spline.h"
#include "segment/vertex_regions.h"

namespace s2p {

const char* toString(GarmentLayout layout) {
  switch (layout) {
    case GarmentLayout::UpperLower:
      return "upper_lower";
    case GarmentLayout::OnePiece:
      return "one_piece";
    case GarmentLayout::UpperOnly:
      return "upper_only";
    case GarmentLayout::LowerOnly:
      return "lower_only";
  }
  return "invalid";
}

const char* toString(Occlusion occlusion) {
  switch (occlusion) {
    case Occlusion::None:
      return "none";
    case Occlusion::LowerOccluded:
      return "lower_occluded";
    case Occlusion::UpperOccluded:
      return "upper_occluded";
  }
  return "invalid";
}

namespace {

using Vec3 = Eigen::Vector3d;
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// A mesh the next boundary is optimised on: what the previous cuts left of the scan.
struct Stage {
  TriMesh mesh;
  Eigen::MatrixX3d lab;        // #V×3 smoothed CIELAB
  Eigen::MatrixX3d srgb;       // #V×3
  Eigen::VectorXi faceOrigin;  // #F → scan face
  Eigen::VectorXi scanVertex;  // #V → scan vertex, −1 for a vertex made by a cut
  // With the body under the clothes (empty without): the offset from it and the step field
  // (segment/body_offset.h), both computed once on the whole scan and carried through the cuts.
  Eigen::VectorXd offset;  // #V, m
  Eigen::VectorXd step;    // #V, m
  Eigen::VectorXd smoothOffset;  // #V, m: the offset smoothed over the scanner's noise
  Eigen::MatrixX3d bodyNormal;  // #V×3: the normal of the body's closest face (not unit after cuts)
};

Stage childStage(const Stage& parent, const CutPart& part) {
  Stage s;
  s.mesh = part.mesh;
  const int n = part.mesh.numVertices();
  s.lab.resize(n, 3);
  s.srgb.resize(n, 3);
  s.scanVertex.resize(n);
  for (int v = 0; v < n; ++v) {
    const VertexOrigin& o = part.vertexOrigin[v];
    s.lab.row(v) = (1 - o.t) * parent.lab.row(o.a) + o.t * parent.lab.row(o.b);
    s.srgb.row(v) = (1 - o.t) * parent.srgb.row(o.a) + o.t * parent.srgb.row(o.b);
    s.scanVertex[v] = o.isOriginal() ? parent.scanVertex[o.a] : -1;
  }
  if (parent.step.size() > 0) {
    s.offset.resize(n);
    s.step.resize(n);
    s.smoothOffset.resize(n);
    for (int v = 0; v < n; ++v) {
      const VertexOrigin& o = part.vertexOrigin[v];
      s.offset[v] = (1 - o.t) * parent.offset[o.a] + o.t * parent.offset[o.b];
      s.step[v] = (1 - o.t) * parent.step[o.a] + o.t * parent.step[o.b];
      s.smoothOffset[v] = (1 - o.t) * parent.smoothOffset[o.a] + o.t * parent.smoothOffset[o.b];
    }
  }
  if (parent.bodyNormal.rows() > 0) {
    s.bodyNormal.resize(n, 3);
    for (int v = 0; v < n; ++v) {
      const VertexOrigin& o = part.vertexOrigin[v];
      s.bodyNormal.row(v) =
          (1 - o.t) * parent.bodyNormal.row(o.a) + o.t * parent.bodyNormal.row(o.b);
    }
  }
  s.faceOrigin.resize(part.faceOrigin.size());
  for (int f = 0; f < part.faceOrigin.size(); ++f)
    s.faceOrigin[f] = parent.faceOrigin[part.faceOrigin[f]];
  return s;
}

// Area of every scan face per label, accumulated from the pieces the cuts produce.
class LabelAreas {
 public:
  LabelAreas(int numVertices, int numFaces)
      : area_(Eigen::MatrixXd::Zero(numFaces, kNumLabels)),
        vertexLabel_(Eigen::VectorXi::Constant(numVertices, -1)) {}

  // Every face of `stage` to `label`, or per face when `faceLabel` is given.
  void add(const Stage& stage, Label label, const Eigen::VectorXi* faceLabel = nullptr,
           const Eigen::VectorXi* vertexLabel = nullptr) {
    const Eigen::VectorXd a = faceAreas(stage.mesh);
    for (int f = 0; f < stage.mesh.numFaces(); ++f)
      area_(stage.faceOrigin[f], faceLabel ? (*faceLabel)[f] : static_cast<int>(label)) += a[f];
    for (int v = 0; v < stage.mesh.numVertices(); ++v)
      if (stage.scanVertex[v] >= 0)
        vertexLabel_[stage.scanVertex[v]] =
            vertexLabel ? (*vertexLabel)[v] : static_cast<int>(label);
  }

  Eigen::VectorXi faceLabels() const {
    Eigen::VectorXi out(area_.rows());
    for (int f = 0; f < area_.rows(); ++f) area_.row(f).maxCoeff(&out[f]);
    return out;
  }
  // Vertices no piece kept (none, as every scan vertex lies in exactly one piece) take the label
  // of an incident face.
  Eigen::VectorXi vertexLabels(const TriMesh& scan, const Eigen::VectorXi& faceLabel) const {
    Eigen::VectorXi out = vertexLabel_;
    for (int f = 0; f < scan.numFaces(); ++f)
      for (int k = 0; k < 3; ++k)
        if (out[scan.F(f, k)] < 0) out[scan.F(f, k)] = faceLabel[f];
    return out.cwiseMax(0);
  }

 private:
  Eigen::MatrixXd area_;         // #F × kNumLabels
  Eigen::VectorXi vertexLabel_;  // #V, −1 until set
};

// A feature projected to the scan: its position, which stays valid on every later stage.
struct Anchor {
  Vec3 position;
  double value = 0;
};

struct ProjectedCurve {
  std::string name;
  std::vector<Eigen::MatrixX3d> splines;  // surviving anchors of each spline
  std::vector<bool> closed;
  std::vector<Anchor> signs;
  int anchors = 0, droppedAnchors = 0, numSigns = 0, droppedSigns = 0;
  int carriedSplines = 0, droppedSplines = 0;  // fallbacks of projectCurve
};

// A spline that loses most of its anchors to Appendix B (or too many to draw it) is replaced by
// the body's own loop carried onto the scan (every anchor's closest scan point), unless the loop
// lies farther than `missingDistance` from the scan at most anchors (median): the body says the
// limb is not there (a hand or foot the scan lacks) and the spline is dropped. The sign points
// likewise: when none survives, all are carried by closest point. Each fallback is noted.
ProjectedCurve projectCurve(const FeatureProjector& projector, const CurveFeatures& curve,
                            const TriMesh& body, double missingDistance,
                            std::vector<std::string>& notes) {
  ProjectedCurve out;
  out.name = curve.name;
  for (const FeatureSpline& s : curve.splines) {
    const std::vector<ProjectedPoint> p = projector.project(s.anchors);
    std::vector<Vec3> kept;
    for (const ProjectedPoint& q : p)
      if (q.ok()) kept.push_back(q.p);
    out.anchors += static_cast<int>(p.size());
    out.droppedAnchors += static_cast<int>(p.size() - kept.size());
    const size_t need = s.closed ? 3 : 2;
    if (kept.size() < need || 2 * kept.size() < p.size()) {
      std::vector<double> gap;
      for (size_t i = 0; i < p.size(); ++i)
        gap.push_back((s.anchors[i].position(body) - p[i].p).norm());
      std::nth_element(gap.begin(), gap.begin() + gap.size() / 2, gap.end());
      const double median = gap.empty() ? 0.0 : gap[gap.size() / 2];
      if (p.size() < need || median > missingDistance) {
        notes.push_back(fmt::format(
            "spline '{}' of boundary {} dropped: {} of its {} anchors ill-projected (Appendix B) "
            "and the fitted body's loop lies {:.0f} mm from the scan (median): the scan has no "
            "limb there",
            s.name, curve.name, p.size() - kept.size(), p.size(), 1000 * median));
        ++out.droppedSplines;
        continue;
      }
      notes.push_back(fmt::format(
          "spline '{}' of boundary {}: {} of its {} anchors ill-projected (Appendix B); the "
          "fitted body's own loop carried onto the scan instead (closest points, median {:.0f} mm)",
          s.name, curve.name, p.size() - kept.size(), p.size(), 1000 * median));
      ++out.carriedSplines;
      kept.clear();
      for (const ProjectedPoint& q : p) kept.push_back(q.p);
    }
    Eigen::MatrixX3d A(static_cast<int>(kept.size()), 3);
    for (size_t i = 0; i < kept.size(); ++i) A.row(static_cast<int>(i)) = kept[i].transpose();
    out.splines.push_back(A);
    out.closed.push_back(s.closed);
  }
  std::vector<Anchor> carried;
  for (const SignPoint& s : curve.signs) {
    const ProjectedPoint q = projector.project(s.point);
    ++out.numSigns;
    carried.push_back({q.p, s.value});
    if (q.ok())
      out.signs.push_back({q.p, s.value});
    else
      ++out.droppedSigns;
  }
  if (out.signs.empty() && !carried.empty()) {
    notes.push_back(fmt::format(
        "boundary {}: all {} sign points ill-projected (Appendix B); carried onto the scan by "
        "closest point instead",
        curve.name, carried.size()));
    out.signs = std::move(carried);
  }
  return out;
}

// Points given by position on the scan, located on a stage mesh (the part of the scan left):
// those farther than `tolerance` from it were cut away.
std::vector<SurfacePoint> locate(const MeshQuery& query, const std::vector<Vec3>& positions,
                                 double tolerance, std::vector<int>* kept = nullptr) {
  std::vector<SurfacePoint> out;
  if (positions.empty()) return out;
  Eigen::MatrixX3d P(static_cast<int>(positions.size()), 3);
  for (size_t i = 0; i < positions.size(); ++i) P.row(static_cast<int>(i)) = positions[i];
  const std::vector<ClosestHit> hits = query.closestPoints(P);
  for (size_t i = 0; i < hits.size(); ++i)
    if (hits[i].distance <= tolerance) {
      out.push_back({hits[i].face, hits[i].bary});
      if (kept) kept->push_back(static_cast<int>(i));
    }
  return out;
}

std::vector<Eigen::MatrixX3d> curvePolylines(const Isoline& iso, std::vector<bool>& closed) {
  std::vector<Eigen::MatrixX3d> out;
  closed.clear();
  for (const IsolineCurve& c : iso.curves) {
    Eigen::MatrixX3d P(static_cast<int>(c.points.size()), 3);
    for (size_t i = 0; i < c.points.size(); ++i)
      P.row(static_cast<int>(i)) = c.points[i].position.transpose();
    out.push_back(P);
    closed.push_back(c.closed);
  }
  return out;
}

// Eq. (5): φ_dn(u) = max(2(|o·n_u| − ½), 0) with o the normal of the plane fitted to the
// boundary curve nearest to u (one plane per loop: two ankle loops of a walking pose are not
// coplanar). Only vertices within `band` metres of the boundary get it.
Eigen::VectorXd normalDisplacement(const TriMesh& mesh, const Isoline& boundary,
                                   const Eigen::VectorXd& phi, double band) {
  std::vector<Vec3> centroid, normal;
  for (const IsolineCurve& c : boundary.curves) {
    if (c.points.size() < 3) continue;
    std::vector<Vec3> points;
    for (const IsolinePoint& p : c.points) points.push_back(p.position);
    const FittedPlane plane = fitPlane(points);
    centroid.push_back(plane.centre);
    normal.push_back(plane.normal());
  }
  Eigen::VectorXd out = Eigen::VectorXd::Zero(mesh.numVertices());
  if (centroid.empty()) return out;
  const Eigen::MatrixX3d N = vertexNormals(mesh);
  for (int v = 0; v < mesh.numVertices(); ++v) {
    if (std::abs(phi[v]) > band) continue;
    const Vec3 p = mesh.V.row(v).transpose();
    size_t best = 0;
    for (size_t c = 1; c < centroid.size(); ++c)
      if ((p - centroid[c]).squaredNorm() < (p - centroid[best]).squaredNorm()) best = c;
    const double d = std::abs(normal[best].dot(N.row(v).transpose()));
    out[v] = std::max(2 * (d - 0.5), 0.0);
  }
  return out;
}

// Eq. (5) with the body under the clothes known (issue 18): φ_dn counts only where the scan turns
// away from that body, fully where its normal lies 60° or more off the body's (a hem's riser, the
// cap closing a skirt or a cuff), not at all within 30° (linear between). Eq. (5) alone takes any
// surface facing along the boundary's plane normal for a gap: the torso's sides under the arms
// face along an armhole's, and where colour cannot tell skin from the top (close_to_skin) φ_dn
// alone pushed the skin side into the top there, though top and body run parallel. bodyNormal:
// #V×3, the normal of the body's closest face.
void onlyWhereTurnedAway(const TriMesh& mesh, const Eigen::MatrixX3d& bodyNormal,
                         Eigen::VectorXd& phiDn) {
  const double cos30 = std::sqrt(3.0) / 2, cos60 = 0.5;
  const Eigen::MatrixX3d N = vertexNormals(mesh);
  for (int v = 0; v < mesh.numVertices(); ++v) {
    if (phiDn[v] <= 0) continue;
    const Vec3 b = bodyNormal.row(v).transpose();
    const double c = b.norm() > 0 ? N.row(v).dot(b.transpose()) / b.norm() : 0.0;
    phiDn[v] *= std::clamp((cos30 - c) / (cos30 - cos60), 0.0, 1.0);
  }
}

// Which vertices are gap-filling triangles (§5.2) rather than garment or skin. A candidate
// faces along the boundary's plane normal (φ_dn > 0) and does not look onto the body: its inward
// normal meets no body surface within 2·reach (a shoulder under a neckline looks down onto the
// body an ease away; the cap that closes a skirt's hem looks up into the skirt). A connected
// set of candidates is a gap when some of it lies farther than `reach` from the body: the cap
// spans the gap out to a skirt's rim, while the riser under a fitted hem is an ease wide and
// counts as garment (so does the generator's truth). And when its colour is not the garment's
// beside it (the non-candidates within `reach` on the garment's side, φ < 0): §5.2's filling
// triangles carry "meaningless colours", what the cameras saw through the gap (a garment's
// inside in its own shadow, the skin beyond), while a collar standing off the neck or the
// surface closing a thick garment at its edge is cloth in the cloth's colour. `sameColour` is
// that test's ΔE00; each wide set's ΔE is appended to `deltaE` when given.
std::vector<bool> gapVertices(const TriMesh& mesh, const Eigen::VectorXd& phiDn,
                              const MeshQuery& body, double reach, const Eigen::MatrixX3d& lab,
                              const Eigen::VectorXd& phi, double sameColour,
                              std::vector<std::pair<double, bool>>* deltaE = nullptr) {
  const int nV = mesh.numVertices();
  const Eigen::MatrixX3d N = vertexNormals(mesh);
  std::vector<bool> candidate(nV, false);
  for (int v = 0; v < nV; ++v) {
    if (phiDn[v] <= 0) continue;
    // From a fifth of `reach` outside: bare skin may lie a hair inside the body.
    const Vec3 n = N.row(v).transpose();
    const double lead = 0.2 * reach;
    candidate[v] =
        !body.rayCast(mesh.V.row(v).transpose() + lead * n, -n, 0, lead + 2 * reach).has_value();
  }
  const MeshTopology topo(mesh.F, nV);
  const VertexRegions regions = vertexRegions(
      topo, [&](int e) { return candidate[topo.edges()(e, 0)] && candidate[topo.edges()(e, 1)]; });
  std::vector<bool> wide(regions.count, false);
  for (int v = 0; v < nV; ++v)
    if (candidate[v] && !wide[regions.region[v]] &&
        body.closestPoint(mesh.V.row(v).transpose()).distance > reach)
      wide[regions.region[v]] = true;
  // The colour test, per wide set, against the garment's side beside it.
  std::vector<int> setOf(nV, -1);
  std::vector<std::vector<int>> own(regions.count);
  for (int v = 0; v < nV; ++v)
    if (candidate[v] && wide[regions.region[v]]) {
      setOf[v] = regions.region[v];
      own[regions.region[v]].push_back(v);
    }
  const std::vector<std::vector<int>> beside = besideSets(
      mesh.V, setOf, regions.count, reach, [&](int v) { return !candidate[v] && phi[v] < 0; });
  for (int r = 0; r < regions.count; ++r) {
    if (!wide[r] || beside[r].empty()) continue;
    const double d = deltaE2000(medianColour(lab, own[r]), medianColour(lab, beside[r]));
    wide[r] = d >= sameColour;
    if (deltaE) deltaE->push_back({d, wide[r]});
  }
  std::vector<bool> out(nV, false);
  for (int v = 0; v < nV; ++v) out[v] = candidate[v] && wide[regions.region[v]];
  return out;
}

double meanHeight(const Isoline& iso) {
  double sum = 0, len = 0;
  forEachSegment(iso, [&](const Vec3& a, const Vec3& b) {
    sum += 0.5 * (a.y() + b.y()) * (b - a).norm();
    len += (b - a).norm();
  });
  return len > 0 ? sum / len : 0.0;
}

// Everything one boundary needs from the scan: its projected features and which colour
// regions lie on which side.
struct BoundaryJob {
  const ProjectedCurve* curve = nullptr;
  std::vector<int> regions;  // indices into the fitted region models
  std::vector<bool> positive;
  bool gapFilling = false;
  Label garment = Label::Upper, other = Label::Skin;
  // Colour cannot tell the sides apart (e.g. black trousers over black shoes): the boundary
  // stays on the initial spline (φ₀), with a note, instead of wandering.
  bool keepInitial = false;
  // The geometric cues: ΔE between the two sides' colours (their weight, geometryWeight), and
  // which side of a step is positive: −1 when the positive side is skin or what a garment
  // covers (the garment is the outer, offset side), +1 when it is the outer garment, 0 to take
  // it from the steps near the initial curve (stepOrientation; B(U|L): a top worn over the
  // trousers or tucked into them).
  double deltaE = 100;
  double highSide = -1;
  bool geometry = true;  // false: colour alone whatever deltaE
  // The offset itself beside the steps (offsetDisplacement): the garment's region, whose
  // points' median offset is the garment's level (the skin's is the skin region's), and +1 when
  // skin is on the positive side, −1 when the garment is; −1 for the region: no offset term.
  int offsetRegion = -1;
  double offsetSign = 1;
  // Both sides are garments of different colours (B(U|L) of upper and lower): a colour both of
  // their models hold (sharedColours: a jersey's white stripes over white shorts) pushes neither
  // way. Its posterior otherwise goes to the model where that colour weighs more, and the waist
  // boundary stopped in the first stripe of it, 17 cm above the jersey's hem.
  bool neutralSharedColours = false;
};

// The labelled region points projected to the scan, by RegionLabel (skin, upper, lower, foot);
// the ill-projected ones dropped (counted). Fewer than 4 skin, upper or lower points left →
// InputError: the colour model cannot be fitted.
std::vector<std::vector<SurfacePoint>> projectRegionPoints(const FeatureProjector& projector,
                                                           const FeatureSet& features, int& total,
                                                           int& dropped) {
  std::vector<std::vector<SurfacePoint>> regions(4);
  for (const RegionPoint& r : features.regions) {
    const ProjectedPoint q = projector.project(r.point);
    ++total;
    if (!q.ok()) {
      ++dropped;
      continue;
    }
    regions[static_cast<int>(r.label)].push_back(q.point);
  }
  for (RegionLabel l : {RegionLabel::Skin, RegionLabel::Upper, RegionLabel::Lower})
    if (regions[static_cast<int>(l)].size() < 4)
      throw InputError(fmt::format(
          "segmentation: only {} '{}' region points survived the projection to the scan; the "
          "colour model needs at least 4 (check the body fit)",
          regions[static_cast<int>(l)].size(), toString(l)));
  return regions;
}

double bodyHeight(const TriMesh& body) {
  const BoundingBox bb = boundingBox(body.V);
  return (bb.max - bb.min).maxCoeff();
}

void checkColour(const TriMesh& scan, const Eigen::MatrixX3d& colour) {
  if (colour.rows() != scan.numVertices() || colour.cols() != 3 || !colour.allFinite())
    throw InputError(
        "segmentation: the scan has no usable colour (" + std::to_string(colour.rows()) +
        " colours for " + std::to_string(scan.numVertices()) +
        " vertices); garment boundaries are found from colour, so give a scan with vertex "
        "colours or a texture");
}

struct BoundaryRun {
  BoundaryResult result;
  BoundaryReport report;
};

class Segmenter {
 public:
  Segmenter(const TriMesh& scan, const Eigen::MatrixX3d& colour, const TriMesh& body,
            const TriMesh* underBody, const FeatureSet& features,
            const SegmentationOptions& options, Progress& progress)
      : scan_(scan), options_(options), progress_(progress) {
    validateMesh(scan, "scan");
    validateMesh(body, "body");
    checkColour(scan, colour);
    if (underBody && options.geometry.enabled) {
      validateMesh(*underBody, "body under the clothes");
      progress_.begin("offset from the body under the clothes");
      underQuery_ = std::make_unique<MeshQuery>(*underBody);
      root_.offset = bodyOffset(scan, *underQuery_, *underBody, &root_.bodyNormal);
      root_.step = coarseStepField(scan, root_.offset, root_.smoothOffset);
      progress_.end();
    }
    height_ = bodyHeight(body);
    bodyQuery_ = std::make_unique<MeshQuery>(body);
    tolerance_ = 1e-7 * std::max(height_, 1.0);
    ProjectionOptions popt = options.projection;
    popt.bodyLength = height_;
    progress_.begin("project features");
    const FeatureProjector projector(body, scan, popt);
    const double missing = kLimbMissingFraction * height_;
    upperSkin_ = projectCurve(projector, features.upperSkin, body, missing, projectionNotes_);
    lowerSkin_ = projectCurve(projector, features.lowerSkin, body, missing, projectionNotes_);
    upperLower_ = projectCurve(projector, features.upperLower, body, missing, projectionNotes_);
    projectRegions(projector, features, colour);
    progress_.end();

    root_.mesh = scan;
    root_.lab = colours_.lab;  // root_.offset and root_.step are set above
    root_.srgb = colour;
    root_.faceOrigin = Eigen::VectorXi::LinSpaced(scan.numFaces(), 0, scan.numFaces() - 1);
    root_.scanVertex = Eigen::VectorXi::LinSpaced(scan.numVertices(), 0, scan.numVertices() - 1);
  }

  Segmentation run() {
    const auto t0 = Clock::now();
    Segmentation out;
    out.notes = projectionNotes_;
    decideLayout(out);
    if (!tentativeNoUpper_) pruneLowerModel(out);
    LabelAreas labels(scan_.numVertices(), scan_.numFaces());
    Stage current = root_;
    // A held object first: its features (a hip point landing on a bag) drop out with it.
    if (options_.heldObjects && hasGeometry()) cutHeldObjects(current, out, labels);
    bool hasUpper = out.layout != GarmentLayout::LowerOnly;
    if (options_.hair && hasUpper) fitHairModel(out);
    const bool hasLower = out.layout != GarmentLayout::UpperOnly;
    const Label upperLabel = Label::Upper;
    const Label lowerLabel = out.layout == GarmentLayout::OnePiece ? Label::Upper : Label::Lower;

    // B(U|S): head and hands are cut away, and the hair with them.
    if (hasUpper) {
      BoundaryJob job{&upperSkin_,         {kSkin, kUpper}, {true, false},
                      options_.gapFilling, upperLabel,      Label::Skin};
      if (hairModel_) {
        job.regions.push_back(kHair);
        job.positive.push_back(true);
      }
      // The lower garment's colour is no skin either. Where the hands touch the thighs (a relaxed
      // stance) the scan joins them, and with two labels the skin side flowed over trousers whose
      // colour lies nearer the skin's than the top's (studio_relaxed: khaki chinos under a green
      // shirt, all cut away as skin).
      if (hasLower && out.layout == GarmentLayout::UpperLower) {
        job.regions.push_back(kLower);
        job.positive.push_back(false);
      }
      job.deltaE = separation(kUpper, kSkin);
      job.offsetRegion = kUpper;
      // A torso of this person's skin colour lying near the body: the geometry alone finds the
      // top's edges, and decides whether there is one (tentativeNoUpper_).
      if (tentativeNoUpper_) job.deltaE = 0;
      const size_t notesBefore = geometryNotes_.size();
      auto [run, cut] = optimiseAndCut(current, job);
      if (tentativeNoUpper_ && !upperFoundByGeometry(run, current, out)) {
        hasUpper = false;
        geometryNotes_.resize(notesBefore);  // the run is dropped, and what it said with it
      } else {
        // A top found this way keeps the lower model whole: pruned against the top's model (this
        // person's skin colour), B(L|S) came off the shoes' edge (skin_tone_top: lower|shoes
        // 6.2 mm mean against 1.0 unpruned; upper|lower 0.7 against 2.7 mm).
        labelSkinSide(childStage(current, cut.positive), run.result.boundary, run.report, labels,
                      out);
        out.boundaries.push_back(run.report);
        if (hairReport_) out.boundaries.push_back(*hairReport_);
        current = childStage(current, cut.negative);
      }
    }
    if (!hasUpper) {
      out.notes.push_back("B(U|S) skipped: no upper garment");
    }
    // B(L|S): feet (shoes or skin) and bare legs are cut away.
    if (hasLower) {
      BoundaryJob job{&lowerSkin_,         {kSkin, kLower}, {true, false},
                      options_.gapFilling, lowerLabel,      Label::Skin};
      job.deltaE = separation(kLower, kSkin);
      job.offsetRegion = kLower;
      if (out.shoes) {
        job.regions.push_back(kFoot);
        job.positive.push_back(true);
        // Beyond the hem lies a shoe, which stands off the foot like a garment: the offset does
        // not say which side is which (the colour, or the ankle template, decides).
        job.geometry = false;
        // The mixture must tell the foot's own points from the lower garment's.
        const double footAsLower = fractionNegative(job, colours_.colours[kFoot]);
        const double lowerAsFoot = 1 - fractionNegative(job, colours_.colours[kLower]);
        if (footAsLower > 0.5 || lowerAsFoot > 0.5) {
          job.keepInitial = true;
          out.notes.push_back(fmt::format(
              "B(L|S) kept on the ankle template: the colour model takes {:.0f} % of the foot "
              "points for the lower garment and {:.0f} % of the lower garment's for feet",
              100 * footAsLower, 100 * lowerAsFoot));
        }
      }
      auto [run, cut] = optimiseAndCut(current, job);
      const Stage feet = childStage(current, cut.positive);
      const Eigen::VectorXi footVertex = skinOrShoes(feet, out.shoes);
      const Eigen::VectorXi footFace = faceLabelsFromVertices(feet.mesh, footVertex);
      labels.add(feet, Label::Skin, &footFace, &footVertex);
      // Skin or shoes by colour, which the vertices at the boundary blend (khaki and black make a
      // skin-like brown): the majority within 3 cm names each point.
      splitByLabel(run.report, run.result.boundary, feet.mesh.V, footVertex, 0.03);
      out.boundaries.push_back(run.report);
      current = childStage(current, cut.negative);
    } else {
      out.notes.push_back("B(L|S) skipped: no lower garment");
    }

    if (out.layout == GarmentLayout::OnePiece) {
      labels.add(current, Label::Upper);
      out.garments.push_back(piece("onepiece", Label::Upper, current));
      out.notes.push_back("B(U|L) skipped: one-piece garment (§5.3)");
    } else {
      splitUpperLower(current, out, labels);
    }
    out.faceLabel = labels.faceLabels();
    out.vertexLabel = labels.vertexLabels(scan_, out.faceLabel);
    addRimBoundaries(out);
    if (heldReport_) {
      // The objects' edge split where the garment beside it changes (a bag over the waist).
      Eigen::VectorXi beside = out.vertexLabel;
      for (int v = 0; v < beside.size(); ++v)
        if (beside[v] == static_cast<int>(Label::Other)) beside[v] = -1;
      // The garments beside it were cut exactly: the nearest vertex names each point (a majority
      // over 3 cm moved the split 15–20 mm past where the garment boundary meets the edge).
      splitByLabel(*heldReport_, heldBoundary_, scan_.V, beside, 0.0);
      out.boundaries.insert(out.boundaries.begin(), *heldReport_);
    }
    out.regionPoints = regionPoints_;
    out.droppedRegionPoints = droppedRegionPoints_;
    for (const std::string& n : skipNotes_) out.notes.push_back(n);
    for (const std::string& n : pieceNotes_) out.notes.push_back(n);
    for (const std::string& n : geometryNotes_) out.notes.push_back(n);
    for (const BoundaryReport& b : out.boundaries)
      if (!b.converged)
        out.notes.push_back(
            fmt::format("boundary {} did not converge in {} iterations", b.name, b.iterations));
    out.seconds = secondsSince(t0);
    return out;
  }

 private:
  static constexpr int kSkin = 0, kUpper = 1, kLower = 2, kFoot = 3;
  static constexpr int kHair = 4;  // colours_.models[kHair]: fitted from hair seeds when found
  // A body loop farther than this fraction of the height from the scan (median over its
  // anchors) is a limb the scan does not have (projectCurve).
  static constexpr double kLimbMissingFraction = 0.05;

  void projectRegions(const FeatureProjector& projector, const FeatureSet& features,
                      const Eigen::MatrixX3d& colour) {
    std::vector<std::vector<SurfacePoint>> regions =
        projectRegionPoints(projector, features, regionPoints_, droppedRegionPoints_);
    hasFootRegion_ = regions[kFoot].size() >= 4;
    upperPoints_ = regions[kUpper];
    for (int r = 0; r < 4; ++r)
      for (const SurfacePoint& p : regions[r]) regionPositions_[r].push_back(p.position(scan_));
    for (const SurfacePoint& p : regions[kFoot]) footPoints_.push_back(p.position(scan_));
    if (!hasFootRegion_) regions[kFoot] = regions[kSkin];
    colours_ = fitRegionColours(scan_, colour, regions, options_.colour);
    if (dropSkinPointsOnGarments(regions)) {
      if (!hasFootRegion_) regions[kFoot] = regions[kSkin];
      colours_ = fitRegionColours(scan_, colour, regions, options_.colour);
    }
    if (hasGeometry())
      for (int r = 0; r < 4; ++r) {
        const std::vector<double> o = offsetsAt(scan_, root_.offset, regions[r]);
        regionOffset_[r] = median(o);
        regionClothed_[r] = offsetSaysClothed(o, options_.geometry);
      }
  }

  bool hasGeometry() const { return root_.step.size() > 0; }

  // The skin region's points that landed on a garment (a hand's points on a long sleeve's cuff:
  // a third of f2's) would teach the skin's model the garment's colour: left out
  // (skinSamplesOfGarments), unless that leaves fewer than half of them. True when some went
  // (the colour models are then to be fitted again).
  bool dropSkinPointsOnGarments(std::vector<std::vector<SurfacePoint>>& regions) {
    const std::vector<bool> strays = skinSamplesOfGarments(
        colours_.colours[kSkin], {colours_.models[kUpper], colours_.models[kLower]},
        options_.sameColourDeltaE);
    const auto n = std::count(strays.begin(), strays.end(), true);
    if (n == 0 || 2 * static_cast<size_t>(n) > strays.size()) return false;
    std::vector<SurfacePoint> kept;
    std::vector<Vec3> keptPositions;
    for (size_t i = 0; i < strays.size(); ++i)
      if (!strays[i]) {
        kept.push_back(regions[kSkin][i]);
        keptPositions.push_back(regionPositions_[kSkin][i]);
      }
    regions[kSkin] = std::move(kept);
    regionPositions_[kSkin] = std::move(keptPositions);
    pieceNotes_.push_back(fmt::format(
        "{} of the skin region's {} points have a garment's colour (a hand's points on a "
        "sleeve's cuff): left out of the skin's colour model",
        n, strays.size()));
    return true;
  }

  // The step field of the offset (body_offset.h). On a large scan it is smoothed on the
  // decimated copy the boundaries are optimised on and carried back: its two surface smoothings
  // (3 mm and 3 cm) each factor M + l²L, 10 s a factorisation at 1M vertices.
  // `smoothOffset` receives the offset smoothed over the scanner's noise (#V).
  Eigen::VectorXd coarseStepField(const TriMesh& scan, const Eigen::VectorXd& offset,
                                  Eigen::VectorXd& smoothOffset) const {
    const std::optional<CoarseMesh> copy =
        options_.coarseVertices > 0 ? decimatedCopy(scan, options_.coarseVertices) : std::nullopt;
    if (!copy) return stepField(scan, offset, options_.geometry, &smoothOffset);
    Eigen::VectorXd coarseOffset(copy->mesh.numVertices());
    for (int v = 0; v < coarseOffset.size(); ++v) coarseOffset[v] = offset[copy->fineVertex[v]];
    Eigen::VectorXd coarseSmooth;
    const CoarseToFine map(copy->mesh, scan);
    const Eigen::VectorXd step =
        map.carry(stepField(copy->mesh, coarseOffset, options_.geometry, &coarseSmooth));
    smoothOffset = map.carry(coarseSmooth);
    return step;
  }

  static double median(std::vector<double> v) {
    if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  }

  double deltaE(int a, int b) const { return deltaE2000(colours_.means[a], colours_.means[b]); }

  // How far apart two regions' colours are for the geometric cues' weight: the median CIEDE2000
  // of a's points from b's mean colour, or of b's from a's, the larger (a striped dress's mean
  // is near skin, its points are not).
  double separation(int a, int b) const {
    const auto medianFrom = [&](int from, int to) {
      const Eigen::MatrixXd& lab = colours_.colours[from];
      std::vector<double> d;
      for (int i = 0; i < lab.rows(); ++i)
        d.push_back(deltaE2000(lab.row(i).transpose(), colours_.means[to]));
      return median(d);
    };
    return std::max(medianFrom(a, b), medianFrom(b, a));
  }

  // The chest is covered by any top; the hips are not when the top is worn untucked, and their
  // points then teach the lower model the top's colours.
  void pruneLowerModel(Segmentation& out) {
    if (out.layout != GarmentLayout::UpperLower || tentativeOnePiece_) return;
    double borrowed = 0;
    colours_.models[kLower] = withoutBorrowedComponents(colours_.models[kLower],
                                                        colours_.models[kUpper], 0.5, &borrowed);
    if (borrowed > 0)
      out.notes.push_back(fmt::format(
          "{:.0f} % of the lower region's points have the upper garment's colours (a top worn "
          "over the waistband): left out of the lower colour model",
          100 * borrowed));
  }

  // A torso of this person's skin colour near the body (tentativeNoUpper_): B(U|S) was run on
  // the geometry alone; a top is there when the boundary found runs along steps of the offset
  // (a neckline, sleeve hems: the same median step vote as a hem between upper and lower of one
  // colour) and leaves most of the chest and back on the garment side. A bare torso fails one
  // or the other: its boundary stays on the neck and wrist loops, where nothing steps, or runs
  // down to the trousers' waistband, which steps but leaves the chest on the skin side.
  // Otherwise the layout becomes LowerOnly and the run is dropped.
  bool upperFoundByGeometry(BoundaryRun& run, const Stage& stage, Segmentation& out) {
    const double support = run.result.vanished
                               ? 0.0
                               : hemContrast(stage.mesh, run.result.phi, stage.step, -1.0,
                                             options_.geometry);
    run.report.hemContrast = support;
    int covered = 0;
    for (const SurfacePoint& p : upperPoints_) covered += p.interpolate(stage.mesh.F, run.result.phi) < 0;
    const double share =
        upperPoints_.empty() ? 0.0 : covered / static_cast<double>(upperPoints_.size());
    const bool found = !run.result.vanished && support >= options_.geometry.hemContrast &&
                       share > 0.5;
    if (found) {
      out.notes.push_back(fmt::format(
          "upper garment of this person's skin colour found by its edges: B(U|S) on the offset "
          "from the body runs along its steps (median {:.2f} mm, ≥ {:.1f}) with {:.0f} % of the "
          "chest and back on the garment side",
          1000 * support, 1000 * options_.geometry.hemContrast, 100 * share));
      return true;
    }
    out.layout = GarmentLayout::LowerOnly;
    out.notes.push_back(fmt::format(
        "no upper garment: torso colour within ΔE {:.1f} of skin, {:.0f} % of its points, and no "
        "top's edge in the offset from the body (B(U|S) on the geometry: median step {:.2f} mm, "
        "{:.0f} % of the chest and back on the garment side)",
        out.upperSkinDeltaE, 100 * out.upperSkinLike, 1000 * support, 100 * share));
    return false;
  }

  void decideLayout(Segmentation& out) {
    out.upperLowerDeltaE = deltaE(kUpper, kLower);
    out.upperSkinDeltaE = deltaE(kUpper, kSkin);
    out.lowerSkinDeltaE = deltaE(kLower, kSkin);
    out.footSkinDeltaE = hasFootRegion_ ? deltaE(kFoot, kSkin) : 0.0;
    const double same = options_.sameColourDeltaE;
    out.shoes = hasFootRegion_ && out.footSkinDeltaE >= same;
    // Skin-like by this person's skin (its spread on the face and hands), not a fixed ΔE.
    // A garment is missing when most of its region's points are this skin: the region's mean
    // colour alone would take a red-and-white striped dress (a pinkish mean) for bare skin.
    const SkinModel skin =
        fitSkinModel(colours_.colours[kSkin], options_.skinSpreadFactor, options_.minSkinDeltaE,
                     options_.sameColourDeltaE);
    out.skinDeltaE = skin.threshold;
    out.upperSkinLike = skin.skinLikeFraction(colours_.colours[kUpper]);
    out.lowerSkinLike = skin.skinLikeFraction(colours_.colours[kLower]);
    // Most of the region's points must be this person's skin; its mean colour need only be
    // skin-like by the population bound (sameColourDeltaE): a bare leg's region also holds a
    // minority of sock, shoe or waistband points that pull the mean by more than the spread of
    // the face and hands, and the fraction is the test that does not move with them.
    bool noUpper = out.upperSkinDeltaE < same && out.upperSkinLike > 0.5;
    bool noLower = out.lowerSkinDeltaE < same && out.lowerSkinLike > 0.5;
    out.geometricCues = hasGeometry();
    out.upperOffset = regionOffset_[kUpper];
    out.lowerOffset = regionOffset_[kLower];
    out.skinOffset = regionOffset_[kSkin];
    if (hasGeometry()) {
      // A region off the body by more than a garment's minimum is clothed whatever its colour (a
      // top of the wearer's skin tone); one on the body is bare when its colour is this person's
      // skin, as a tight garment lies on the body too (and the fitted body, pushed into the ease,
      // lies within a few mm of most garments).
      const double g = options_.geometry.garmentOffset;
      const bool u = noUpper && !regionClothed_[kUpper];
      const bool l = noLower && !regionClothed_[kLower];
      if (u != noUpper || l != noLower)
        out.notes.push_back(fmt::format(
            "the body under the clothes decides the garments: upper region {:.0f} mm off it "
            "(median; {} ), lower region {:.0f} mm ({}); a garment lies more than {:.0f} mm off",
            1000 * out.upperOffset, u ? "bare" : "clothed", 1000 * out.lowerOffset,
            l ? "bare" : "clothed", 1000 * g));
      noUpper = u;
      noLower = l;
      // A torso of the skin's colour near the body is bare, or a top of the wearer's skin tone
      // that the fit pushed the body into: B(U|S) on the geometry alone decides
      // (upperFoundByGeometry). A one-piece decision by colour likewise waits for B(U|L).
      if (noUpper && !noLower) {
        tentativeNoUpper_ = true;
        noUpper = false;
      }
    }
    if (noUpper && noLower)
      throw InputError(fmt::format(
          "segmentation: no garment found: the upper body (ΔE {:.1f}) and the lower body (ΔE "
          "{:.1f}) have the colour of the skin",
          out.upperSkinDeltaE, out.lowerSkinDeltaE));
    if (noUpper) {
      out.layout = GarmentLayout::LowerOnly;
      out.notes.push_back(fmt::format(
          "no upper garment: torso colour within ΔE {:.1f} of skin, {:.0f} % of its points",
          out.upperSkinDeltaE, 100 * out.upperSkinLike));
    } else if (noLower) {
      out.layout = GarmentLayout::UpperOnly;
      out.notes.push_back(fmt::format(
          "no lower garment: leg colour within ΔE {:.1f} of skin, {:.0f} % of its points",
          out.lowerSkinDeltaE, 100 * out.lowerSkinLike));
    } else if (out.upperLowerDeltaE < same && hasGeometry() && !tentativeNoUpper_) {
      // The colour says one piece; a hem step between the two regions says two. B(U|L) is run on
      // the steps and decides (splitUpperLower).
      tentativeOnePiece_ = true;
    } else if (out.upperLowerDeltaE < same) {
      out.layout = GarmentLayout::OnePiece;
      out.notes.push_back(
          fmt::format("one-piece garment: upper and lower body colours within ΔE {:.1f} (§5.3)",
                      out.upperLowerDeltaE));
    }
    if (!out.shoes) out.notes.push_back("no shoes: the feet have the colour of the skin");
  }

  // A garment that ends in an open rim of the scan around a piece of skin: the hem of a skirt
  // whose legs the scanner made a piece of their own (issue 17) is where the skirt's piece stops,
  // not an isoline, and the legs pass through it. Such a rim (long, all its faces one garment's,
  // another piece's skin crossing the plane inside it) is reported as that garment's boundary
  // with the skin, beside its isolines. A hole where no camera looked has no other piece in it.
  void addRimBoundaries(Segmentation& out) const {
    constexpr double kMinRim = 0.2;  // m: shorter open loops are holes, not hems
    // Skin of another piece inside the rim's outline and within a tenth of the height of its
    // plane passes through it (legs scanned apart start where the cameras stopped seeing under the
    // hem, a few cm below it; a hole in a garment has no other piece inside it at any distance).
    const double planeBand = 0.1 * height_;
    constexpr int kMinCrossing = 5;  // such skin vertices
    const MeshTopology topo(scan_.F, scan_.numVertices());
    if (topo.numComponents() < 2 || topo.boundaryLoops().empty()) return;
    std::vector<int> vertexPiece(scan_.numVertices(), -1);
    for (int f = 0; f < scan_.numFaces(); ++f)
      for (int k = 0; k < 3; ++k) vertexPiece[scan_.F(f, k)] = topo.faceComponent()[f];
    for (const std::vector<int>& loop : topo.boundaryLoops()) {
      const int n = static_cast<int>(loop.size());
      if (n < 3) continue;
      double length = 0;
      std::array<int, kNumLabels> faces{};
      for (int i = 0; i < n; ++i) {
        const int a = loop[i], b = loop[(i + 1) % n];
        length += (scan_.V.row(a) - scan_.V.row(b)).norm();
        const int e = topo.findEdge(a, b);
        if (e < 0) continue;
        for (int f : topo.edgeFaces(e))
          if (out.faceLabel[f] >= 0 && out.faceLabel[f] < kNumLabels) ++faces[out.faceLabel[f]];
      }
      const int g = static_cast<int>(std::max_element(faces.begin(), faces.end()) - faces.begin());
      if (length < kMinRim ||
          (g != static_cast<int>(Label::Upper) && g != static_cast<int>(Label::Lower)))
        continue;
      if (faces[g] < 0.9 * n) continue;
      // The rim's plane and its outline in it.
      std::vector<Vec3> rim;
      for (int v : loop) rim.push_back(scan_.V.row(v).transpose());
      const FittedPlane plane = fitPlane(rim);
      const Vec3 &c = plane.centre, normal = plane.normal(), u = plane.axes.col(2),
                 w = plane.axes.col(1);
      std::vector<Eigen::Vector2d> outline;
      for (const Vec3& p : rim) outline.emplace_back((p - c).dot(u), (p - c).dot(w));
      const auto inside = [&](const Eigen::Vector2d& q) {
        bool in = false;
        for (size_t i = 0, j = outline.size() - 1; i < outline.size(); j = i++) {
          const Eigen::Vector2d &a = outline[i], &b = outline[j];
          if ((a.y() > q.y()) != (b.y() > q.y()) &&
              q.x() < (b.x() - a.x()) * (q.y() - a.y()) / (b.y() - a.y()) + a.x())
            in = !in;
        }
        return in;
      };
      const int piece = vertexPiece[loop[0]];
      int crossing = 0;
      for (int v = 0; v < scan_.numVertices() && crossing < kMinCrossing; ++v) {
        if (vertexPiece[v] == piece || out.vertexLabel[v] != static_cast<int>(Label::Skin))
          continue;
        const Vec3 d = scan_.V.row(v).transpose() - c;
        if (std::abs(d.dot(normal)) < planeBand && inside({d.dot(u), d.dot(w)})) ++crossing;
      }
      if (crossing < kMinCrossing) continue;
      // The rim reported as a curve across the triangles, as every other boundary is: the open
      // edge zigzags between the scanner's vertices, a wavelength of about two edges and up to
      // 2 cm high (skirt_legs_piece: 1.70 m of edge round a 1.37 m hem, 1.58 m of it within
      // 3 mm of it), so it is averaged over an edge either side. The cut stays the scan's edge.
      std::vector<double> edges;
      for (int i = 0; i < n; ++i) edges.push_back((rim[(i + 1) % n] - rim[i]).norm());
      std::nth_element(edges.begin(), edges.begin() + n / 2, edges.end());
      const Eigen::MatrixX3d P = boxFilterClosedPolyline(rim, std::max(0.005, edges[n / 2]));
      const Label garment = static_cast<Label>(g);
      auto report = std::find_if(
          out.boundaries.begin(), out.boundaries.end(),
          [&](const BoundaryReport& b) { return b.garment == garment && b.other == Label::Skin; });
      if (report == out.boundaries.end()) {
        BoundaryReport rim;
        rim.name = garment == Label::Upper ? "U|S" : "L|S";
        rim.garment = garment;
        rim.converged = true;
        out.boundaries.push_back(rim);
        report = out.boundaries.end() - 1;
      }
      report->finalCurves.push_back(P);
      report->finalClosed.push_back(true);
      report->otherLabels.push_back(Label::Skin);
      out.notes.push_back(fmt::format(
          "the {} garment ends in an open rim of the scan ({:.2f} m round) that a separate piece "
          "of skin passes through (such as legs under a skirt the scanner did not join to it): "
          "the rim is its boundary with the skin",
          garment == Label::Upper ? "upper" : "lower", length));
    }
  }

  // Per-vertex skin or shoes on the cut-away feet: the nearer model in CIEDE2000 (to the closest
  // component mean). Not the GMM posterior: the skin model is fitted on the face and hands, and
  // the shading of a leg puts its colour in the tails of both mixtures, where the broader one
  // wins whatever the hue.
  Eigen::VectorXi skinOrShoes(const Stage& feet, bool shoes) const {
    Eigen::VectorXi out =
        Eigen::VectorXi::Constant(feet.mesh.numVertices(), static_cast<int>(Label::Skin));
    if (!shoes) return out;
    auto nearest = [](const GaussianMixture& g, const Eigen::Vector3d& lab) {
      double best = std::numeric_limits<double>::infinity();
      for (int k = 0; k < g.components(); ++k)
        best = std::min(best, deltaE2000(lab, g.means.row(k).transpose()));
      return best;
    };
    // The foot's points that landed on an ankle's skin make a component the skin model holds:
    // left in, every leg vertex near the feet is as near it as to the skin's own.
    const GaussianMixture foot = withoutBorrowedComponents(colours_.models[kFoot],
                                                           colours_.models[kSkin], 0.5);
    for (int v = 0; v < feet.mesh.numVertices(); ++v) {
      const Eigen::Vector3d lab = feet.lab.row(v).transpose();
      if (nearFoot(feet.mesh.V.row(v).transpose()) &&
          nearest(foot, lab) < nearest(colours_.models[kSkin], lab))
        out[v] = static_cast<int>(Label::Shoes);
    }
    return out;
  }

  // Share of the colours `lab` (#N×3) the job's displacement puts on its negative side.
  double fractionNegative(const BoundaryJob& job, const Eigen::MatrixX3d& lab) const {
    if (lab.rows() == 0) return 0;
    std::vector<GaussianMixture> models;
    for (int r : job.regions) models.push_back(colours_.models[r]);
    const Eigen::VectorXd d = posteriorDisplacement(models, job.positive, lab);
    return static_cast<double>((d.array() < 0).count()) / static_cast<double>(d.size());
  }

  // A shoe reaches at most this far from the foot's region points (mid and front foot): no
  // leg, and no gap-filling triangle under a hem, is taken for a shoe however it is coloured.
  bool nearFoot(const Vec3& p) const {
    constexpr double kShoeReach = 0.2;  // m
    for (const Vec3& q : footPoints_)
      if ((p - q).squaredNorm() < kShoeReach * kShoeReach) return true;
    return false;
  }

  GarmentPiece piece(const std::string& name, Label label, const Stage& s) const {
    GarmentPiece p;
    p.name = name;
    p.label = label;
    p.mesh = s.mesh;
    p.colour = s.srgb;
    p.faceOrigin = s.faceOrigin;
    return p;
  }

  struct Located {
    std::vector<std::vector<SurfacePoint>> splines;
    std::vector<ValueConstraint> signs;
    // Pieces a spline crosses but no sign point lies on, signed by their labelled region points
    // instead (regionSignedPieces): how many, their vertices, and the points added to `signs`.
    int regionSignedPieces = 0, regionSignedVertices = 0, regionSigns = 0;
  };

  // The curve's anchors and sign points that lie on `present` (the part of the scan left: those
  // an earlier cut took away lie off it), located on `stage` (that part, or its decimated copy,
  // whose surface strays from it by a fraction of a millimetre); the pieces of `stage` a spline
  // crosses but no sign point lies on get the job's labelled region points on them as sign
  // points (regionSignedPieces).
  Located locateFeatures(const Stage& stage, const ProjectedCurve& curve, const BoundaryJob& job,
                         const TriMesh& present) const {
    const MeshQuery query(stage.mesh);
    const std::optional<MeshQuery> presentQuery =
        &present == &stage.mesh ? std::nullopt : std::make_optional<MeshQuery>(present);
    const MeshQuery& onPresent = presentQuery ? *presentQuery : query;
    const auto kept = [&](const std::vector<Vec3>& positions) {
      std::vector<int> k;
      locate(onPresent, positions, tolerance_, &k);
      std::vector<Vec3> p;
      for (int i : k) p.push_back(positions[i]);
      return std::pair{k, p};
    };
    constexpr double kAnywhere = std::numeric_limits<double>::infinity();
    Located out;
    for (size_t s = 0; s < curve.splines.size(); ++s) {
      // Anchors cut away by an earlier boundary drop out; the spline goes through the rest.
      std::vector<Vec3> anchors;
      for (int i = 0; i < curve.splines[s].rows(); ++i)
        anchors.push_back(curve.splines[s].row(i).transpose());
      const auto [index, left] = kept(anchors);
      if (left.size() < (curve.closed[s] ? 3u : 2u)) continue;
      Eigen::MatrixX3d A(static_cast<int>(left.size()), 3);
      for (size_t i = 0; i < left.size(); ++i) A.row(static_cast<int>(i)) = left[i];
      // At most about one zero constraint per face: denser constraints make the biharmonic's
      // zero set wiggle between them at the scale of the mesh.
      const double spacing = std::max(options_.splineSpacing, meanEdgeLength(stage.mesh));
      out.splines.push_back(surfaceSpline(query, A, curve.closed[s], spacing));
    }
    std::vector<Vec3> positions;
    for (const Anchor& a : curve.signs) positions.push_back(a.position);
    const auto [index, left] = kept(positions);
    const std::vector<SurfacePoint> pts = locate(query, left, kAnywhere);
    for (size_t i = 0; i < pts.size(); ++i)
      out.signs.push_back({pts[i], curve.signs[index[i]].value});
    regionSignedPieces(stage, job, query, onPresent, out);
    return out;
  }

  // The biharmonic of Eq. (1) is solved per piece of the scan (the Laplacian has one block per
  // piece), so a piece that holds zero constraints and no sign point gets φ ≡ 0: which side of
  // the curve is which is decided there by nothing (boots scanned apart hold every sign point of
  // B(L|S), toes and soles, while the ankle splines lie on the legs: the whole torso once went to
  // the feet's side). On such a piece the labelled region points (face and hands, chest, hips
  // and thigh tops, feet: where each label lies on every outfit) stand in for sign points, each
  // with the side its label takes at this boundary. A piece with sign points keeps them alone.
  void regionSignedPieces(const Stage& stage, const BoundaryJob& job, const MeshQuery& query,
                          const MeshQuery& onPresent, Located& out) const {
    if (out.splines.empty() || out.signs.empty()) return;  // nothing cut (optimise's skip)
    const MeshTopology topo(stage.mesh.F, stage.mesh.numVertices());
    const int n = topo.numComponents();
    if (n < 2) return;
    const Eigen::VectorXi& pieceOf = topo.faceComponent();
    std::vector<char> crossed(n, 0), hasSign(n, 0);
    for (const std::vector<SurfacePoint>& s : out.splines)
      for (const SurfacePoint& p : s) crossed[pieceOf[p.face]] = 1;
    for (const ValueConstraint& c : out.signs)
      if (c.value != 0) hasSign[pieceOf[c.point.face]] = 1;
    std::vector<char> unsignedPiece(n, 0);
    bool any = false;
    for (int p = 0; p < n; ++p) any |= (unsignedPiece[p] = crossed[p] && !hasSign[p]) != 0;
    if (!any) return;
    constexpr double kAnywhere = std::numeric_limits<double>::infinity();
    std::vector<char> used(n, 0);
    for (size_t i = 0; i < job.regions.size(); ++i) {
      const std::vector<Vec3>& positions = regionPositions_[job.regions[i]];
      std::vector<int> kept;
      locate(onPresent, positions, tolerance_, &kept);
      std::vector<Vec3> left;
      for (int k : kept) left.push_back(positions[k]);
      for (const SurfacePoint& p : locate(query, left, kAnywhere)) {
        const int piece = pieceOf[p.face];
        if (!unsignedPiece[piece]) continue;
        out.signs.push_back({p, job.positive[i] ? 1.0 : -1.0});
        used[piece] = 1;
        ++out.regionSigns;
      }
    }
    std::vector<int> vertexPiece(stage.mesh.numVertices(), -1), vertices(n, 0);
    for (int f = 0; f < stage.mesh.numFaces(); ++f)
      for (int k = 0; k < 3; ++k) vertexPiece[stage.mesh.F(f, k)] = pieceOf[f];
    for (int p : vertexPiece)
      if (p >= 0) ++vertices[p];
    for (int p = 0; p < n; ++p)
      if (used[p]) {
        ++out.regionSignedPieces;
        out.regionSignedVertices += vertices[p];
      }
  }

  // optimiseAndCutOnce with a solver's failure restated: which boundary, on what, what to do.
  std::pair<BoundaryRun, CutResult> optimiseAndCut(const Stage& stage, const BoundaryJob& job) {
    try {
      return optimiseAndCutOnce(stage, job);
    } catch (const SolverError& e) {
      const int pieces = MeshTopology(stage.mesh.F, stage.mesh.numVertices()).numComponents();
      throw stageSolverError(
          e, "segmentation, boundary " + job.curve->name,
          fmt::format("the {} vertices left of the scan ({} {})", stage.mesh.numVertices(), pieces,
                      pieces == 1 ? "piece" : "pieces"),
          "the scan may hold slivers or pieces without area: check it with `scan2pattern info`, "
          "clean or remesh it, and try again");
    }
  }

  // The boundary optimised on `stage`, or on a decimated copy of it when it is large (the
  // curves carried back), and the stage cut exactly along it.
  std::pair<BoundaryRun, CutResult> optimiseAndCutOnce(const Stage& stage, const BoundaryJob& job) {
    const auto t0 = Clock::now();
    progress_.begin(fmt::format("boundary {}", job.curve->name));
    const std::optional<CoarseMesh> coarse =
        options_.coarseVertices > 0 ? decimatedCopy(stage.mesh, options_.coarseVertices)
                                    : std::nullopt;
    double coarseSeconds = secondsSince(t0);
    BoundaryRun run;
    if (coarse) {
      const Stage copy = coarseStage(stage, *coarse);
      run = optimise(copy, job, stage.mesh);
      const auto t1 = Clock::now();
      carryToFine(run, copy.mesh, stage.mesh);
      coarseSeconds += secondsSince(t1);
    } else {
      run = optimise(stage, job, stage.mesh);
    }
    run.report.coarseSeconds = coarseSeconds;
    run.report.optimisedVertices = coarse ? coarse->mesh.numVertices() : stage.mesh.numVertices();
    if (!run.report.skipped) settleUncutPieces(stage, job, run);
    CutResult cut = cutAlongIsoline(stage.mesh, awayFromZero(run.result.phi, stage.mesh));
    run.report.seconds = secondsSince(t0);
    progress_.end();
    return {std::move(run), std::move(cut)};
  }

  // Pieces of the stage that no curve crosses and no feature of the boundary lies on (a skirt
  // whose legs are a piece of their own: the ankle splines are on the legs) take the side their
  // labelled region points vote for (sidePiecesByVotes), not the side the balance of the
  // displacement happened to leave them on.
  void settleUncutPieces(const Stage& stage, const BoundaryJob& job, BoundaryRun& run) {
    const Eigen::VectorXd& phi = run.result.phi;
    const MeshTopology topo(stage.mesh.F, stage.mesh.numVertices());
    if (topo.numComponents() < 2) {
      if ((phi.array() < 0).any() && (phi.array() >= 0).any()) return;
    }
    const MeshQuery query(stage.mesh);
    std::vector<Vec3> features;
    for (const Eigen::MatrixX3d& s : job.curve->splines)
      for (int i = 0; i < s.rows(); ++i) features.push_back(s.row(i).transpose());
    for (const Anchor& a : job.curve->signs) features.push_back(a.position);
    const std::vector<SurfacePoint> anchors = locate(query, features, tolerance_);
    std::vector<SideVote> votes;
    for (size_t i = 0; i < job.regions.size(); ++i)
      for (const SurfacePoint& p : locate(query, regionPositions_[job.regions[i]], tolerance_))
        votes.push_back({p, job.positive[i] ? 1.0 : -1.0});
    for (const PieceSide& p : sidePiecesByVotes(stage.mesh, run.result.phi, anchors, votes)) {
      if (!p.flipped) continue;
      const bool toPositive = p.positiveVotes > p.negativeVotes;
      pieceNotes_.push_back(fmt::format(
          "boundary {}: a piece of {} vertices that no curve crosses and no feature of the "
          "boundary lies on goes to the {} side, as {} of the {} labelled region points on it say "
          "(the displacement alone left it on the {} side)",
          job.curve->name, p.vertices, toPositive ? toString(job.other) : toString(job.garment),
          toPositive ? p.positiveVotes : p.negativeVotes, p.positiveVotes + p.negativeVotes,
          toPositive ? toString(job.garment) : toString(job.other)));
    }
  }

  // The part of the scan `stage` restricted to the vertices of its decimated copy.
  static Stage coarseStage(const Stage& stage, const CoarseMesh& coarse) {
    const auto rows = [&](const auto& m) {
      using M = std::decay_t<decltype(m)>;
      M out(coarse.fineVertex.size(), m.cols());
      for (int v = 0; v < coarse.fineVertex.size(); ++v) out.row(v) = m.row(coarse.fineVertex[v]);
      return out;
    };
    Stage s;
    s.mesh = coarse.mesh;
    s.lab = rows(stage.lab);
    s.srgb = rows(stage.srgb);
    if (stage.step.size() > 0) {
      s.offset = rows(stage.offset);
      s.step = rows(stage.step);
      s.smoothOffset = rows(stage.smoothOffset);
    }
    if (stage.bodyNormal.rows() > 0) s.bodyNormal = rows(stage.bodyNormal);
    s.scanVertex = rows(stage.scanVertex);
    return s;  // faceOrigin stays empty: a copy's faces lie in no one scan face
  }

  // φ₀ and φ of a boundary optimised on a decimated copy carried to the full mesh `fine` (each
  // vertex takes the value at its closest point on the copy), and the curves re-extracted there:
  // what is cut and reported is the full mesh's zero isoline.
  static void carryToFine(BoundaryRun& run, const TriMesh& coarse, const TriMesh& fine) {
    const CoarseToFine map(coarse, fine);
    const MeshTopology topology(fine.F, fine.numVertices());
    BoundaryResult& r = run.result;
    r.phi = map.carry(r.phi);
    r.boundary = extractIsoline(fine, topology, r.phi);
    if (r.phi0.size() > 0) {
      r.phi0 = map.carry(r.phi0);
      r.initial = extractIsoline(fine, topology, r.phi0);
    }
    BoundaryReport& rep = run.report;
    rep.initialCurves = curvePolylines(r.initial, rep.initialClosed);
    rep.finalCurves = curvePolylines(r.boundary, rep.finalClosed);
    rep.otherLabels.assign(rep.finalCurves.size(), rep.other);
  }

  // Algorithm 1 for one boundary on `stage` (the part of the scan left, or its decimated copy),
  // with the second pass of §5.2 and the islands merged; not cut.
  BoundaryRun optimise(const Stage& stage, const BoundaryJob& job, const TriMesh& present) {
    const ProjectedCurve& curve = *job.curve;
    BoundaryRun run;
    BoundaryReport& rep = run.report;
    rep.name = curve.name;
    rep.garment = job.garment;
    rep.other = job.other;
    rep.anchors = curve.anchors;
    rep.droppedAnchors = curve.droppedAnchors;
    rep.signs = curve.numSigns;
    rep.droppedSigns = curve.droppedSigns;
    const Located f = locateFeatures(stage, curve, job, present);
    if (f.regionSignedPieces > 0)
      pieceNotes_.push_back(fmt::format(
          "boundary {}: {} piece(s) of {} vertices that a spline crosses but no sign point lies on "
          "signed by the {} labelled region points on them",
          curve.name, f.regionSignedPieces, f.regionSignedVertices, f.regionSigns));
    int pos = 0, neg = 0;
    for (const ValueConstraint& c : f.signs) (c.value > 0 ? pos : neg)++;
    if (f.splines.empty() || pos + neg == 0) {
      // Nothing to start this boundary from on what is left of the scan: it is skipped and the
      // whole stage stays on the garment side, rather than stopping the run.
      rep.skipped = true;
      skipNotes_.push_back(fmt::format(
          "boundary {} skipped: {} on what the earlier cuts left of the scan ({} of {} splines "
          "dropped, {} of {} sign points ill-projected); nothing cut away there",
          curve.name, f.splines.empty() ? "no spline lies" : "no sign point lies",
          curve.droppedSplines, curve.splines.size() + curve.droppedSplines, curve.droppedSigns,
          curve.numSigns));
      run.result.phi0 = run.result.phi = Eigen::VectorXd::Constant(stage.mesh.numVertices(), -1.0);
      run.result.converged = true;
      rep.converged = true;
      return run;
    }
    std::vector<GaussianMixture> models;
    for (int r : job.regions) models.push_back(colours_.models[r]);
    std::vector<bool> neutral;  // #V: a colour both sides hold; the steps decide there alone
    if (job.neutralSharedColours && job.regions.size() == 2) {
      // The negative side's strays are not a colour the garments share: its region points on a
      // top worn untucked make a minority component the positive side explains (kept when the top
      // was found by its edges, pruneLowerModel), and their colour is the top's alone.
      const GaussianMixture& positive = colours_.models[job.regions[0]];
      neutral = sharedColours(positive,
                              withoutBorrowedComponents(colours_.models[job.regions[1]], positive),
                              stage.lab);
      const auto shared = std::count(neutral.begin(), neutral.end(), true);
      if (shared == 0) neutral.clear();
      if (shared > 0)
        pieceNotes_.push_back(fmt::format(
            "boundary {}: {:.1f} % of the vertices have a colour both garments' models hold; "
            "colour pushes neither way there",
            curve.name, 100.0 * static_cast<double>(shared) / static_cast<double>(neutral.size())));
    }
    Eigen::VectorXd phiD =
        smoothedDisplacement(stage.mesh, models, job.positive, stage.lab, options_.colour, neutral);
    BoundaryOptimizer optimizer(stage.mesh, options_.boundary);
    const double w =
        stage.step.size() > 0 && job.geometry ? geometryWeight(job.deltaE, options_.geometry) : 0.0;
    if (job.keepInitial) {
      BoundaryResult& r = run.result;
      r.phi0 = r.phi = optimizer.initialImplicit(f.splines, f.signs);
      r.initial = r.boundary = extractIsoline(stage.mesh, r.phi);
      r.converged = true;
    } else if (w > 0 || (stage.step.size() > 0 && job.geometry && !neutral.empty())) {
      // Colour that cannot tell the sides apart: the steps of the offset join it (body_offset.h),
      // at full weight where the colour is one both sides hold.
      const auto tInit = Clock::now();
      const Eigen::VectorXd phi0 = optimizer.initialImplicit(f.splines, f.signs);
      double high = job.highSide;
      if (high == 0) {
        constexpr double kBand = 0.25;  // m: the steps within a hand's span of the initial curve
        const double o =
            stepOrientation(stage.mesh, stage.offset, stage.step, phi0, kBand, options_.geometry);
        high = o < 0 ? -1.0 : 1.0;  // no step near the curve: the common case, a top worn over
      }
      const double gap = job.offsetRegion >= 0
                             ? regionOffset_[job.offsetRegion] - regionOffset_[kSkin]
                             : 0.0;
      if (gap >= options_.geometry.offsetGap) {
        // Bare skin on the body, the garment off it by its ease: the offset pushes toward the
        // skin side below the skin's level and toward the garment above the garment's.
        phiD += options_.geometry.offsetWeight * w * job.offsetSign *
                offsetDisplacement(stage.smoothOffset, regionOffset_[kSkin],
                                   regionOffset_[job.offsetRegion]);
        geometryNotes_.push_back(fmt::format(
            "boundary {}: the offset from the body joins the displacement (skin at {:.1f} mm, the "
            "garment at {:.1f} mm, medians)",
            curve.name, 1000 * regionOffset_[kSkin], 1000 * regionOffset_[job.offsetRegion]));
      }
      const Eigen::VectorXd step = stepDisplacement(stage.step, high, options_.geometry);
      phiD = combinedDisplacement(phiD, step, w);
      for (size_t v = 0; v < neutral.size(); ++v)
        if (neutral[v]) phiD[v] = std::clamp(phiD[v] + 2 * (1 - w) * step[v], -1.0, 1.0);
      rep.geometryWeight = w;
      rep.highSide = high;
      geometryNotes_.push_back(fmt::format(
          "boundary {}: the two sides' colours {:.1f} ΔE apart, the steps of the offset from the "
          "body weigh {:.2f} beside the colour (outer garment on the {} side)",
          curve.name, job.deltaE, w, high > 0 ? "positive" : "negative"));
      const double initSeconds = secondsSince(tInit);
      run.result = optimizer.iterate(phi0, f.signs, phiD);
      run.result.timings.total += initSeconds;
    } else {
      run.result = optimizer.run(f.splines, f.signs, phiD);
    }
    rep.iterations = run.result.iterations;
    if (!neutral.empty() && !job.keepInitial && !run.result.vanished)
      neutralPlanePass(stage, job, f.signs, neutral, phiD, optimizer, run);
    if (job.gapFilling && !job.keepInitial && !run.result.vanished) {
      // §5.2: a second pass with the normal displacement (Eq. 6), kept when it moves the
      // boundary (a gap was bridged).
      Eigen::VectorXd phiDn =
          normalDisplacement(stage.mesh, run.result.boundary, run.result.phi, 0.25 * height_);
      if (options_.gapOnlyWhereTurnedAway && stage.bodyNormal.rows() > 0)
        onlyWhereTurnedAway(stage.mesh, stage.bodyNormal, phiDn);
      // Eq. (6), except on gap-filling triangles, which push to the side that is not garment
      // (+1) whatever their colour: the paper calls their colours meaningless, and a cap patch in
      // the garment's colour (φ_d = −1) cancelled φ_dn and held the hem on the cap under a long
      // skirt; on a coarse cap the normals near the rim are tilted and φ_dn alone is weak.
      const std::vector<bool> gap =
          gapVertices(stage.mesh, phiDn, underQuery_ ? *underQuery_ : *bodyQuery_,
                      options_.gapReach, stage.lab, run.result.phi, options_.gapSameColourDeltaE,
                      &rep.gapSetDeltaE);
      Eigen::VectorXd phiGap = phiD + phiDn;
      for (int v = 0; v < phiGap.size(); ++v)
        if (gap[v]) phiGap[v] = 1;
      BoundaryResult second = optimizer.iterate(run.result.phi, f.signs, phiGap);
      rep.gapPass = true;
      rep.gapShift = curveShift(second.boundary, run.result.boundary);
      if (!second.vanished && rep.gapShift > options_.gapMinShift) {
        rep.gapApplied = true;
        second.phi0 = run.result.phi0;
        second.initial = run.result.initial;
        rep.iterations += second.iterations;
        run.result = std::move(second);
      }
    }
    // Also when the zero set vanished: φ is then its last state, and the specks of one side it
    // still held (skirt_legs_piece's B(L|S): five bits of curve, 28 mm in all) are not a boundary.
    rep.islandsRemoved = removeIslands(stage.mesh, run.result.phi, options_.minRegionArea, f.signs);
    if (rep.islandsRemoved > 0) run.result.boundary = extractIsoline(stage.mesh, run.result.phi);
    rep.converged = run.result.converged;
    rep.vanished = run.result.vanished;
    rep.timings = run.result.timings;
    rep.initialCurves = curvePolylines(run.result.initial, rep.initialClosed);
    rep.finalCurves = curvePolylines(run.result.boundary, rep.finalClosed);
    rep.otherLabels.assign(rep.finalCurves.size(), job.other);
    return run;
  }

  // A colour both garments hold pushes neither way, and the front can stall in a band of it
  // (segment/hem_plane.h): a second pass lets those vertices push toward the plane of the first
  // pass's curve, the positive garment's side above it, as far as the offset's steps leave them
  // free (a riser that says where the hem is still decides); every other vertex keeps its push.
  // Only the neutral part moves, so its change is measured over that part's area (else a bay
  // filling at α per iteration reads as converged). Kept when it does not vanish.
  void neutralPlanePass(const Stage& stage, const BoundaryJob& job,
                        const std::vector<ValueConstraint>& signs,
                        const std::vector<bool>& neutral, const Eigen::VectorXd& phiD,
                        BoundaryOptimizer& optimizer, BoundaryRun& run) const {
    const std::vector<Vec3>& region = regionPositions_[job.regions[0]];
    const std::optional<FittedPlane> plane = trimmedCurvePlane(run.result.boundary);
    if (!plane || region.empty()) return;
    Vec3 positive = Vec3::Zero();
    for (const Vec3& p : region) positive += p;
    const Eigen::VectorXd toPlane =
        planeDisplacement(stage.mesh, *plane, positive / static_cast<double>(region.size()));
    const Eigen::VectorXd area = vertexAreas(stage.mesh);
    Eigen::VectorXd phiPlane = phiD;
    double neutralArea = 0;
    for (size_t v = 0; v < neutral.size(); ++v) {
      if (!neutral[v]) continue;
      const auto i = static_cast<Eigen::Index>(v);
      phiPlane[i] += (1 - std::abs(phiD[i])) * toPlane[i];
      neutralArea += area[i];
    }
    // Floored at 2 % of the scan: a front jittering by a cell in a few vertices would not stop.
    const double share = std::max(neutralArea / area.sum(), 0.02);
    BoundaryResult second =
        optimizer.iterate(run.result.phi, signs, phiPlane, share * options_.boundary.tolerance);
    if (second.vanished) return;
    run.report.iterations += second.iterations;
    second.phi0 = run.result.phi0;
    second.initial = run.result.initial;
    run.result = std::move(second);
    run.report.planePass = true;
  }

  // A boundary beside cut-away parts of several labels (B(L|S): skin or shoes; B(U|S): skin or
  // hair; a held object's edge: the garments beside it): the reported curves are split where the
  // label beyond them changes, so each piece carries its true label pair. V: #N×3 positions of
  // the vertices on that side, label: #N codes (< 0: not counted). Each boundary point takes the
  // majority label of the counted vertices within `reach` metres (ties and none: the report's
  // own `other`), or its nearest counted vertex's when reach is 0. Runs of one label shorter
  // than kMinRun join their longer neighbour, and curves shorter than it are dropped: a label
  // change is a garment's edge reaching the boundary, not a speck of a few vertices.
  static void splitByLabel(BoundaryReport& rep, const Isoline& iso, const Eigen::MatrixX3d& V,
                           const Eigen::VectorXi& label, double reach) {
    constexpr double kMinRun = 0.01;  // m
    rep.otherLabels.clear();
    rep.finalCurves.clear();
    rep.finalClosed.clear();
    std::vector<int> rows;
    for (int v = 0; v < V.rows(); ++v)
      if (label[v] >= 0) rows.push_back(v);
    const RowCloud cloud{&V, &rows};
    const RowTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    std::vector<std::pair<std::uint32_t, double>> hits;
    const auto labelAt = [&](const Vec3& p) {
      int best = static_cast<int>(rep.other);
      if (rows.empty()) return best;
      if (reach <= 0) {
        std::uint32_t i = 0;
        double d2 = 0;
        tree.knnSearch(p.data(), 1, &i, &d2);
        return label[rows[i]];
      }
      hits.clear();
      tree.radiusSearch(p.data(), reach * reach, hits, nanoflann::SearchParams(32, 0, false));
      std::array<int, kNumLabels> count{};
      for (const auto& [i, d2] : hits) ++count[label[rows[i]]];
      for (int l = 0; l < kNumLabels; ++l)
        if (count[l] > count[best]) best = l;
      return best;
    };
    for (const IsolineCurve& c : iso.curves) {
      const size_t n = c.points.size();
      std::vector<Vec3> positions;
      for (const IsolinePoint& p : c.points) positions.push_back(p.position);
      const std::vector<double> share = arcLengthShares(positions, c.closed);
      if (n < 2 || std::accumulate(share.begin(), share.end(), 0.0) < kMinRun) continue;
      std::vector<int> pointLabel;
      for (const IsolinePoint& p : c.points) pointLabel.push_back(labelAt(p.position));
      mergeShortRuns(pointLabel, share, c.closed, kMinRun);
      // Runs of one label; a closed curve of one label stays closed.
      bool uniform = true;
      for (size_t i = 1; i < n; ++i) uniform &= pointLabel[i] == pointLabel[0];
      if (uniform) {
        Eigen::MatrixX3d P(static_cast<int>(n), 3);
        for (size_t i = 0; i < n; ++i) P.row(static_cast<int>(i)) = c.points[i].position;
        rep.finalCurves.push_back(P);
        rep.finalClosed.push_back(c.closed);
        rep.otherLabels.push_back(static_cast<Label>(pointLabel[0]));
        continue;
      }
      size_t start = 0;  // begin at a label change so that no run wraps around
      if (c.closed)
        while (pointLabel[start] == pointLabel[(start + n - 1) % n]) ++start;
      size_t i = 0;
      while (i < n) {
        std::vector<Vec3> run;
        const int l = pointLabel[(start + i) % n];
        while (i < n && pointLabel[(start + i) % n] == l)
          run.push_back(c.points[(start + i++) % n].position);
        if (i < n || c.closed)
          run.push_back(c.points[(start + i) % n].position);  // join the next run
        Eigen::MatrixX3d P(static_cast<int>(run.size()), 3);
        for (size_t k = 0; k < run.size(); ++k) P.row(static_cast<int>(k)) = run[k];
        rep.finalCurves.push_back(P);
        rep.finalClosed.push_back(false);
        rep.otherLabels.push_back(static_cast<Label>(l));
      }
    }
  }

  // === Held objects and hair (segment/non_garment.h)

  // Objects held against the body (a bag) cut off `current` along their edge and labelled
  // Other; the edge is reported once the garments beside it are known (run).
  void cutHeldObjects(Stage& current, Segmentation& out, LabelAreas& labels) {
    Vec3 axis = Vec3::Zero();
    int n = 0;
    for (int r : {kUpper, kLower})
      for (const Vec3& p : regionPositions_[r]) axis += p, ++n;
    if (n == 0) return;
    axis /= n;
    double level = 0;
    for (int r : {kUpper, kLower})
      if (std::isfinite(regionOffset_[r])) level = std::max(level, regionOffset_[r]);
    double chin = std::numeric_limits<double>::infinity();
    for (const Vec3& p : facePoints()) chin = std::min(chin, p.y());
    double floor = -std::numeric_limits<double>::infinity();
    for (const Vec3& p : footPoints_) floor = std::max(floor, p.y());
    const HeldObjects held = findHeldObjects(current.mesh, current.smoothOffset, axis, level,
                                             options_.held, chin, floor, &current.lab);
    for (double dE : held.garmentColoured)
      out.notes.push_back(fmt::format(
          "a part of the scan standing more than {:.0f} mm off the body has the colour of the scan "
          "beside it (ΔE {:.1f} < {:.1f}): a lump or fold of that garment, not a held object",
          1000 * options_.held.seedOffset, dE, options_.held.sameColourDeltaE));
    if (held.rejectedSeeds > 0)
      out.notes.push_back(fmt::format(
          "{} part(s) of the scan more than {:.0f} mm off the body hang all around it (more than "
          "{:.0f}°): a garment hanging free, not a held object",
          held.rejectedSeeds, 1000 * options_.held.seedOffset, options_.held.maxSpan));
    if (held.objects.empty()) return;
    const CutResult cut = cutAlongIsoline(current.mesh, awayFromZero(held.field, current.mesh));
    labels.add(childStage(current, cut.positive), Label::Other);
    BoundaryReport rep;
    rep.name = "held";
    rep.garment = Label::Other;
    rep.other = Label::Upper;
    rep.converged = true;
    heldReport_ = rep;
    heldBoundary_ = cut.isoline;
    out.heldObjects = held.objects;
    for (const HeldObject& o : held.objects)
      out.notes.push_back(fmt::format(
          "held object cut away (labelled other): {:.3f} m² standing up to {:.0f} mm off the body "
          "under the clothes at ({:.2f}, {:.2f}, {:.2f}) m, {:.0f}° around the body; its edge where "
          "the offset falls to {:.0f} mm (the garments' {:.0f} mm + {:.0f})",
          o.area, 1000 * o.maxOffset, o.centroid.x(), o.centroid.y(), o.centroid.z(), o.span,
          1000 * (level + options_.held.edgeMargin), 1000 * level,
          1000 * options_.held.edgeMargin));
    current = childStage(current, cut.negative);
  }

  // The face's region points: the skin points within a head's reach of the highest (not the
  // hands, wherever the arms are).
  std::vector<Vec3> facePoints() const {
    constexpr double kHead = 0.3;  // m
    const std::vector<Vec3>& skin = regionPositions_[kSkin];
    std::vector<Vec3> out;
    if (skin.empty()) return out;
    const Vec3 top = *std::max_element(skin.begin(), skin.end(),
                                       [](const Vec3& a, const Vec3& b) { return a.y() < b.y(); });
    for (const Vec3& p : skin)
      if ((p - top).norm() < kHead) out.push_back(p);
    return out;
  }

  // A colour model of the hair, from the head's scan that is not this person's skin (hairSeeds),
  // unless it has the top's colours (hair and a top of one colour are not told apart by it).
  void fitHairModel(Segmentation& out) {
    const std::vector<Vec3> face = facePoints();
    const SkinModel skin =
        fitSkinModel(colours_.colours[kSkin], options_.skinSpreadFactor, options_.minSkinDeltaE,
                     options_.sameColourDeltaE);
    const std::vector<int> seeds =
        hairSeeds(scan_, colours_.lab, face, skin, options_.hairOptions);
    if (seeds.empty()) return;
    const Eigen::VectorXd area = vertexAreas(scan_);
    Eigen::MatrixX3d lab(static_cast<int>(seeds.size()), 3);
    for (size_t i = 0; i < seeds.size(); ++i) {
      lab.row(static_cast<int>(i)) = colours_.lab.row(seeds[i]);
      out.hairSeedArea += area[seeds[i]];
    }
    const Vec3 mean = lab.colwise().mean().transpose();
    const auto medianFrom = [&](const Eigen::MatrixX3d& from, const Vec3& to) {
      std::vector<double> d;
      for (int i = 0; i < from.rows(); ++i) d.push_back(deltaE2000(from.row(i).transpose(), to));
      return median(d);
    };
    const double fromUpper = std::max(medianFrom(lab, colours_.means[kUpper]),
                                      medianFrom(colours_.colours[kUpper], mean));
    if (fromUpper < options_.sameColourDeltaE) {
      out.notes.push_back(fmt::format(
          "hair not labelled: the head's {:.3f} m² not of this person's skin has the upper "
          "garment's colour (ΔE {:.1f})",
          out.hairSeedArea, fromUpper));
      return;
    }
    hairModel_ = fitGaussianMixture(lab, options_.colour.gmm);
    Vec3 centre = Vec3::Zero();
    for (const Vec3& p : face) centre += p;
    headCentre_ = centre / static_cast<double>(face.size());
    colours_.models.push_back(*hairModel_);
    colours_.colours.push_back(lab);
    colours_.means.push_back(mean);
  }

  // The skin side of B(U|S) split into hair and bare skin (hairField), cut exactly along the
  // hair's edge; B(U|S)'s curves split into upper|skin and upper|hair, the hair's edge on the
  // skin reported as S|H. Without a hair model all of it is skin.
  void labelSkinSide(const Stage& skin, const Isoline& boundary, BoundaryReport& rep,
                     LabelAreas& labels, Segmentation& out) {
    if (!hairModel_ || skin.mesh.numFaces() == 0) {
      labels.add(skin, Label::Skin);
      return;
    }
    // The face's region points reach the fringe: the skin model's component of hair goes.
    const GaussianMixture bare =
        withoutBorrowedComponents(colours_.models[kSkin], *hairModel_, 0.5);
    Eigen::VectorXd phi =
        hairField(skin.mesh, skin.lab, *hairModel_, bare, headCentre_, options_.hairOptions);
    removeIslands(skin.mesh, phi, options_.minRegionArea, {});
    if (!(phi.array() >= 0).any() || !(phi.array() < 0).any()) {
      const bool all = (phi.array() >= 0).any();
      labels.add(skin, all ? Label::Hair : Label::Skin);
      if (all) out.hairArea = surfaceArea(skin.mesh);
      return;
    }
    const CutResult cut = cutAlongIsoline(skin.mesh, awayFromZero(phi, skin.mesh));
    const Stage hair = childStage(skin, cut.positive);
    labels.add(hair, Label::Hair);
    labels.add(childStage(skin, cut.negative), Label::Skin);
    out.hairArea = surfaceArea(hair.mesh);
    Eigen::VectorXi side(skin.mesh.numVertices());
    for (int v = 0; v < side.size(); ++v)
      side[v] = static_cast<int>(phi[v] >= 0 ? Label::Hair : Label::Skin);
    splitByLabel(rep, boundary, skin.mesh.V, side, 0.0);  // sides exact, by φ's sign
    BoundaryReport h;
    h.name = "S|H";
    h.garment = Label::Hair;
    h.other = Label::Skin;
    h.converged = true;
    h.finalCurves = curvePolylines(cut.isoline, h.finalClosed);
    h.otherLabels.assign(h.finalCurves.size(), Label::Skin);
    hairReport_ = h;
    out.notes.push_back(fmt::format(
        "hair labelled: {:.3f} m² cut away with the skin by B(U|S) (its colour model from {:.3f} "
        "m² of the head not of this person's skin)",
        out.hairArea, out.hairSeedArea));
  }

  // B(U|L) and §5.3: occlusion from where the optimised waist lies against the initial one.
  void splitUpperLower(const Stage& stage, Segmentation& out, LabelAreas& labels) {
    const bool lowerOnly = out.layout == GarmentLayout::LowerOnly;
    const bool upperOnly = out.layout == GarmentLayout::UpperOnly;
    BoundaryJob job{&upperLower_,  {lowerOnly ? kSkin : kUpper, upperOnly ? kSkin : kLower},
                    {true, false}, false,
                    Label::Upper,  Label::Lower};
    job.deltaE = separation(kUpper, kLower);
    job.highSide = 0;  // from the steps: a top worn over the trousers, or tucked in
    job.neutralSharedColours = !lowerOnly && !upperOnly && !tentativeOnePiece_;
    if (lowerOnly) {
      job.garment = Label::Lower;
      job.other = Label::Skin;
      job.deltaE = separation(kLower, kSkin);
      job.highSide = -1;  // skin on the positive side
      job.offsetRegion = kLower;
    } else if (upperOnly) {
      job.other = Label::Skin;
      job.deltaE = separation(kUpper, kSkin);
      job.highSide = 1;  // the top over bare legs
      job.offsetRegion = kUpper;
      job.offsetSign = -1;  // the garment on the positive side
    }
    auto [run, cut] = optimiseAndCut(stage, job);
    if (tentativeOnePiece_) {
      // Upper and lower of one colour: two garments only when the waist boundary found runs
      // along a step of the offset (a hem); otherwise one piece, as §5.3 decides by colour.
      const double support = run.result.vanished
                                 ? 0.0
                                 : hemContrast(stage.mesh, run.result.phi, stage.step,
                                               run.report.highSide, options_.geometry);
      run.report.hemContrast = support;
      if (support < options_.geometry.hemContrast) {
        out.layout = GarmentLayout::OnePiece;
        labels.add(stage, Label::Upper);
        out.garments.push_back(piece("onepiece", Label::Upper, stage));
        for (BoundaryReport& b : out.boundaries)
          if (b.name == lowerSkin_.name) b.garment = Label::Upper;
        out.notes.push_back(fmt::format(
            "one-piece garment: upper and lower body colours within ΔE {:.1f} (§5.3), and no "
            "hem under the waist boundary found (median step {:.2f} mm, a hem shows ≥ {:.1f})",
            out.upperLowerDeltaE, 1000 * support, 1000 * options_.geometry.hemContrast));
        return;
      }
      out.notes.push_back(fmt::format(
          "upper and lower garments of one colour (ΔE {:.1f}) told apart by the hem: the waist "
          "boundary runs along a step of the offset from the body (median {:.2f} mm)",
          out.upperLowerDeltaE, 1000 * support));
    }
    const Label positiveLabel = lowerOnly ? Label::Skin : Label::Upper;
    const Label negativeLabel = upperOnly ? Label::Skin : Label::Lower;
    const Stage positive = childStage(stage, cut.positive),
                negative = childStage(stage, cut.negative);
    labels.add(positive, positiveLabel);
    labels.add(negative, negativeLabel);
    if (lowerOnly) {
      out.garments.push_back(piece("lower", Label::Lower, negative));
    } else if (upperOnly) {
      out.garments.push_back(piece("upper", Label::Upper, positive));
    } else {
      const double shift = meanHeight(run.result.boundary) - meanHeight(run.result.initial);
      GarmentPiece upper = piece("upper", Label::Upper, positive);
      GarmentPiece lower = piece("lower", Label::Lower, negative);
      if (std::abs(shift) >= options_.occlusionShift && !run.result.initial.curves.empty()) {
        // The optimised boundary below the initial one: the upper garment hangs over the lower
        // one, whose hidden part reaches up to the initial boundary (and vice versa).
        out.occlusion = shift < 0 ? Occlusion::LowerOccluded : Occlusion::UpperOccluded;
        const CutResult initialCut =
            cutAlongIsoline(stage.mesh, awayFromZero(run.result.phi0, stage.mesh));
        const bool lowerHidden = out.occlusion == Occlusion::LowerOccluded;
        const CutPart& part = lowerHidden ? initialCut.negative : initialCut.positive;
        GarmentPiece& hidden = lowerHidden ? lower : upper;
        hidden =
            completeOccluded(hidden.name, hidden.label, stage, part, run.result.phi, lowerHidden);
        out.notes.push_back(fmt::format(
            "{} garment occluded: the optimised waist boundary lies {:.0f} mm {} the initial one; "
            "{:.3f} m² completed under the {} garment (§5.3)",
            lowerHidden ? "lower" : "upper", 1000 * std::abs(shift), shift < 0 ? "below" : "above",
            hidden.completedArea, lowerHidden ? "upper" : "lower"));
      }
      out.garments.push_back(std::move(upper));
      out.garments.push_back(std::move(lower));
    }
    out.boundaries.push_back(run.report);
  }

  // The occluded garment cut along the initial boundary; the band the outer garment covers
  // (where the optimised φ says "other garment") is pulled onto the body by a biharmonic
  // deformation with the visible part fixed (Fig. 10).
  GarmentPiece completeOccluded(const std::string& name, Label label, const Stage& stage,
                                const CutPart& part, const Eigen::VectorXd& phiFinal,
                                bool lowerHidden) const {
    const Stage s = childStage(stage, part);
    GarmentPiece p = piece(name, label, s);
    const int n = s.mesh.numVertices();
    std::vector<bool> fixed(n, false);
    std::vector<int> rim;
    std::vector<bool> hiddenVertex(n, false);
    for (int v = 0; v < n; ++v) {
      const VertexOrigin& o = part.vertexOrigin[v];
      const double phi = (1 - o.t) * phiFinal[o.a] + o.t * phiFinal[o.b];
      // Hidden: on the outer garment's side of the optimised boundary.
      const bool hidden = lowerHidden ? phi >= 0 : phi < 0;
      hiddenVertex[v] = hidden;
      if (!o.isOriginal())
        rim.push_back(v);
      else if (!hidden)
        fixed[v] = true;
    }
    if (rim.empty()) return p;
    Eigen::MatrixX3d rimPositions(static_cast<int>(rim.size()), 3);
    for (size_t i = 0; i < rim.size(); ++i)
      rimPositions.row(static_cast<int>(i)) = s.mesh.V.row(rim[i]);
    const std::vector<ClosestHit> onBody = bodyQuery_->closestPoints(rimPositions);
    Eigen::MatrixX3d targets(static_cast<int>(rim.size()), 3);
    for (size_t i = 0; i < rim.size(); ++i)
      targets.row(static_cast<int>(i)) = onBody[i].point.transpose();
    p.mesh.V = biharmonicDeformation(s.mesh, rim, targets, fixed);
    p.occluded = true;
    const Eigen::VectorXd a = faceAreas(p.mesh);
    for (int f = 0; f < p.mesh.numFaces(); ++f) {
      int hidden = 0;
      for (int k = 0; k < 3; ++k) hidden += hiddenVertex[p.mesh.F(f, k)];
      if (hidden >= 2) p.completedArea += a[f];
    }
    return p;
  }

 private:
  const TriMesh& scan_;
  SegmentationOptions options_;
  Progress& progress_;
  double height_ = 1.75;
  double tolerance_ = 1e-7;
  ProjectedCurve upperSkin_, lowerSkin_, upperLower_;
  RegionColours colours_;
  bool hasFootRegion_ = false;
  // Median offset of each region's points from the body under the clothes (m), NaN without it.
  double regionOffset_[4] = {
      std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN(),
      std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  bool regionClothed_[4] = {false, false, false, false};  // offsetSaysClothed per region
  // Upper and lower of one colour with the geometric cues: one piece unless B(U|L) finds a hem.
  bool tentativeOnePiece_ = false;
  // A torso of the skin's colour near the body: bare unless B(U|S) finds a top's edges.
  bool tentativeNoUpper_ = false;
  std::vector<SurfacePoint> upperPoints_;  // projected upper region points (chest and back)
  std::vector<Vec3> footPoints_;  // projected foot region points
  // Projected region points by kSkin..kFoot, on the scan; kHair has none (its seeds are not
  // labelled points and do not vote for pieces).
  std::vector<Vec3> regionPositions_[5];
  int regionPoints_ = 0, droppedRegionPoints_ = 0;
  Stage root_;
  std::unique_ptr<MeshQuery> bodyQuery_;
  // The body under the clothes (§4's fit), when given: the gap test measures against it, since
  // the fully fitted body follows the scan into a loose sleeve and puts its cap on the body.
  std::unique_ptr<MeshQuery> underQuery_;
  std::vector<std::string> projectionNotes_;  // fallbacks of the feature projection
  std::vector<std::string> skipNotes_;        // boundaries skipped (optimiseAndCut)
  std::vector<std::string> pieceNotes_;  // pieces sent to the side their region points say
  std::vector<std::string> geometryNotes_;    // boundaries the geometric cues joined
  std::optional<GaussianMixture> hairModel_;  // fitted from the hair seeds (fitHairModel)
  Vec3 headCentre_ = Vec3::Zero();            // mean of the face's region points
  std::optional<BoundaryReport> hairReport_;  // S|H, the hair's edge on the skin
  std::optional<BoundaryReport> heldReport_;  // the held objects' edge, split once labelled
  Isoline heldBoundary_;
};

}  // namespace

namespace {

Segmentation segmentScanWith(const TriMesh& scan, const Eigen::MatrixX3d& colour,
                             const TriMesh& body, const TriMesh* underBody,
                             const FeatureSet& features, const SegmentationOptions& options,
                             Progress* progress) {
  Progress& p = progress ? *progress : Progress::silent();
  try {
    Segmenter s(scan, colour, body, underBody, features, options, p);
    return s.run();
  } catch (const SolverError& e) {
    if (std::string(e.what()).rfind("segmentation", 0) == 0) throw;  // already restated
    throw stageSolverError(e, "segmentation", fmt::format("the {}-vertex scan", scan.numVertices()),
                           "check the scan with `scan2pattern info`, clean or remesh it, and try "
                           "again");
  }
}

}  // namespace

Segmentation segmentScan(const TriMesh& scan, const Eigen::MatrixX3d& colour, const TriMesh& body,
                         const FeatureSet& features, const SegmentationOptions& options,
                         Progress* progress) {
  return segmentScanWith(scan, colour, body, nullptr, features, options, progress);
}

Segmentation segmentScan(const TriMesh& scan, const Eigen::MatrixX3d& colour, const TriMesh& body,
                         const TriMesh& underBody, const FeatureSet& features,
                         const SegmentationOptions& options, Progress* progress) {
  return segmentScanWith(scan, colour, body, &underBody, features, options, progress);
}

namespace {

Segmentation segmentScanMrfWith(const TriMesh& scan, const Eigen::MatrixX3d& colour,
                                const TriMesh& body, const TriMesh* underBody,
                                const FeatureSet& features, const SegmentationOptions& options,
                                const MrfOptions& mrf, Progress* progress) {
  Progress& p = progress ? *progress : Progress::silent();
  const auto t0 = Clock::now();
  validateMesh(scan, "scan");
  validateMesh(body, "body");
  checkColour(scan, colour);
  Segmentation out;
  out.decided = false;
  p.begin("project features");
  ProjectionOptions popt = options.projection;
  popt.bodyLength = bodyHeight(body);
  const FeatureProjector projector(body, scan, popt);
  const std::vector<std::vector<SurfacePoint>> regions =
      projectRegionPoints(projector, features, out.regionPoints, out.droppedRegionPoints);
  p.end();
  std::vector<MrfRegion> mrfRegions = {{static_cast<int>(Label::Skin), regions[0], true},
                                       {static_cast<int>(Label::Upper), regions[1]},
                                       {static_cast<int>(Label::Lower), regions[2]}};
  if (regions[3].size() >= 4) mrfRegions.push_back({static_cast<int>(Label::Shoes), regions[3]});
  MrfOptions mo = mrf;
  mo.colour = options.colour;
  Eigen::VectorXd offset;
  if (underBody && options.geometry.enabled) {
    // The geometric cues: the offset from the body under the clothes, smoothed over the
    // scanner's noise as the curve method's is (segment/body_offset.h).
    validateMesh(*underBody, "body under the clothes");
    p.begin("offset from the body under the clothes");
    const MeshQuery query(*underBody);
    const Eigen::MatrixXd raw = bodyOffset(scan, query, *underBody);
    offset = smoothOnSurface(scan, raw, options.geometry.noiseLength).col(0);
    out.geometricCues = true;
    p.end();
  }
  p.begin("MRF labelling (graph cut)");
  const MrfResult r = mrfSegmentation(scan, colour, mrfRegions, mo, offset);
  p.end();
  out.vertexLabel = r.vertexLabel;
  out.faceLabel = faceLabelsFromVertices(scan, r.vertexLabel);
  if (out.geometricCues) {
    out.skinOffset = r.skinOffset.mean;
    out.upperOffset = out.lowerOffset = r.clothedOffset.mean;
    out.notes.push_back(fmt::format(
        "MRF geometric cues: offset from the body {:.1f} ± {:.1f} mm on the skin's region points, "
        "{:.1f} ± {:.1f} mm on the others'",
        1000 * r.skinOffset.mean, 1000 * r.skinOffset.sigma, 1000 * r.clothedOffset.mean,
        1000 * r.clothedOffset.sigma));
  }
  out.notes.push_back(
      fmt::format("MRF baseline: {} alpha-expansion sweeps, energy {:.1f}", r.sweeps, r.energy));
  out.seconds = secondsSince(t0);
  return out;
}

}  // namespace

Segmentation segmentScanMrf(const TriMesh& scan, const Eigen::MatrixX3d& colour,
                            const TriMesh& body, const FeatureSet& features,
                            const SegmentationOptions& options, const MrfOptions& mrf,
                            Progress* progress) {
  return segmentScanMrfWith(scan, colour, body, nullptr, features, options, mrf, progress);
}

Segmentation segmentScanMrf(const TriMesh& scan, const Eigen::MatrixX3d& colour,
                            const TriMesh& body, const TriMesh& underBody,
                            const FeatureSet& features, const SegmentationOptions& options,
                            const MrfOptions& mrf, Progress* progress) {
  return segmentScanMrfWith(scan, colour, body, &underBody, features, options, mrf, progress);
}

}  // namespace s2p
