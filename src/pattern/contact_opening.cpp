#include "pattern/contact_opening.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include "core/mesh_topology.h"
#include "core/shapes.h"
#include "pattern/loop_fill.h"
#include "segment/mesh_cut.h"

namespace s2p {

namespace {

using Vec3 = Eigen::Vector3d;

// One connected piece of the isoline of a refined mesh (the edges between a face of each side).
struct IsolinePiece {
  std::vector<std::pair<int, int>> edges;  // refined-mesh vertex pairs
  std::vector<int> cycle;  // the vertices in order round the loop; empty when the piece is not
                           // one loop (it ends on the border or touches itself)
};

std::vector<IsolinePiece> isolinePieces(const RefinedMesh& r, const MeshTopology& topo) {
  const int nV = r.mesh.numVertices();
  std::vector<std::vector<int>> adj(nV);
  for (int e = 0; e < topo.numEdges(); ++e) {
    const std::vector<int> ef = topo.edgeFaces(e);
    if (ef.size() != 2 || r.faceSide[ef[0]] == r.faceSide[ef[1]]) continue;
    adj[topo.edges()(e, 0)].push_back(topo.edges()(e, 1));
    adj[topo.edges()(e, 1)].push_back(topo.edges()(e, 0));
  }
  std::vector<IsolinePiece> pieces;
  std::vector<char> seen(nV, 0);
  for (int s = 0; s < nV; ++s) {
    if (adj[s].empty() || seen[s]) continue;
    std::vector<int> component{s};
    seen[s] = 1;
    for (size_t i = 0; i < component.size(); ++i)
      for (int w : adj[component[i]])
        if (!seen[w]) {
          seen[w] = 1;
          component.push_back(w);
        }
    IsolinePiece piece;
    for (int v : component)
      for (int w : adj[v])
        if (v < w) piece.edges.emplace_back(v, w);
    if (std::all_of(component.begin(), component.end(),
                    [&](int v) { return adj[v].size() == 2; })) {
      piece.cycle.push_back(s);
      for (int prev = s, cur = adj[s][0]; cur != s;) {
        piece.cycle.push_back(cur);
        const int next = adj[cur][0] == prev ? adj[cur][1] : adj[cur][0];
        prev = cur;
        cur = next;
      }
    }
    pieces.push_back(std::move(piece));
  }
  return pieces;
}

// One contact to open: the crease part of an arm's armhole loop, tip to tip through its lowest
// point (refined-mesh vertex ids).
struct Crease {
  std::string side;
  std::vector<int> chain;  // chain.front(), chain.back(): the tips, at the contact's top
  double drop = 0;
};

}  // namespace

ContactOpening openFusedContacts(const TriMesh& garment, const Eigen::VectorXi& faceOrigin,
                                 const SeamLine& armhole,
                                 const std::array<double, 2>& armpitHeights, const BodyFrame& frame,
                                 const SeamOptions& seamOptions,
                                 const ContactOpeningOptions& options) {
  ContactOpening out;
  out.mesh = garment;
  out.faceOrigin = faceOrigin;
  if (!armhole.kept || armhole.phi.size() != garment.numVertices()) return out;
  const std::vector<SeamFold> folds = armholeFolds(garment, armhole, seamOptions);
  if (folds.empty()) return out;
  const MeshTopology topo(garment.F, garment.numVertices());
  const RefinedMesh r = refineAlongIsoline(garment, topo, armhole.phi);
  const MeshTopology rt(r.mesh.F, r.mesh.numVertices());
  const auto P = [&](int v) -> Vec3 { return r.mesh.V.row(v).transpose(); };
  // A segment of the loop is on a fold when armholeFolds named it (same isoline, same points).
  std::vector<Vec3> foldMid;
  for (const SeamFold& f : folds) foldMid.push_back(0.5 * (f.a + f.b));
  const auto onFold = [&](int a, int b) {
    const Vec3 mid = 0.5 * (P(a) + P(b));
    for (const Vec3& m : foldMid)
      if ((m - mid).squaredNorm() < 1e-10) return true;
    return false;
  };

  std::vector<Crease> creases;
  for (const IsolinePiece& piece : isolinePieces(r, rt)) {
    // The fold's extent along the piece, and the piece's side.
    double top = -std::numeric_limits<double>::infinity(),
           low = std::numeric_limits<double>::infinity();
    Vec3 c = Vec3::Zero();
    for (const auto& [a, b] : piece.edges) {
      c += P(a) + P(b);
      if (!onFold(a, b)) continue;
      top = std::max({top, frame.height(P(a)), frame.height(P(b))});
      low = std::min({low, frame.height(P(a)), frame.height(P(b))});
    }
    const std::string side = frame.side(c / (2.0 * std::max<size_t>(1, piece.edges.size())));
    if (!(top - low >= options.minDrop)) continue;  // no fold, or a rounded armpit
    // The contact lies below the body's armpit, where arm and torso are apart; above it they
    // are one, and a fold there is the arm's root, where an armhole belongs.
    const double armpit = armpitHeights[side == "left" ? 0 : 1];
    if (std::isfinite(armpit)) top = std::min(top, armpit);
    if (top - low < options.minDrop) continue;  // the arm's root: no contact below
    const std::vector<int>& cycle = piece.cycle;
    const int n = static_cast<int>(cycle.size());
    if (n < 4) {
      out.notes.push_back(fmt::format(
          "{} armhole: it follows a fold {:.0f} mm below the armpit, but its line does not close "
          "round the arm (it runs into an opening: a cuff the scan joined to the hem?); left "
          "fused",
          side, 1000 * (top - low)));
      continue;
    }
    std::vector<double> h(n);
    for (int i = 0; i < n; ++i) h[i] = frame.height(P(cycle[i]));
    // The crease: the stretch of the loop below that top around the loop's lowest point.
    const int lowest = static_cast<int>(std::min_element(h.begin(), h.end()) - h.begin());
    if (top - h[lowest] < options.minDrop) continue;
    int a = lowest, b = lowest, steps = 0;
    while (h[(a + n - 1) % n] < top && steps++ < n) a = (a + n - 1) % n;
    while (h[(b + 1) % n] < top && steps++ < n) b = (b + 1) % n;
    a = (a + n - 1) % n;  // the tips: the first points at the top on each side
    b = (b + 1) % n;
    if (steps >= n || a == b) {
      out.notes.push_back(fmt::format(
          "{} armhole: its whole loop lies below the top of its fold; left fused", side));
      continue;
    }
    Crease crease;
    crease.side = side;
    crease.drop = top - h[lowest];
    for (int i = a;; i = (i + 1) % n) {
      crease.chain.push_back(cycle[i]);
      if (i == b) break;
    }
    if (crease.chain.size() < 3) continue;
    bool reachesEdge = false;
    for (int v : crease.chain) reachesEdge |= rt.isBoundaryVertex()[v];
    if (reachesEdge) {
      out.notes.push_back(fmt::format(
          "{} armhole: its crease reaches the garment's edge (the contact runs into the cuff); "
          "left fused",
          side));
      continue;
    }
    creases.push_back(std::move(crease));
  }
  if (creases.empty()) return out;

  // The median edge of the garment sets the patches' spacing.
  std::vector<double> lengths;
  for (int e = 0; e < topo.numEdges(); ++e)
    lengths.push_back(
        (garment.V.row(topo.edges()(e, 0)) - garment.V.row(topo.edges()(e, 1))).norm());
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  const double spacing =
      std::clamp(lengths[lengths.size() / 2], options.minSpacing, options.maxSpacing);

  std::vector<Vec3> V;
  for (int v = 0; v < r.mesh.numVertices(); ++v) V.push_back(P(v));
  std::vector<Eigen::Vector3i> F;
  std::vector<int> origin;
  for (int f = 0; f < r.mesh.numFaces(); ++f) {
    F.push_back(r.mesh.F.row(f).transpose());
    origin.push_back(faceOrigin[r.faceOrigin[f]]);
  }
  const auto addVertex = [&](const Vec3& p) {
    V.push_back(p);
    return static_cast<int>(V.size()) - 1;
  };
  for (const Crease& crease : creases) {
    const std::vector<int>& chain = crease.chain;
    std::vector<Vec3> chainP;
    for (int v : chain) chainP.push_back(P(v));
    const Vec3 tipA = chainP.front(), tipB = chainP.back();
    const int segments = std::max(1, static_cast<int>(std::ceil((tipA - tipB).norm() / spacing)));
    std::vector<Vec3> line;  // from tip B back to tip A, inner samples
    for (int j = 1; j < segments; ++j)
      line.push_back(tipB + (tipA - tipB) * (static_cast<double>(j) / segments));
    std::vector<Vec3> outline = chainP;  // the crease, then the line under the arm back
    outline.insert(outline.end(), line.begin(), line.end());
    std::string why;
    const std::optional<LoopFill> patch = fillLoop(outline, spacing, &why);
    if (!patch) {
      out.notes.push_back(fmt::format("{} armhole: its crease cannot be closed ({}); left fused",
                                      crease.side, why));
      continue;
    }
    // The faces holding the crease's first edge (tip A → chain[1]), one on each side.
    int sleeveLipFace = -1, trunkLipFace = -1;
    for (int f : rt.vertexFaces(chain[0]))
      if ((r.mesh.F.row(f).array() == chain[1]).any())
        (r.faceSide[f] == 0 ? sleeveLipFace : trunkLipFace) = f;
    if (trunkLipFace < 0 || sleeveLipFace < 0) {
      out.notes.push_back(
          fmt::format("{} armhole: its crease has no cloth on one side; left fused", crease.side));
      continue;
    }
    // The sleeve's faces along the chain get their own copies of its inner vertices.
    std::map<int, int> sleeveCopy;
    Vec3 sleeveCentre = Vec3::Zero();
    int sleeveFaces = 0;
    for (size_t i = 1; i + 1 < chain.size(); ++i) sleeveCopy[chain[i]] = addVertex(chainP[i]);
    for (size_t i = 1; i + 1 < chain.size(); ++i)
      for (int f : rt.vertexFaces(chain[i])) {
        if (r.faceSide[f] != 0) continue;
        for (int k = 0; k < 3; ++k) {
          const auto it = sleeveCopy.find(F[f][k]);
          if (it != sleeveCopy.end()) F[f][k] = it->second;
        }
        sleeveCentre += (P(r.mesh.F(f, 0)) + P(r.mesh.F(f, 1)) + P(r.mesh.F(f, 2))) / 3;
        ++sleeveFaces;
      }
    const Vec3 chainCentre = 0.5 * (tipA + tipB);
    const double toArm =
        (sleeveCentre / sleeveFaces - chainCentre).dot(patch->normal) >= 0 ? 1 : -1;
    std::vector<int> lineIds;
    for (const Vec3& p : line) lineIds.push_back(addVertex(p));
    OpenedContact opened;
    opened.side = crease.side;
    opened.drop = crease.drop;
    opened.topWidth = (tipA - tipB).norm();
    for (size_t i = 0; i + 1 < chainP.size(); ++i)
      opened.creaseLength += (chainP[i + 1] - chainP[i]).norm();
    for (const bool sleeve : {true, false}) {
      const double offset = (sleeve ? 0.5 : -0.5) * toArm * options.separation;
      std::vector<int> id(patch->V.rows());
      const int chainCount = static_cast<int>(chain.size());
      const int nB = chainCount + static_cast<int>(line.size());
      for (int i = 0; i < chainCount; ++i) {
        const int v = chain[i];
        id[i] = sleeve && sleeveCopy.count(v) ? sleeveCopy.at(v) : v;
      }
      for (size_t i = 0; i < line.size(); ++i) id[chainCount + i] = lineIds[i];
      std::vector<Vec3> hinted;
      for (int v = nB; v < patch->V.rows(); ++v) {
        id[v] = addVertex(patch->V.row(v).transpose() + offset * patch->bump[v] * patch->normal);
        if (patch->bump[v] < options.hintBump) continue;
        const Vec3& p = V[id[v]];
        if (std::any_of(hinted.begin(), hinted.end(),
                        [&](const Vec3& q) { return (p - q).norm() < options.hintSpacing; }))
          continue;
        hinted.push_back(p);
        out.hints.push_back({p, sleeve ? -1.0 : 1.0});
      }
      // Orientation: the patch runs the lip's first edge the other way from the cloth beside it.
      const int lipFace = sleeve ? sleeveLipFace : trunkLipFace;
      const int a = id[0], b = id[1];
      bool clothAB = false;
      for (int k = 0; k < 3; ++k) clothAB |= F[lipFace][k] == a && F[lipFace][(k + 1) % 3] == b;
      bool patchAB = false;
      for (int f = 0; f < patch->F.rows(); ++f)
        for (int k = 0; k < 3; ++k) patchAB |= patch->F(f, k) == 0 && patch->F(f, (k + 1) % 3) == 1;
      double area = 0;
      for (int f = 0; f < patch->F.rows(); ++f) {
        Eigen::Vector3i t(id[patch->F(f, 0)], id[patch->F(f, 1)], id[patch->F(f, 2)]);
        if (clothAB == patchAB) std::swap(t[1], t[2]);
        area += 0.5 * (V[t[1]] - V[t[0]]).cross(V[t[2]] - V[t[0]]).norm();
        F.push_back(t);
        origin.push_back(origin[lipFace]);
      }
      (sleeve ? opened.sleeveArea : opened.trunkArea) = area;
    }
    out.opened.push_back(opened);
  }
  if (out.opened.empty()) return out;

  // Assembled (any vertex no face uses dropped); a result that is not a manifold is not used.
  TriMesh m;
  m.V.resize(static_cast<int>(V.size()), 3);
  for (size_t v = 0; v < V.size(); ++v) m.V.row(static_cast<int>(v)) = V[v].transpose();
  m.F.resize(static_cast<int>(F.size()), 3);
  for (size_t f = 0; f < F.size(); ++f) m.F.row(static_cast<int>(f)) = F[f].transpose();
  removeUnreferencedVertices(m);
  const MeshTopology mt(m.F, m.numVertices());
  if (!mt.manifoldness().isManifold()) {
    out.notes.push_back(fmt::format(
        "the contact(s) under the arm were not opened: the completed garment was not a manifold "
        "({} non-manifold edges, {} vertices)",
        mt.manifoldness().nonManifoldEdges.size(), mt.manifoldness().nonManifoldVertices.size()));
    out.opened.clear();
    out.hints.clear();
    return out;
  }
  out.mesh = std::move(m);
  out.faceOrigin =
      Eigen::Map<const Eigen::VectorXi>(origin.data(), static_cast<int>(origin.size()));
  return out;
}

}  // namespace s2p
