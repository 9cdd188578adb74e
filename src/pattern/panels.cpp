#include "pattern/panels.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <exception>
#include <functional>
#include <map>
#include <numeric>
#include <optional>
#include <queue>
#include <set>
#include <unordered_map>

#include "core/error.h"
#include "core/mesh_query.h"
#include "core/mesh_topology.h"
#include "core/shapes.h"
#include "pattern/contact_opening.h"
#include "segment/mesh_cut.h"

namespace s2p {

namespace {

using Vec3 = Eigen::Vector3d;

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  }
  void join(int a, int b) { parent[find(a)] = find(b); }
};

// The garment with every kept seam's isoline inserted (one mesh, faces on one side of each).
struct SeamedGarment {
  TriMesh mesh;
  Eigen::VectorXi garmentFace;          // #F: the garment face each face lies in
  std::vector<Eigen::VectorXd> fields;  // per kept seam, #V
  std::vector<Eigen::VectorXi> sides;   // per kept seam, #F: 1 on its positive side
  std::vector<const SeamLine*> seams;   // the kept seams, in order
};

SeamedGarment insertSeams(const TriMesh& garment, const std::vector<SeamLine>& seams) {
  SeamedGarment g;
  g.mesh = garment;
  g.garmentFace = Eigen::VectorXi::LinSpaced(garment.numFaces(), 0, garment.numFaces() - 1);
  for (const SeamLine& s : seams)
    if (s.kept) {
      g.seams.push_back(&s);
      g.fields.push_back(s.phi);
    }
  for (size_t k = 0; k < g.seams.size(); ++k) {
    g.fields[k] = awayFromZero(g.fields[k], g.mesh);
    const MeshTopology topo(g.mesh.F, g.mesh.numVertices());
    RefinedMesh r = refineAlongIsoline(g.mesh, topo, g.fields[k]);
    for (Eigen::VectorXd& f : g.fields) f = carryToVertices(r.vertexOrigin, f);
    for (Eigen::VectorXi& s : g.sides) s = s(r.faceOrigin).eval();
    g.sides.push_back(r.faceSide);
    g.garmentFace = g.garmentFace(r.faceOrigin).eval();
    g.mesh = std::move(r.mesh);
  }
  return g;
}

// A panel's faces taken out of the seamed garment: vertices shared by faces of the panel are
// one vertex unless the faces meet only across cut edges.
struct PanelMesh {
  TriMesh mesh;
  std::vector<int> globalVertex;  // #V of the panel → seamed-garment vertex
  std::vector<int> globalFace;    // #F of the panel → seamed-garment face
};

PanelMesh extractPanel(const TriMesh& m, const MeshTopology& topo, const std::vector<int>& faces,
                       const std::vector<int>& panelOf, int panel,
                       const std::vector<char>& cutEdge) {
  const int n = static_cast<int>(faces.size());
  std::vector<int> local(m.numFaces(), -1);
  for (int i = 0; i < n; ++i) local[faces[i]] = i;
  UnionFind uf(3 * n);
  const auto corner = [&](int i, int v) {
    const int f = faces[i];
    for (int k = 0; k < 3; ++k)
      if (m.F(f, k) == v) return 3 * i + k;
    return -1;
  };
  for (int i = 0; i < n; ++i) {
    const int f = faces[i];
    for (int k = 0; k < 3; ++k) {
      const int e = topo.faceEdges()(f, k);
      if (cutEdge[e]) continue;
      const std::vector<int> ef = topo.edgeFaces(e);
      if (ef.size() != 2) continue;
      const int g = ef[0] == f ? ef[1] : ef[0];
      if (panelOf[g] != panel || local[g] < 0) continue;
      const int a = m.F(f, (k + 1) % 3), b = m.F(f, (k + 2) % 3);
      uf.join(3 * i + (k + 1) % 3, corner(local[g], a));
      uf.join(3 * i + (k + 2) % 3, corner(local[g], b));
    }
  }
  PanelMesh out;
  std::vector<int> id(3 * n, -1);
  out.mesh.F.resize(n, 3);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      const int r = uf.find(3 * i + k);
      if (id[r] < 0) {
        id[r] = static_cast<int>(out.globalVertex.size());
        out.globalVertex.push_back(m.F(faces[i], k));
      }
      out.mesh.F(i, k) = id[r];
    }
  out.mesh.V.resize(static_cast<int>(out.globalVertex.size()), 3);
  for (size_t v = 0; v < out.globalVertex.size(); ++v)
    out.mesh.V.row(static_cast<int>(v)) = m.V.row(out.globalVertex[v]);
  out.globalFace = faces;
  return out;
}

// Fraction of 8 horizontal camera directions from which each vertex is seen (its normal faces
// the direction and a ray from it meets neither the garment nor the body).
Eigen::VectorXd horizontalVisibility(const TriMesh& m, const TriMesh& body,
                                     const BodyFrame& frame) {
  const MeshQuery garmentQuery(m), bodyQuery(body);
  const Eigen::MatrixX3d N = vertexNormals(m);
  const double eps = 1e-3 * std::max(meanEdgeLength(m), 1e-4);
  Eigen::VectorXd vis = Eigen::VectorXd::Zero(m.numVertices());
  for (int v = 0; v < m.numVertices(); ++v) {
    const Vec3 p = m.V.row(v).transpose(), n = N.row(v).transpose();
    int seen = 0;
    for (int i = 0; i < 8; ++i) {
      const double a = i * M_PI / 4;
      const Vec3 d = std::cos(a) * frame.front() + std::sin(a) * frame.left();
      if (n.dot(d) <= 0.1) continue;
      const Vec3 o = p + eps * n;
      if (garmentQuery.rayCast(o, d, eps)) continue;
      if (bodyQuery.rayCast(o, d, 0)) continue;
      ++seen;
    }
    vis[v] = seen / 8.0;
  }
  return vis;
}

