#include "pipeline/drape_stage.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <map>

#include "body/posing.h"
#include "core/error.h"
#include "core/mesh_query.h"
#include "pipeline/pipeline.h"

namespace s2p {

DrapeInput drapeInput(const PatternResult& pattern, std::vector<int>* panelOf) {
  DrapeInput in;
  const Placement& pl = pattern.placement;
  std::vector<int> cloth(pattern.flat.panels.size(), -1);  // pattern panel → cloth panel
  std::vector<int> of;
  for (size_t p = 0; p < pattern.flat.panels.size(); ++p) {
    const FlatPanel& fp = pattern.flat.panels[p];
    if (!fp.error.empty() || fp.remeshed.V.rows() == 0 || p >= pl.panels.size() ||
        !pl.panels[p].placed)
      continue;
    const Panel& panel = pattern.panels.panels[p];
    ClothPanel c;
    c.name = panel.garment + "_" + panel.name;
    c.rest2d = fp.remeshed.V;
    c.start = pl.panels[p].V;
    c.F = fp.remeshed.F;
    cloth[p] = static_cast<int>(in.panels.size());
    of.push_back(static_cast<int>(p));
    in.panels.push_back(std::move(c));
  }
  for (const Stitch& s : pattern.stitches.stitches) {
    const int a = cloth[s.panelA], b = cloth[s.panelB];
    if (a < 0 || b < 0) continue;
    for (const auto& [va, vb] : s.vertices) in.stitches.push_back({a, va, b, vb});
  }
  // On the body under the clothes: the rest body follows the scanned clothes (see Placement).
  in.body = pl.underBody.numFaces() > 0 ? pl.underBody : pl.restBody;
  if (panelOf) *panelOf = std::move(of);
  return in;
}

DrapeInput coarseDrapeInput(const PatternResult& pattern, const std::vector<int>& panelOf,
                            double edge, std::string* why) {
  RemeshOptions ro;
  ro.targetEdgeLength = edge;
  std::vector<std::string> errors;
  const std::vector<RemeshedPanel> meshes = remeshOutlines(pattern.flat, ro, &errors);
  DrapeInput in;
  const Placement& pl = pattern.placement;
  std::vector<int> cloth(pattern.flat.panels.size(), -1);
  for (size_t c = 0; c < panelOf.size(); ++c) {
    const int p = panelOf[c];
    const RemeshedPanel& m = meshes[p];
    const Panel& panel = pattern.panels.panels[p];
    if (m.V.rows() == 0) {
      if (why)
        *why = fmt::format("panel '{} {}' could not be remeshed at {:.0f} mm: {}", panel.garment,
                           panel.name, 1e3 * edge, errors[p]);
      return {};
    }
    ClothPanel cp;
    cp.name = panel.garment + "_" + panel.name;
    cp.rest2d = m.V;
    cp.F = m.F;
    // The placement is rigid: 3D = R·(x, y, 0) + t (placement.h).
    const PlacedPanel& placed = pl.panels[p];
    cp.start = (m.V * placed.R.leftCols<2>().transpose()).rowwise() + placed.t.transpose();
    cloth[p] = static_cast<int>(in.panels.size());
    in.panels.push_back(std::move(cp));
  }
  for (const Stitch& s : pattern.stitches.stitches) {
    const int a = cloth[s.panelA], b = cloth[s.panelB];
    if (a < 0 || b < 0) continue;
    const std::vector<int>& ea = meshes[s.panelA].edgeVertices[s.edgeA];
    const std::vector<int>& eb = meshes[s.panelB].edgeVertices[s.edgeB];
    if (ea.size() != eb.size()) {  // remeshOutlines gives a stitched pair one count
      if (why)
        *why = fmt::format("seam '{}' has {} and {} coarse vertices", s.name, ea.size(), eb.size());
      return {};
    }
    // As makeStitches: vertex k of edge A to vertex n−1−k of edge B.
    for (size_t k = 0, n = ea.size(); k < n; ++k)
      in.stitches.push_back({a, ea[k], b, eb[n - 1 - k]});
  }
  in.body = pl.underBody.numFaces() > 0 ? pl.underBody : pl.restBody;
  return in;
}

// Layers from the segmentation: a garment whose hidden part was completed (§5.3) lies under the
// garment that hid it, so its panels are the inner layer (0) and the others the outer (1). With
// no garment completed nothing says which is on top, and all panels share one layer.
namespace {
void assignLayers(DrapeInput& in, const PatternResult& pattern, const std::vector<int>& panelOf,
                  const Segmentation& segmentation) {
  std::vector<std::string> under;
  for (const GarmentPiece& piece : segmentation.garments)
    if (piece.occluded) under.push_back(piece.name);
  if (under.empty()) return;
  for (size_t c = 0; c < in.panels.size() && c < panelOf.size(); ++c) {
    const std::string& g = pattern.panels.panels[panelOf[c]].garment;
    in.panels[c].layer = std::find(under.begin(), under.end(), g) == under.end() ? 1 : 0;
  }
}
}  // namespace

Eigen::MatrixX3d toDrapePose(const Eigen::MatrixX3d& P, const PosedFeatures& body,
                             const Placement& placement) {
  if (!body.model) throw InputError("drape: the fitted body has no model to unpose the garments");
  const BodyModel& model = *body.model;
  const PosedBody fitted = poseBody(model, body.params);
  const Eigen::VectorXd& shape = body.params.shape;
  if (placement.drapePose.axisAngle.rows() != model.numJoints())
    throw InputError("drape: the placement carries no drape pose for this body model");
  const PosedBody drape = poseBody(model, {shape, placement.drapePose});
  // Placement's shift into the rest frame (feet on y = 0, pelvis above the origin).
  const Eigen::RowVector3d shift = placement.canonical.row(0) - drape.canonical.row(0);
  // Garment frame → the parameters' frame, where the fitted body is posed.
  const Eigen::MatrixX3d Q = (body.toGarments.inverse() * P.transpose()).transpose();
  const Eigen::SparseMatrix<double, Eigen::RowMajor> W = closestPointWeights(model, fitted.mesh, Q);
  Eigen::MatrixX3d out = poseSkinned(drape, W, unposeSkinned(fitted, W, Q));
  out.rowwise() += shift;
  return out;
}

DrapeStage runDrapeStage(const PatternResult& pattern, const Segmentation& segmentation,
                         const PosedFeatures& body, const DrapeStageOptions& options,
                         Progress* progress) {
  const auto t0 = std::chrono::steady_clock::now();
  DrapeStage out;
  if (!options.enabled) return out;
  if (pattern.placement.panels.empty() || pattern.placement.restBody.numFaces() == 0) {
    out.warnings.push_back("drape: skipped, the pattern was not placed around a rest body");
    return out;
  }
  DrapeInput in = drapeInput(pattern, &out.panelOf);
  assignLayers(in, pattern, out.panelOf, segmentation);
  if (in.panels.empty()) {
    out.warnings.push_back("drape: skipped, no panel was flattened and placed");
    return out;
  }
  // Coarse to fine when the coarse mesh has markedly fewer vertices than the pattern's own.
  DrapeInput coarse;
  std::string why;
  if (options.coarseEdge > 0)
    coarse = coarseDrapeInput(pattern, out.panelOf, options.coarseEdge, &why);
  assignLayers(coarse, pattern, out.panelOf, segmentation);
  int fineVertices = 0;
  for (const ClothPanel& p : in.panels) fineVertices += p.numVertices();
  for (const ClothPanel& p : coarse.panels) out.coarseVertices += p.numVertices();
  if (options.coarseEdge > 0 && coarse.panels.empty())
    out.warnings.push_back(
        fmt::format("drape: sewn at the pattern's own resolution only ({})", why));
  if (!coarse.panels.empty() && 2 * out.coarseVertices < fineVertices) {
    out.twoLevel = runDrapeCoarseToFine(in, coarse, options.drape, options.coarseToFine, progress);
    out.drape = std::move(out.twoLevel.fine);
    out.twoLevel.fine = DrapeResult{};
    out.coarseToFine = true;
    if (out.twoLevel.carried)
      for (const std::string& w : out.twoLevel.coarse.warnings)
        out.warnings.push_back(fmt::format("coarse ({:.0f} mm) {}", 1e3 * options.coarseEdge, w));
  } else {
    out.drape = runDrape(in, options.drape, progress);
    out.coarseVertices = 0;
  }
  out.ran = true;
  for (const std::string& w : out.drape.warnings) out.warnings.push_back(w);

  if (progress) progress->begin("unpose the scanned garments, compare the drape with them");
  // Per garment: its cloth panels (vertices as in drape.garment) against its scanned mesh.
  std::map<std::string, int> index;
  out.garmentOf.assign(out.panelOf.size(), -1);
  for (size_t c = 0; c < out.panelOf.size(); ++c) {
    const std::string& g = pattern.panels.panels[out.panelOf[c]].garment;
    const auto found = index.find(g);
    if (found != index.end()) {
      out.garmentOf[c] = found->second;
      continue;
    }
    for (const GarmentPiece& piece : segmentation.garments)
      if (piece.name == g && piece.mesh.numFaces() > 0) {
        index[g] = static_cast<int>(out.garments.size());
        out.garmentOf[c] = index[g];
        GarmentDrape gd;
        gd.garment = g;
        gd.scanned = TriMesh(toDrapePose(piece.mesh.V, body, pattern.placement), piece.mesh.F);
        out.garments.push_back(std::move(gd));
        break;
      }
  }
  // Only a sewn garment at rest is a drape to measure and write: a failed or unsettled run is
  // reported as such (its positions say nothing about the pattern), the pattern files unaffected.
  if (out.drape.status != DrapeStatus::Settled || !out.drape.garment.V.allFinite()) {
    out.warnings.push_back(fmt::format(
        "drape: {}: no draped garment written or measured (the pattern files are unaffected)",
        out.drape.status == DrapeStatus::Failed ? "the simulation failed"
        : out.drape.seamsClosed                 ? "the cloth did not settle in its step budget"
                                                : "the seams did not close in the step budgets"));
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  }
  for (size_t g = 0; g < out.garments.size(); ++g) {
    GarmentDrape& gd = out.garments[g];
    std::vector<int> map(out.drape.garment.numVertices(), -1);
    int nv = 0, nf = 0;
    for (size_t c = 0; c < out.panelOf.size(); ++c)
      if (out.garmentOf[c] == static_cast<int>(g)) {
        for (int v = out.drape.panelOffset[c]; v < out.drape.panelOffset[c + 1]; ++v) map[v] = nv++;
        nf += in.panels[c].numFaces();
      }
    gd.draped.V.resize(nv, 3);
    gd.draped.F.resize(nf, 3);
    for (int v = 0; v < out.drape.garment.numVertices(); ++v)
      if (map[v] >= 0) gd.draped.V.row(map[v]) = out.drape.garment.V.row(v);
    int f = 0;
    for (int k = 0; k < out.drape.garment.numFaces(); ++k) {
      const int a = map[out.drape.garment.F(k, 0)];
      if (a < 0) continue;
      gd.draped.F.row(f++) << a, map[out.drape.garment.F(k, 1)], map[out.drape.garment.F(k, 2)];
    }
    gd.comparison = compareMeshes(gd.draped, gd.scanned);
    gd.topDropMm = topDropMm(gd.draped, gd.scanned, Eigen::Vector3d::UnitY());
    // As far as a close-fitting garment's p95 may be from the scan (issue 19): beyond it the
    // garment has slid, and the distances above say more about what holds it than about its cut.
    constexpr double kSlidMm = 30;
    if (gd.topDropMm > kSlidMm)
      out.warnings.push_back(fmt::format(
          "drape: garment '{}' hangs {:.0f} mm below where it was scanned (its top edge): nothing "
          "holds it there in the simulation. A top without straps wider than the chest, straps "
          "or shoulders the scan did not join front to back, or a waist looser than the body "
          "slide down; the scanned garment was held by something the pattern does not have",
          gd.garment, gd.topDropMm));
    // Per panel region: its block of draped vertices (panels are concatenated in cloth order).
    for (size_t c = 0, v0 = 0; c < out.panelOf.size(); ++c) {
      if (out.garmentOf[c] != static_cast<int>(g)) continue;
      const ClothPanel& cp = in.panels[c];
      const TriMesh panel(gd.draped.V.middleRows(static_cast<int>(v0), cp.numVertices()), cp.F);
      gd.panels.emplace_back(
          cp.name, distanceStats(panel, gd.comparison.distanceA.segment(static_cast<int>(v0),
                                                                        cp.numVertices())));
      v0 += cp.numVertices();
    }
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace s2p