// The cheapest path of interior edges from boundary loop `from` to any other loop of a panel;
// its edges as panel vertex pairs. Empty when there is none.
std::vector<std::pair<int, int>> cheapestCut(const TriMesh& panel, const MeshTopology& topo,
                                             const Eigen::VectorXd& vertexCost) {
  const auto& loops = topo.boundaryLoops();
  const int nV = panel.numVertices();
  std::vector<int> loopOf(nV, -1);
  for (size_t l = 0; l < loops.size(); ++l)
    for (int v : loops[l]) loopOf[v] = static_cast<int>(l);
  std::vector<std::vector<int>> adj(nV);
  for (int e = 0; e < topo.numEdges(); ++e) {
    if (topo.isBoundaryEdge(e)) continue;
    adj[topo.edges()(e, 0)].push_back(topo.edges()(e, 1));
    adj[topo.edges()(e, 1)].push_back(topo.edges()(e, 0));
  }
  std::vector<double> dist(nV, std::numeric_limits<double>::infinity());
  std::vector<int> prev(nV, -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> q;
  for (int v : loops[0]) {
    dist[v] = 0;
    q.push({0, v});
  }
  int target = -1;
  while (!q.empty()) {
    const auto [d, v] = q.top();
    q.pop();
    if (d > dist[v]) continue;
    if (loopOf[v] > 0) {
      target = v;
      break;
    }
    // Only the start loop's vertices and interior vertices are passed through.
    if (loopOf[v] == 0 && prev[v] >= 0) continue;
    for (int w : adj[v]) {
      if (loopOf[w] == 0) continue;
      const double len = (panel.V.row(v) - panel.V.row(w)).norm();
      const double nd = d + len * 0.5 * (vertexCost[v] + vertexCost[w]);
      if (nd < dist[w]) {
        dist[w] = nd;
        prev[w] = v;
        q.push({nd, w});
      }
    }
  }
  std::vector<std::pair<int, int>> path;
  for (int v = target; v >= 0 && prev[v] >= 0; v = prev[v]) path.push_back({prev[v], v});
  return path;
}

Vec3 facesCentroid(const TriMesh& m, const std::vector<int>& faces) {
  Vec3 c = Vec3::Zero();
  double w = 0;
  for (int f : faces) {
    const Vec3 p = m.V.row(m.F(f, 0)), q = m.V.row(m.F(f, 1)), r = m.V.row(m.F(f, 2));
    const double a = 0.5 * (q - p).cross(r - p).norm();
    c += a * (p + q + r) / 3;
    w += a;
  }
  return w > 0 ? Vec3(c / w) : c;
}

class GarmentPanelizer {
 public:
  GarmentPanelizer(const PanelsInput& in, const PanelsInput::Garment& garment, int garmentIndex,
                   const BodyFrame& frame, const PanelOptions& options, PanelsResult& result)
      : in_(in),
        garment_(garment),
        index_(garmentIndex),
        frame_(frame),
        options_(options),
        result_(result) {}

  void run(std::optional<std::vector<SeamLine>> seams = std::nullopt) {
    GarmentPanels gp;
    gp.name = garment_.name;
    gp.kind = garment_.kind;
    const TriMesh& mesh = garment_.mesh;
    if (mesh.numFaces() == 0)
      throw InputError(
          fmt::format("pattern: garment '{}' has no faces; the segmentation found "
                      "nothing of it (check segment/)",
                      garment_.name));
    validateMesh(mesh, fmt::format("garment '{}'", garment_.name));
    if (garment_.faceOrigin.size() != mesh.numFaces())
      throw InputError(fmt::format("pattern: garment '{}' has {} faces but {} scan-face entries",
                                   garment_.name, mesh.numFaces(), garment_.faceOrigin.size()));
    if (options_.trimInside && !seams) trimInside(gp);
    const MeshTopology topo(mesh.F, mesh.numVertices());
    if (!topo.manifoldness().isManifold())
      throw TopologyError(fmt::format(
          "pattern: garment '{}' is not a manifold mesh ({} non-manifold edges, {} vertices); "
          "seams cannot be traced on it. Clean the scan (scan2pattern convert) and rerun",
          garment_.name, topo.manifoldness().nonManifoldEdges.size(),
          topo.manifoldness().nonManifoldVertices.size()));
    gp.openings = classifyOpenings(mesh, topo, garment_.kind, frame_);
    if (seams) {
      gp.seams = std::move(*seams);
    } else {
      // The armhole first: where it shows a fused contact, the garment is completed and every
      // seam is found on that instead; the fused garment's other seams are then not needed.
      SeamEstimator estimator(mesh, garment_.kind, in_.body, in_.features, gp.openings,
                              options_.seams, in_.bodyLimbWeight);
      const SeamLine* armhole = estimator.seam(SeamKind::Armhole);
      const bool opened = options_.openFusedContacts && armhole && armhole->kept &&
                          openContacts(*armhole, gp);
      if (!opened) gp.seams = estimator.all();
    }
    for (const SeamLine& s : gp.seams)
      if (!s.kept)
        gp.notes.push_back(fmt::format("seam '{}' removed: {}", s.name, s.removedWhy));
      else if (s.phi.size() != mesh.numVertices())
        throw InputError(
            fmt::format("pattern: seam '{}' of garment '{}' has {} values for {} "
                        "vertices",
                        s.name, garment_.name, s.phi.size(), mesh.numVertices()));
    for (const SeamLine& s : gp.seams)
      if (s.kind == SeamKind::Armhole) noteFolds(mesh, s, gp);
    seamed_ = insertSeams(mesh, gp.seams);
    topo_ = std::make_unique<MeshTopology>(seamed_.mesh.F, seamed_.mesh.numVertices());
    if (seamed_.seams.empty()) {
      const MeshTopology topo(mesh.F, mesh.numVertices());  // of the garment as completed
      const bool disk = topo.boundaryLoops().size() == 1 && topo.eulerCharacteristic() == 1;
      std::string why;  // each seam's reason, so the user sees which feature failed
      for (const SeamLine& s : gp.seams) why += fmt::format("; {}: {}", s.name, s.removedWhy);
      if (!disk)
        throw TopologyError(fmt::format(
            "pattern: no seam line survived on garment '{}' and it is not a disk ({} openings, "
            "χ = {}): it cannot be flattened as one panel. Check the body fit (fit/) and the "
            "segmentation (segment/){}",
            garment_.name, topo.boundaryLoops().size(), topo.eulerCharacteristic(), why));
      result_.warnings.push_back(
          fmt::format("garment '{}': no seam line survived; kept as one panel", garment_.name));
    }
    assignPanels();
    chooseUnderarmCuts();
    buildPanels(gp);
    gp.openings = classifyOpenings(seamed_.mesh, *topo_, garment_.kind, frame_);
    tagEdges(gp);
    gp.type = garmentType(gp);
    result_.garments.push_back(std::move(gp));
  }

 private:
  // Where the scan fused a sleeve to the trunk below the armpit (along `armhole`, the fused
  // garment's armhole seam), opens the contact and supplies the hidden cloth
  // (openFusedContacts), then finds the openings and seams again on the completed garment:
  // gp.openings and gp.seams. False (gp's seams untouched, notes added) when nothing was opened
  // or the completed garment's seams cannot be found.
  bool openContacts(const SeamLine& armhole, GarmentPanels& gp) {
    ContactOpening c =
        openFusedContacts(garment_.mesh, garment_.faceOrigin, armhole, armpitHeights(), frame_,
                          options_.seams, options_.contacts);
    for (const std::string& note : c.notes) gp.notes.push_back(note);
    if (c.opened.empty()) return false;
    try {
      const MeshTopology topo(c.mesh.F, c.mesh.numVertices());
      std::vector<Opening> openings = classifyOpenings(c.mesh, topo, garment_.kind, frame_);
      std::vector<SeamLine> seams =
          estimateSeams(c.mesh, garment_.kind, in_.body, in_.features, openings, options_.seams,
                        in_.bodyLimbWeight, c.hints);
      gp.openings = std::move(openings);
      gp.seams = std::move(seams);
    } catch (const Error& e) {
      gp.notes.push_back(fmt::format(
          "the contact(s) under the arm were opened but the seams of the completed garment "
          "could not be found ({}); left fused",
          e.what()));
      return false;
    }
    garment_.mesh = std::move(c.mesh);
    garment_.faceOrigin = std::move(c.faceOrigin);
    for (const OpenedContact& o : c.opened) opened_.insert(o.side);
    for (const OpenedContact& o : c.opened)
      gp.notes.push_back(fmt::format(
          "{} armhole: the scan fused sleeve and trunk below the armpit along a crease {:.0f} mm "
          "long, {:.0f} mm deep; the contact was opened and the cloth it hid supplied ({:.4f} m² "
          "of the sleeve's underside, {:.4f} m² of the side under the arm, joined along {:.0f} mm "
          "under the arm), so the armhole passes under the arm",
          o.side, 1000 * o.creaseLength, 1000 * o.drop, o.sleeveArea, o.trunkArea,
          1000 * o.topWidth));
    return true;
  }

  // The garment's inside the scan saw through an opening, dropped (trimInsideSeenThroughOpenings).
  void trimInside(GarmentPanels& gp) {
    std::optional<InsideTrim> t = trimInsideSeenThroughOpenings(garment_.mesh, garment_.faceOrigin,
                                                                in_.body, options_.inside);
    if (!t) return;
    gp.notes.push_back(fmt::format(
        "the scan saw the garment's inside through an opening (such as under a hem): {:.4f} m² "
        "({} faces) turned to the body along the rim dropped, the rim where they met is the edge",
        t->removedArea, t->removedFaces));
    garment_.mesh = std::move(t->mesh);
    garment_.faceOrigin = std::move(t->faceOrigin);
  }

  // The fitted body's armpit heights, left and right (armpitHeight), found once.
  const std::array<double, 2>& armpitHeights() {
    if (!armpit_)
      armpit_ = std::array<double, 2>{armpitHeight(in_.body, frame_, true),
                                      armpitHeight(in_.body, frame_, false)};
    return *armpit_;
  }

  // Says, per arm, how much of the armhole seam follows a fold below the body's armpit where the
  // scan fused the sleeve to the trunk (armholeFolds) and the contact was left fused: there the
  // seam cannot pass under the arm at the armpit. (Above the armpit a fold is the arm's root.)
  void noteFolds(const TriMesh& mesh, const SeamLine& armhole, GarmentPanels& gp) {
    if (opened_.size() == 2) return;
    const std::vector<SeamFold> folds = armholeFolds(mesh, armhole, options_.seams);
    if (folds.empty()) return;
    for (const char* side : {"left", "right"}) {
      // An opened contact's lips and membranes make folds of their own beside the crease it cut,
      // which a stray stretch of the isoline can follow; the panels no longer do.
      if (opened_.count(side)) continue;
      double length = 0, top = -std::numeric_limits<double>::infinity(),
             low = std::numeric_limits<double>::infinity();
      for (const SeamFold& f : folds) {
        if (std::string(frame_.side(0.5 * (f.a + f.b))) != side) continue;
        length += (f.b - f.a).norm();
        for (const Vec3& p : {f.a, f.b}) {
          top = std::max(top, frame_.height(p));
          low = std::min(low, frame_.height(p));
        }
      }
      const double armpit = armpitHeights()[std::string(side) == "left" ? 0 : 1];
      if (std::isfinite(armpit)) top = std::min(top, armpit);
      if (length == 0 || top - low < options_.seams.creaseReportDrop) continue;
      gp.notes.push_back(fmt::format(
          "{} armhole: {:.0f} mm of it follow a fold down {:.0f} mm below the armpit: the scan "
          "fused sleeve and trunk there (the sleeve's underside and the side under the arm are "
          "hidden in the contact), so the seam runs down the crease, not under the arm",
          side, 1000 * length, 1000 * (top - low)));
    }
  }

  int seamIndex(SeamKind kind) const {
    for (size_t k = 0; k < seamed_.seams.size(); ++k)
      if (seamed_.seams[k]->kind == kind) return static_cast<int>(k);
    return -1;
  }

  // Face labels from the seam sides, connected pieces, small pieces merged.
  void assignPanels() {
    const TriMesh& m = seamed_.mesh;
    const int nF = m.numFaces();
    const int fb = seamIndex(SeamKind::FrontBack), arm = seamIndex(SeamKind::Armhole),
              lr = seamIndex(SeamKind::LeftRight);
    std::vector<int> key(nF, 0);
    for (int f = 0; f < nF; ++f) {
      if (arm >= 0 && seamed_.sides[arm][f] == 0) {
        key[f] = 100;  // a sleeve, whatever its side of the front/back seam
        continue;
      }
      key[f] = (fb >= 0 ? seamed_.sides[fb][f] : 1) + 2 * (lr >= 0 ? seamed_.sides[lr][f] : 0);
    }
    // Connected pieces of one key.
    UnionFind uf(nF);
    for (int e = 0; e < topo_->numEdges(); ++e) {
      const std::vector<int> ef = topo_->edgeFaces(e);
      if (ef.size() == 2 && key[ef[0]] == key[ef[1]]) uf.join(ef[0], ef[1]);
    }
    std::map<int, int> pieceOf;
    piece_.assign(nF, -1);
    for (int f = 0; f < nF; ++f) {
      const auto [it, added] = pieceOf.try_emplace(uf.find(f), static_cast<int>(pieceOf.size()));
      piece_[f] = it->second;
    }
    const int nP = static_cast<int>(pieceOf.size());
    std::vector<int> pieceKey(nP);
    for (int f = 0; f < nF; ++f) pieceKey[piece_[f]] = key[f];
    // Merge pieces below the area threshold into their longest-bordering neighbour.
    const Eigen::VectorXd area = faceAreas(m);
    const double total = area.sum();
    std::vector<int> target(nP);
    std::iota(target.begin(), target.end(), 0);
    for (bool changed = true; changed;) {
      changed = false;
      std::vector<double> pa(nP, 0.0);
      for (int f = 0; f < nF; ++f) pa[piece_[f]] += area[f];
      std::vector<std::map<int, double>> border(nP);
      for (int e = 0; e < topo_->numEdges(); ++e) {
        const std::vector<int> ef = topo_->edgeFaces(e);
        if (ef.size() != 2 || piece_[ef[0]] == piece_[ef[1]]) continue;
        const double len = (m.V.row(topo_->edges()(e, 0)) - m.V.row(topo_->edges()(e, 1))).norm();
        border[piece_[ef[0]]][piece_[ef[1]]] += len;
        border[piece_[ef[1]]][piece_[ef[0]]] += len;
      }
      int smallest = -1;
      for (int p = 0; p < nP; ++p)
        if (pa[p] > 0 && pa[p] < options_.minPanelFraction * total && !border[p].empty() &&
            (smallest < 0 || pa[p] < pa[smallest]))
          smallest = p;
      if (smallest < 0) break;
      const auto best =
          std::max_element(border[smallest].begin(), border[smallest].end(),
                           [](const auto& a, const auto& b) { return a.second < b.second; });
      for (int f = 0; f < nF; ++f)
        if (piece_[f] == smallest) piece_[f] = best->first;
      ++merged_;
      changed = true;
    }
    // Pieces of one label that touch once the slivers between them are gone are one panel (a
    // thin band between two nearby isolines of one seam, e.g. around a shin, had split a leg).
    {
      UnionFind join(nP);
      for (int e = 0; e < topo_->numEdges(); ++e) {
        const std::vector<int> ef = topo_->edgeFaces(e);
        if (ef.size() == 2 && pieceKey[piece_[ef[0]]] == pieceKey[piece_[ef[1]]])
          join.join(piece_[ef[0]], piece_[ef[1]]);
      }
      for (int f = 0; f < nF; ++f) piece_[f] = join.find(piece_[f]);
    }
    // Renumber the surviving pieces: they are the panels.
    std::map<int, int> renumber;
    for (int f = 0; f < nF; ++f) {
      const auto [it, added] = renumber.try_emplace(piece_[f], static_cast<int>(renumber.size()));
      piece_[f] = it->second;
    }
    panelKey_.assign(renumber.size(), 0);
    for (const auto& [old, now] : renumber) panelKey_[now] = pieceKey[old];
    panelFaces_.assign(renumber.size(), {});
    for (int f = 0; f < nF; ++f) panelFaces_[piece_[f]].push_back(f);
    cut_.assign(topo_->numEdges(), 0);
    fallbackCut_.assign(topo_->numEdges(), 0);
  }

  // A sleeve opens along the chain of the front/back isoline nearest the underarm spline.
  void chooseUnderarmCuts() {
    const int fb = seamIndex(SeamKind::FrontBack);
    if (fb < 0) return;
    const TriMesh& m = seamed_.mesh;
    const Eigen::MatrixX3d& prior = seamed_.seams[fb]->prior;
    for (size_t p = 0; p < panelFaces_.size(); ++p) {
      if (panelKey_[p] != 100) continue;
      std::vector<int> chainEdges;
      for (int f : panelFaces_[p])
        for (int k = 0; k < 3; ++k) {
          const int e = topo_->faceEdges()(f, k);
          const std::vector<int> ef = topo_->edgeFaces(e);
          if (ef.size() == 2 && ef[0] == f && piece_[ef[1]] == static_cast<int>(p) &&
              seamed_.sides[fb][ef[0]] != seamed_.sides[fb][ef[1]])
            chainEdges.push_back(e);  // each edge once, from its first face
        }
      if (chainEdges.empty()) continue;
      UnionFind uf(m.numVertices());
      for (int e : chainEdges) uf.join(topo_->edges()(e, 0), topo_->edges()(e, 1));
      std::map<int, std::pair<double, int>> score;  // chain root → (distance sum, count)
      for (int e : chainEdges) {
        const Vec3 mid =
            0.5 * (m.V.row(topo_->edges()(e, 0)) + m.V.row(topo_->edges()(e, 1))).transpose();
        double best = std::numeric_limits<double>::infinity();
        for (int i = 0; i < prior.rows(); ++i)
          best = std::min(best, (prior.row(i).transpose() - mid).norm());
        auto& s = score[uf.find(topo_->edges()(e, 0))];
        s.first += best;
        ++s.second;
      }
      int chosen = -1;
      double bestMean = std::numeric_limits<double>::infinity();
      for (const auto& [root, s] : score)
        if (s.first / s.second < bestMean) {
          bestMean = s.first / s.second;
          chosen = root;
        }
      for (int e : chainEdges)
        if (uf.find(topo_->edges()(e, 0)) == chosen) cut_[e] = 1;
    }
  }

  std::string panelName(int p) const {
    const Vec3 c = facesCentroid(seamed_.mesh, panelFaces_[p]);
    if (panelKey_[p] == 100) return fmt::format("{}_sleeve", frame_.side(c));
    const bool front = panelKey_[p] % 2 == 1;
    const bool hasLr = seamIndex(SeamKind::LeftRight) >= 0;
    const std::string base = front ? "front" : "back";
    return hasLr ? fmt::format("{}_{}", panelKey_[p] >= 2 ? "left" : "right", base) : base;
  }

  // An underarm chain that wanders onto the cuff cuts off the sliver between itself and the
  // cuff along with opening the sleeve: the panel comes out in two pieces. Un-cuts the cut edges
  // between the panel's largest piece and the others; true when any were.
  bool rejoinSeveredIslands(const PanelMesh& pm, const MeshTopology& pt) {
    std::vector<int> faces(pt.numComponents(), 0);
    for (int f = 0; f < pm.mesh.numFaces(); ++f) ++faces[pt.faceComponent()[f]];
    const int main = static_cast<int>(std::max_element(faces.begin(), faces.end()) - faces.begin());
    std::unordered_map<int, int> componentOf;  // seamed-garment face → panel piece
    for (int f = 0; f < pm.mesh.numFaces(); ++f)
      componentOf[pm.globalFace[f]] = pt.faceComponent()[f];
    bool rejoined = false;
    for (const auto& [face, component] : componentOf) {
      if (component == main) continue;
      for (int k = 0; k < 3; ++k) {
        const int e = topo_->faceEdges()(face, k);
        if (!cut_[e]) continue;
        for (int other : topo_->edgeFaces(e)) {
          const auto it = componentOf.find(other);
          if (it != componentOf.end() && it->second == main) {
            cut_[e] = 0;
            fallbackCut_[e] = 0;
            rejoined = true;
          }
        }
      }
    }
    return rejoined;
  }

  void buildPanels(GarmentPanels& gp) {
    const TriMesh& m = seamed_.mesh;
    const int first = static_cast<int>(result_.panels.size());
    std::map<std::string, int> used;
    for (size_t p = 0; p < panelFaces_.size(); ++p) {
      Panel panel;
      panel.garment = garment_.name;
      panel.garmentIndex = index_;
      panel.name = panelName(static_cast<int>(p));
      if (int n = used[panel.name]++; n > 0) {
        result_.warnings.push_back(
            fmt::format("garment '{}': a second piece named '{}' (the seams left it apart)",
                        garment_.name, panel.name));
        panel.name += fmt::format("_{}", n + 1);
      }
      PanelMesh pm = extractPanel(m, *topo_, panelFaces_[p], piece_, static_cast<int>(p), cut_);
      for (int round = 0;; ++round) {
        const MeshTopology pt(pm.mesh.F, pm.mesh.numVertices());
        const size_t loops = pt.boundaryLoops().size();
        if (loops == 1 && pt.eulerCharacteristic() == 1) break;
        if (pt.numComponents() > 1 && rejoinSeveredIslands(pm, pt)) {
          gp.notes.push_back(fmt::format(
              "panel '{}': a piece its own cut had severed was joined back to it", panel.name));
          pm = extractPanel(m, *topo_, panelFaces_[p], piece_, static_cast<int>(p), cut_);
          continue;
        }
        if (loops < 2 || round > 8)
          throw TopologyError(fmt::format(
              "pattern: panel '{}' of garment '{}' is not a disk ({} boundary loops, χ = {}) "
              "and no cut between its openings makes it one",
              panel.name, garment_.name, loops, pt.eulerCharacteristic()));
        if (visibility_.size() == 0) visibility_ = horizontalVisibility(m, in_.body, frame_);
        Eigen::VectorXd cost(pm.mesh.numVertices());
        for (int v = 0; v < cost.size(); ++v)
          cost[v] = 1 + options_.visibilityWeight * visibility_[pm.globalVertex[v]];
        const auto path = cheapestCut(pm.mesh, pt, cost);
        if (path.empty())
          throw TopologyError(fmt::format(
              "pattern: panel '{}' of garment '{}' has {} boundary loops with no path between "
              "them",
              panel.name, garment_.name, loops));
        for (const auto& [a, b] : path) {
          const int e = topo_->findEdge(pm.globalVertex[a], pm.globalVertex[b]);
          if (e >= 0) {
            cut_[e] = 1;
            fallbackCut_[e] = 1;
          }
        }
        panel.cutOpen = true;
        pm = extractPanel(m, *topo_, panelFaces_[p], piece_, static_cast<int>(p), cut_);
      }
      if (panel.cutOpen)
        gp.notes.push_back(
            fmt::format("panel '{}' was not a disk: cut open along the cheapest "
                        "path between its openings on its least visible side",
                        panel.name));
      panel.mesh = pm.mesh;
      panel.faceOrigin.resize(pm.mesh.numFaces());
      for (int f = 0; f < pm.mesh.numFaces(); ++f)
        panel.faceOrigin[f] = garment_.faceOrigin[seamed_.garmentFace[pm.globalFace[f]]];
      panel.area = surfaceArea(pm.mesh);
      meshes_.push_back(std::move(pm));
      gp.panels.push_back(first + static_cast<int>(p));
      result_.panels.push_back(std::move(panel));
    }
    if (merged_ > 0)
      gp.notes.push_back(
          fmt::format("{} sliver(s) below {:.0f} % of the garment merged into a "
                      "neighbouring panel",
                      merged_, 100 * options_.minPanelFraction));
  }

  // What lies across a boundary half-edge of a panel.
  struct Across {
    int opening = -1;  // garment opening, or
    int panel = -1;    // the panel across a seam (local index in this garment)
    bool operator==(const Across& o) const { return opening == o.opening && panel == o.panel; }
  };

  std::string seamEdgeName(int panel, int partner, const std::vector<int>& globalVerts) const {
    const TriMesh& m = seamed_.mesh;
    Vec3 c = Vec3::Zero();
    for (int v : globalVerts) c += m.V.row(v).transpose();
    c /= std::max<size_t>(1, globalVerts.size());
    // The seam whose field is nearest zero along the edge.
    int best = -1;
    double bestValue = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < seamed_.fields.size(); ++k) {
      double s = 0;
      for (int v : globalVerts) s += std::abs(seamed_.fields[k][v]);
      s /= std::max<size_t>(1, globalVerts.size());
      if (s < bestValue) {
        bestValue = s;
        best = static_cast<int>(k);
      }
    }
    const std::string side = frame_.side(c);
    if (panel == partner && panelKey_[panel] == 100 && best >= 0 &&
        seamed_.seams[best]->kind == SeamKind::FrontBack && bestValue < 1e-6)
      return side + "_underarm";
    if (best < 0 || bestValue > 1e-6) return "cut";
    switch (seamed_.seams[best]->kind) {
      case SeamKind::Armhole:
        return side + "_armhole";
      case SeamKind::LeftRight:
        return panelKey_[panel] % 2 == 1 ? "center_front" : "center_back";
      case SeamKind::FrontBack: {
        using C = Canonical;
        const double shoulderH = 0.5 * (frame_.height(frame_.at(C::LeftShoulder)) +
                                        frame_.height(frame_.at(C::RightShoulder)));
        if (frame_.height(c) > shoulderH - 0.06) return side + "_shoulder";
        const Vec3 hip = frame_.at(side == "left" ? C::LeftHip : C::RightHip);
        if (garment_.kind != GarmentKind::Upper && frame_.height(c) < frame_.height(hip) - 0.1 &&
            std::abs(frame_.lateral(c)) < std::abs(frame_.lateral(hip)))
          return side + "_inseam";
        return side + "_side";
      }
    }
    return "seam";
  }

  void tagEdges(GarmentPanels& gp) {
    // Boundary edge of the seamed garment → opening.
    std::map<std::pair<int, int>, int> openingOf;
    for (size_t o = 0; o < gp.openings.size(); ++o) {
      const auto& loop = gp.openings[o].vertices;
      for (size_t i = 0; i < loop.size(); ++i) {
        const int a = loop[i], b = loop[(i + 1) % loop.size()];
        openingOf[{std::min(a, b), std::max(a, b)}] = static_cast<int>(o);
      }
    }
    const int first = gp.panels.empty() ? 0 : gp.panels.front();
    // (global edge, face on this side) → (panel, edge index), to find partners.
    std::map<std::pair<int, int>, std::pair<int, int>> edgeAt;
    struct Pending {
      int panel, edge;
      std::pair<int, int> twin;  // (global edge, face across)
    };
    std::vector<Pending> pending;
    for (size_t p = 0; p < meshes_.size(); ++p) {
      Panel& panel = result_.panels[first + p];
      const PanelMesh& pm = meshes_[p];
      const MeshTopology pt(pm.mesh.F, pm.mesh.numVertices());
      panel.loop = pt.boundaryLoops().front();
      const std::vector<int>& loop = panel.loop;
      const int n = static_cast<int>(loop.size());
      // Per boundary half-edge: what lies across, its global edge and its face.
      std::vector<Across> across(n);
      std::vector<int> gEdge(n), gFace(n), gOther(n, -1);
      for (int i = 0; i < n; ++i) {
        const int a = loop[i], b = loop[(i + 1) % n];
        const int e = pt.findEdge(a, b);
        const int lf = pt.edgeFaces(e).front();
        gFace[i] = pm.globalFace[lf];
        const int ga = pm.globalVertex[a], gb = pm.globalVertex[b];
        gEdge[i] = topo_->findEdge(ga, gb);
        const std::vector<int> ef = topo_->edgeFaces(gEdge[i]);
        if (ef.size() == 1) {
          const auto it = openingOf.find({std::min(ga, gb), std::max(ga, gb)});
          across[i].opening = it == openingOf.end() ? -2 : it->second;
        } else {
          gOther[i] = ef[0] == gFace[i] ? ef[1] : ef[0];
          across[i].panel = piece_[gOther[i]];
        }
      }
      // Corners: where what lies across changes.
      std::vector<int> corners;
      for (int i = 0; i < n; ++i)
        if (!(across[i] == across[(i + n - 1) % n])) corners.push_back(i);
      if (corners.empty()) {  // one opening all round: two corners half the length apart
        corners = {0, n / 2};
      } else if (corners.size() == 1) {
        corners.push_back((corners[0] + n / 2) % n);
        std::sort(corners.begin(), corners.end());
      }
      for (size_t c = 0; c < corners.size(); ++c) {
        const int s = corners[c], e = corners[(c + 1) % corners.size()];
        const int len = ((e - s) % n + n) % n == 0 ? n : ((e - s) % n + n) % n;
        PanelEdge edge;
        std::vector<int> globalVerts;
        for (int j = 0; j <= len; ++j) {
          const int v = loop[(s + j) % n];
          edge.vertices.push_back(v);
          if (j > 0 && j < len) globalVerts.push_back(pm.globalVertex[v]);
        }
        for (int j = 0; j < len; ++j) {
          const int i = (s + j) % n;
          edge.length += (pm.mesh.V.row(loop[i]) - pm.mesh.V.row(loop[(i + 1) % n])).norm();
        }
        if (globalVerts.empty()) globalVerts.push_back(pm.globalVertex[loop[s]]);
        const Across& a = across[s];
        const int edgeIndex = static_cast<int>(panel.edges.size());
        for (int j = 0; j < len; ++j) {
          const int i = (s + j) % n;
          edgeAt[{gEdge[i], gFace[i]}] = {first + static_cast<int>(p), edgeIndex};
        }
        if (a.panel >= 0) {
          edge.opening = false;
          edge.partnerPanel = first + a.panel;
          edge.name = fallbackCut_[gEdge[s]]
                          ? "cut"
                          : seamEdgeName(static_cast<int>(p), a.panel, globalVerts);
          pending.push_back({first + static_cast<int>(p), edgeIndex, {gEdge[s], gOther[s]}});
        } else {
          edge.opening = true;
          edge.name = a.opening >= 0 ? gp.openings[a.opening].name : "opening";
        }
        panel.edges.push_back(std::move(edge));
      }
    }
    for (const Pending& q : pending) {
      const auto it = edgeAt.find(q.twin);
      if (it == edgeAt.end()) continue;
      result_.panels[q.panel].edges[q.edge].partnerEdge = it->second.second;
    }
  }

  std::string garmentType(const GarmentPanels& gp) const {
    const bool crotch = seamIndex(SeamKind::LeftRight) >= 0;
    switch (garment_.kind) {
      case GarmentKind::Upper: {
        double cuffT = -1;
        int sleeves = 0;
        for (int p : gp.panels)
          sleeves += result_.panels[p].name.find("sleeve") != std::string::npos;
        for (const Opening& o : gp.openings) {
          if (o.name.find("cuff") != std::string::npos) cuffT = std::max(cuffT, o.t);
          for (const Opening::JoinedCuff& c : o.joinedCuffs) cuffT = std::max(cuffT, c.t);
        }
        if (sleeves == 0) return "sleeveless_top";
        return cuffT > 0.75 ? "long_sleeve_shirt" : "tshirt";
      }
      case GarmentKind::Lower: {
        if (!crotch) return "skirt";
        double legT = 0;
        for (const Opening& o : gp.openings)
          if (o.name.find("leg_opening") != std::string::npos) legT = std::max(legT, o.t);
        return legT > 0.6 ? "trousers" : "shorts";
      }
      case GarmentKind::OnePiece:
        return crotch ? "jumpsuit" : "dress";
    }
    return "?";
  }

  const PanelsInput& in_;
  PanelsInput::Garment garment_;  // a copy: openContacts may complete it
  int index_;
  const BodyFrame& frame_;
  const PanelOptions& options_;
  PanelsResult& result_;

  SeamedGarment seamed_;
  std::unique_ptr<MeshTopology> topo_;
  std::vector<int> piece_;                    // #F of the seamed garment: panel (local index)
  std::vector<int> panelKey_;                 // per panel: 100 sleeve, else front + 2·left
  std::vector<std::vector<int>> panelFaces_;  // per panel
  std::vector<char> cut_;                     // per seamed-garment edge: cut open inside a panel
  std::vector<char> fallbackCut_;             // ... of which by the fallback cut
  std::vector<PanelMesh> meshes_;
  Eigen::VectorXd visibility_;
  std::optional<std::array<double, 2>> armpit_;
  std::set<std::string> opened_;  // the sides whose fused contact was opened
  int merged_ = 0;
};

}  // namespace

void panelizeGarment(const PanelsInput& input, int garment, std::vector<SeamLine> seams,
                     const PanelOptions& options, PanelsResult& result) {
  const BodyFrame frame(input.canonical);
  GarmentPanelizer(input, input.garments.at(garment), garment, frame, options, result)
      .run(std::move(seams));
}

int dropStrayPieces(PanelsInput::Garment& g, double minFraction) {
  if (g.mesh.numFaces() == 0) return 0;
  const MeshTopology topo(g.mesh.F, g.mesh.numVertices());
  const int nC = topo.numComponents();
  if (nC <= 1) return 0;
  const Eigen::VectorXi& comp = topo.faceComponent();
  const Eigen::VectorXd area = faceAreas(g.mesh);
  std::vector<double> compArea(nC, 0.0);
  std::vector<char> open(nC, 0);
  for (int f = 0; f < g.mesh.numFaces(); ++f) compArea[comp[f]] += area[f];
  for (int e = 0; e < topo.numEdges(); ++e)
    if (topo.isBoundaryEdge(e)) open[comp[topo.edgeFaces(e).front()]] = 1;
  const double total = area.sum();
  std::vector<int> keep;
  int dropped = 0;
  for (int c = 0; c < nC; ++c) {
    const bool stray = !open[c] || compArea[c] < minFraction * total;
    dropped += stray;
  }
  if (dropped == 0) return 0;
  for (int f = 0; f < g.mesh.numFaces(); ++f) {
    const int c = comp[f];
    if (open[c] && compArea[c] >= minFraction * total) keep.push_back(f);
  }
  TriMesh m;
  m.V = g.mesh.V;
  m.F.resize(static_cast<int>(keep.size()), 3);
  Eigen::VectorXi origin(static_cast<int>(keep.size()));
  for (size_t i = 0; i < keep.size(); ++i) {
    m.F.row(static_cast<int>(i)) = g.mesh.F.row(keep[i]);
    origin[static_cast<int>(i)] = g.faceOrigin[keep[i]];
  }
  removeUnreferencedVertices(m);
  g.mesh = std::move(m);
  g.faceOrigin = origin;
  return dropped;
}

int fillScanHoles(PanelsInput::Garment& g, const BodyFrame& frame, double minOpeningFraction,
                  int* besideArm) {
  if (besideArm) *besideArm = 0;
  if (g.mesh.numFaces() == 0) return 0;
  const MeshTopology topo(g.mesh.F, g.mesh.numVertices());
  if (!topo.manifoldness().isManifold()) return 0;  // refused with its own error later
  const std::vector<Opening> openings = classifyOpenings(g.mesh, topo, g.kind, frame);
  const double stature = frame.height(frame.at(Canonical::HeadTop)) -
                         0.5 * (frame.height(frame.at(Canonical::LeftAnkle)) +
                                frame.height(frame.at(Canonical::RightAnkle)));
  const double minOpening = minOpeningFraction * stature;
  // A loop can be an opening when a hand passes through it and, if it is named for an arm, when
  // the arm passes through it: a hole where no camera looked into the armpit lies beside the arm
  // (f3's tank top, whose armholes the scan merged with its neckline, kept 15–17 cm armpit holes
  // as armholes). The longest such loop of each name is the opening; the others are holes.
  std::vector<bool> armless(openings.size(), false);
  std::map<std::string, int> longest;
  for (size_t i = 0; i < openings.size(); ++i) {
    armless[i] = isArm(openings[i].limb) && openings[i].armCrossings == 0;
    if (openings[i].length < minOpening || armless[i]) continue;
    auto [it, added] = longest.try_emplace(openings[i].name, static_cast<int>(i));
    if (openings[i].length > openings[it->second].length) it->second = static_cast<int>(i);
  }
  std::vector<Eigen::RowVector3d> newV;
  std::vector<Eigen::RowVector3i> newF;
  std::vector<int> newOrigin;
  int filled = 0;
  for (size_t i = 0; i < openings.size(); ++i) {
    const auto kept = longest.find(openings[i].name);
    if (kept != longest.end() && kept->second == static_cast<int>(i)) continue;
    const std::vector<int>& loop = openings[i].vertices;
    if (loop.size() < 3) continue;
    if (besideArm && armless[i] && openings[i].length >= minOpening) ++*besideArm;
    Eigen::RowVector3d centre = Eigen::RowVector3d::Zero();
    for (int v : loop) centre += g.mesh.V.row(v);
    centre /= static_cast<double>(loop.size());
    // A slit-like hole (its loop doubling back on itself, as a 1 mm grid leaves them) has its
    // centroid on its own border: a fan around it has no area, and the new vertex none either
    // (no Laplacian, no mass). Such a hole is closed by a fan from one of its own vertices.
    double fanArea = 0, perimeter = 0;
    for (size_t k = 0; k < loop.size(); ++k) {
      const Eigen::RowVector3d a = g.mesh.V.row(loop[k]);
      const Eigen::RowVector3d b = g.mesh.V.row(loop[(k + 1) % loop.size()]);
      fanArea += 0.5 * (a - centre).cross(b - centre).norm();
      perimeter += (b - a).norm();
    }
    const bool slit = !(fanArea > 1e-4 * perimeter * perimeter);
    const int c = slit ? loop[0] : g.mesh.numVertices() + static_cast<int>(newV.size());
    if (!slit) newV.push_back(centre);
    for (size_t k = 0; k < loop.size(); ++k) {
      const int a = loop[k], b = loop[(k + 1) % loop.size()];
      if (a == c || b == c) continue;
      // The surface lies left of a → b, so the fill face runs b → a.
      newF.push_back({b, a, c});
      const int e = topo.findEdge(a, b);
      newOrigin.push_back(g.faceOrigin[topo.edgeFaces(e).front()]);
    }
    ++filled;
  }
  if (filled == 0) return 0;
  const int nV = g.mesh.numVertices(), nF = g.mesh.numFaces();
  g.mesh.V.conservativeResize(nV + static_cast<int>(newV.size()), 3);
  for (size_t i = 0; i < newV.size(); ++i) g.mesh.V.row(nV + static_cast<int>(i)) = newV[i];
  g.mesh.F.conservativeResize(nF + static_cast<int>(newF.size()), 3);
  g.faceOrigin.conservativeResize(nF + static_cast<int>(newF.size()));
  for (size_t i = 0; i < newF.size(); ++i) {
    g.mesh.F.row(nF + static_cast<int>(i)) = newF[i];
    g.faceOrigin[nF + static_cast<int>(i)] = newOrigin[i];
  }
  return filled;
}

PanelsResult runPanels(const PanelsInput& input, const PanelOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  validateMesh(input.body, "fitted body");
  const BodyFrame frame(input.canonical);
  PanelsResult result;
  // Holes where no camera looked (armpits, under the arms) are boundary loops too, but not
  // garment openings: every loop but the longest of each opening name is filled.
  std::vector<PanelsInput::Garment> garments = input.garments;
  for (size_t g = 0; g < garments.size(); ++g) {
    // Closed bubbles and crumbs labelled as the garment are no cloth to cut.
    const int dropped = dropStrayPieces(garments[g], options.minPanelFraction);
    if (dropped > 0)
      result.warnings.push_back(
          fmt::format("garment '{}': {} closed or tiny piece(s) left out "
                      "(no cloth to cut)",
                      garments[g].name, dropped));
    int besideArm = 0;
    const int filled = fillScanHoles(garments[g], frame, options.minOpeningFraction, &besideArm);
    if (filled > 0)
      result.warnings.push_back(fmt::format(
          "garment '{}': {} hole(s) of the scan filled (boundary loops that are not its "
          "openings{})",
          garments[g].name, filled,
          besideArm > 0 ? fmt::format("; {} of them named for an arm that does not pass "
                                      "through them",
                                      besideArm)
                        : ""));
  }
  // The garments are independent: each is panelled into a result of its own, in parallel, and
  // the results are joined in the garments' order (the panel and garment indices shifted).
  std::vector<PanelsResult> own(garments.size());
  std::vector<std::exception_ptr> failed(garments.size());
  tbb::parallel_for(size_t{0}, garments.size(), [&](size_t g) {
    try {
      GarmentPanelizer(input, garments[g], 0, frame, options, own[g]).run();
    } catch (const Error&) {
      failed[g] = std::current_exception();
    }
  });
  // A garment that makes no pattern does not cost the others theirs: its error becomes a
  // warning, and only when no garment makes one is the error raised.
  std::exception_ptr lastError;
  for (size_t g = 0; g < garments.size(); ++g) {
    for (std::string& w : own[g].warnings) result.warnings.push_back(std::move(w));
    if (failed[g]) {
      try {
        std::rethrow_exception(failed[g]);
      } catch (const Error& e) {
        result.warnings.push_back(
            fmt::format("garment '{}' makes no pattern: {}", garments[g].name, e.what()));
      }
      lastError = failed[g];
      continue;
    }
    // Panels index result.garments (placement, the pattern files), which holds only the
    // garments that made a pattern: a failed garment before this one shifts the index.
    const int panelOffset = static_cast<int>(result.panels.size());
    const int garmentIndex = static_cast<int>(result.garments.size());
    for (Panel& panel : own[g].panels) {
      panel.garmentIndex = garmentIndex;
      for (PanelEdge& edge : panel.edges)
        if (edge.partnerPanel >= 0) edge.partnerPanel += panelOffset;
      result.panels.push_back(std::move(panel));
    }
    for (GarmentPanels& gp : own[g].garments) {
      for (int& p : gp.panels) p += panelOffset;
      result.garments.push_back(std::move(gp));
    }
  }
  if (result.garments.empty() && lastError) std::rethrow_exception(lastError);
  result.seconds = secondsSince(t0);
  return result;
}

}  // namespace s2p
