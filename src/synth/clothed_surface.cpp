#include "synth/clothed_surface.h"

#include <algorithm>
#include <chrono>
#include <map>
#include <set>
#include <string>

#include <tbb/parallel_for.h>

#include "body/posing.h"
#include "core/error.h"
#include "core/mesh_topology.h"
#include "synth/corruption.h"
#include "synth/garment_shapes.h"
#include "synth/level_set.h"

namespace s2p {
namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

void validateOptions(const GeometryOptions& o) {
  if (!(o.voxelSize >= 0.001 && o.voxelSize <= 0.05))
    throw InputError("clothed surface: voxelSize " + std::to_string(o.voxelSize) +
                     " m is outside [0.001, 0.05]; 0.004 is the default");
  if (o.targetVertices != 0 && o.targetVertices < 100)
    throw InputError("clothed surface: targetVertices " + std::to_string(o.targetVertices) +
                     " must be 0 (no decimation) or at least 100");
  if (!(o.noise >= 0 && o.noise <= 0.05))
    throw InputError("clothed surface: noise σ " + std::to_string(o.noise) +
                     " m is outside [0, 0.05]");
  if (o.holes < 0 || o.holes > 6)
    throw InputError("clothed surface: holes = " + std::to_string(o.holes) +
                     " must be in [0, 6] (armpits, crotch, soles, crown)");
  if (o.holes > 0 && !(o.holeRadius > 0.005 && o.holeRadius <= 0.1))
    throw InputError("clothed surface: holeRadius " + std::to_string(o.holeRadius) +
                     " m is outside (0.005, 0.1]");
}

std::string garmentName(const GarmentSpec& s) {
  return s.name.empty() ? std::string(toString(s.type)) : s.name;
}

// Label at p; layer index (−1 skin) in *layer.
Label labelAt(const GarmentLayers& layers, const BodyField& field, const Eigen::Vector3d& p,
              int* layer = nullptr) {
  bool gap = false;
  const int i = layers.visibleLayer(p, field.sample(p), &gap);
  if (layer) *layer = i;
  if (i < 0) return Label::Skin;
  return gap ? Label::Gap : layers.layer(i).label;
}

// The pair a boundary between labels a and b is reported under: the rim of a free-hanging hem
// (garment | gap) is the garment's boundary with the skin.
std::pair<Label, Label> reportedPair(Label a, Label b) {
  if (a == Label::Gap && (b == Label::Upper || b == Label::Lower)) a = Label::Skin;
  if (b == Label::Gap && (a == Label::Upper || a == Label::Lower)) b = Label::Skin;
  if (static_cast<int>(a) > static_cast<int>(b)) std::swap(a, b);
  return {a, b};
}

// True boundaries: on every edge whose end labels differ, the label change is found by
// bisection of the exact label function (resolution independent up to the chord), and the
// crossings are chained face by face into polylines. The label function is exact on the clean
// surface `mesh`; each crossing is then placed at the same fraction of its edge between the
// vertices `finalV` (#V×3: the scan's own positions, after normal noise), so that the truth lies
// on the surface the segmenter is given and is as long as a cut along it.
std::vector<TrueBoundary> computeBoundaries(const TriMesh& mesh, const Eigen::MatrixX3d& finalV,
                                            const Eigen::VectorXi& vlabel,
                                            const GarmentLayers& layers,
                                            const BodyField& field) {
  const MeshTopology topo(mesh.F, mesh.numVertices());
  const Eigen::MatrixX2i& E = topo.edges();
  std::vector<int> crossingEdges;
  for (int e = 0; e < topo.numEdges(); ++e)
    if (vlabel[E(e, 0)] != vlabel[E(e, 1)]) crossingEdges.push_back(e);
  std::vector<int> node(topo.numEdges(), -1);
  const int nc = static_cast<int>(crossingEdges.size());
  std::vector<Eigen::Vector3d> points(nc);
  std::vector<std::pair<Label, Label>> pairOf(nc);
  tbb::parallel_for(0, nc, [&](int i) {
    const int e = crossingEdges[i];
    const Label la = static_cast<Label>(vlabel[E(e, 0)]);
    double lo = 0, hi = 1;  // fractions of the edge from its first vertex
    const Eigen::Vector3d a = mesh.V.row(E(e, 0)).transpose(), b = mesh.V.row(E(e, 1)).transpose();
    for (int it = 0; it < 14; ++it) {
      const double mid = 0.5 * (lo + hi);
      (labelAt(layers, field, a + mid * (b - a)) == la ? lo : hi) = mid;
    }
    const double t = 0.5 * (lo + hi);
    points[i] = ((1 - t) * finalV.row(E(e, 0)) + t * finalV.row(E(e, 1))).transpose();
    pairOf[i] = reportedPair(la, static_cast<Label>(vlabel[E(e, 1)]));
  });
  for (int i = 0; i < nc; ++i) node[crossingEdges[i]] = i;

  // Segments per pair; junction nodes (faces with three labels) are appended to points.
  std::map<std::pair<Label, Label>, std::vector<std::pair<int, int>>> segments;
  for (int f = 0; f < mesh.numFaces(); ++f) {
    int c[3], n = 0;
    for (int k = 0; k < 3; ++k)
      if (node[topo.faceEdges()(f, k)] >= 0) c[n++] = node[topo.faceEdges()(f, k)];
    if (n == 2) {
      segments[pairOf[c[0]]].push_back({c[0], c[1]});
    } else if (n == 3) {
      const int j = static_cast<int>(points.size());
      points.push_back((points[c[0]] + points[c[1]] + points[c[2]]) / 3);
      pairOf.push_back({Label::Skin, Label::Skin});
      for (int k = 0; k < 3; ++k) segments[pairOf[c[k]]].push_back({c[k], j});
    }
  }
  std::vector<TrueBoundary> out;
  for (auto& [pair, segs] : segments) {
    if (pair.first == pair.second) continue;
    std::map<int, std::vector<int>> adj;  // node → segment ids
    for (int s = 0; s < static_cast<int>(segs.size()); ++s) {
      adj[segs[s].first].push_back(s);
      adj[segs[s].second].push_back(s);
    }
    std::vector<bool> used(segs.size(), false);
    TrueBoundary b;
    b.a = pair.first;
    b.b = pair.second;
    auto walk = [&](int start) {
      std::vector<int> chain{start};
      int cur = start;
      for (;;) {
        int next = -1;
        for (int s : adj[cur])
          if (!used[s]) {
            used[s] = true;
            next = segs[s].first == cur ? segs[s].second : segs[s].first;
            break;
          }
        if (next < 0) break;
        chain.push_back(next);
        cur = next;
      }
      const bool closed = chain.size() > 3 && chain.front() == chain.back();
      if (closed) chain.pop_back();
      if (chain.size() < 2) return;
      Eigen::MatrixX3d P(static_cast<int>(chain.size()), 3);
      for (std::size_t i = 0; i < chain.size(); ++i) P.row(int(i)) = points[chain[i]].transpose();
      b.curves.push_back(P);
      b.closed.push_back(closed);
    };
    for (const auto& [n, ss] : adj)  // open chains first, from their ends
      if (ss.size() != 2)
        for (std::size_t k = 0; k < ss.size(); ++k) walk(n);
    for (const auto& [n, ss] : adj) walk(n);
    if (!b.curves.empty()) out.push_back(std::move(b));
  }
  return out;
}

// Candidate hole centres in scanner-missed places: armpits, crotch, soles, crown.
std::vector<Eigen::Vector3d> holeCentres(const PosedBody& posed, double scale) {
  auto c = [&](Canonical k) -> Eigen::Vector3d {
    return posed.canonical.row(static_cast<int>(k)).transpose();
  };
  const Eigen::Vector3d up(0, 1, 0);
  std::vector<Eigen::Vector3d> out;
  for (auto [sh, ch] : {std::pair{Canonical::LeftShoulder, Canonical::Chest},
                        std::pair{Canonical::RightShoulder, Canonical::Chest}}) {
    Eigen::Vector3d p = c(sh) + 0.25 * (c(ch) - c(sh));
    p.y() = c(sh).y() - 0.09 * scale;
    out.push_back(p);
  }
  Eigen::Vector3d crotch = 0.5 * (c(Canonical::LeftHip) + c(Canonical::RightHip));
  crotch.y() -= 0.1 * scale;
  out.push_back(crotch);
  for (auto [heel, toe] : {std::pair{Canonical::LeftHeel, Canonical::LeftToeTip},
                           std::pair{Canonical::RightHeel, Canonical::RightToeTip}}) {
    Eigen::Vector3d p = 0.5 * (c(heel) + c(toe));
    p.y() = std::min(c(heel).y(), c(toe).y()) - 0.05;
    out.push_back(p);
  }
  out.push_back(c(Canonical::HeadTop) + 0.05 * up);
  return out;
}

}  // namespace

ClothedSurface makeClothedSurface(const BodyModel& model, const BodyParams& params,
                                  const Outfit& outfit, const GeometryOptions& options,
                                  Progress& progress) {
  validateOptions(options);
  std::set<std::string> names;
  for (std::size_t i = 0; i < outfit.garments.size(); ++i)
    if (!names.insert(garmentName(outfit.garments[i])).second)
      throw InputError("outfit: garment " + std::to_string(i) + " repeats the name \"" +
                       garmentName(outfit.garments[i]) + "\"; give each garment a unique name");
  ClothedSurface out;
  GeometryStats& st = out.stats;

  // === 1. Body, rest body, layers, body level set.
  auto t0 = Clock::now();
  progress.begin("synth: body level set");
  const PosedBody posed = poseBody(model, params);
  BodyParams restParams;
  restParams.shape = params.shape;
  restParams.pose = BodyPose::zero(model.numJoints());
  const PosedBody rest = poseBody(model, restParams);
  const GarmentLayers layers(rest, posed, outfit, options.seed);
  const BodyField field(posed.mesh, rest.mesh, options.voxelSize,
                        layers.maxEase() + 2 * options.voxelSize);
  progress.end();
  st.secondsBody = since(t0);

  // === 2. CSG union → one closed surface.
  t0 = Clock::now();
  UnionMeshStats us;
  TriMesh mesh = meshUnion(field, layers, &us, progress);
  st.activeVoxels = us.activeVoxels;
  st.removedComponents = us.removedComponents;
  st.levelSetVertices = mesh.numVertices();
  if (us.removedComponents > 0)
    progress.message("synth: dropped " + std::to_string(us.removedComponents) +
                     " floating level-set pieces (" + std::to_string(us.removedFaces) +
                     " faces)");
  st.secondsUnion = since(t0);

  // === 3. Vertex labels and rest positions (vertices survive decimation, so once).
  t0 = Clock::now();
  progress.begin("synth: labels");
  auto labelVertices = [&](const Eigen::MatrixX3d& P, Eigen::VectorXi& label,
                           Eigen::VectorXi& layer, Eigen::MatrixX3d* restPos) {
    const std::vector<BodySample> s = field.samples(P);
    label.resize(P.rows());
    layer.resize(P.rows());
    if (restPos) restPos->resize(P.rows(), 3);
    tbb::parallel_for(0, static_cast<int>(P.rows()), [&](int i) {
      bool gap = false;
      const int l = layers.visibleLayer(P.row(i).transpose(), s[i], &gap);
      layer[i] = l < 0 ? -1 : layers.layer(l).garment;
      label[i] = static_cast<int>(l < 0 ? Label::Skin : gap ? Label::Gap : layers.layer(l).label);
      if (restPos) restPos->row(i) = s[i].rest.transpose();
    });
  };
  labelVertices(mesh.V, out.vertexLabel, out.vertexLayer, &out.restPosition);
  progress.end();
  st.secondsLabels = since(t0);

  // === 4. Decimation.
  t0 = Clock::now();
  if (options.targetVertices > 0 && options.targetVertices < mesh.numVertices()) {
    progress.begin("synth: decimate");
    const Eigen::VectorXi keep = decimateMesh(mesh, options.targetVertices);
    Eigen::VectorXi vl(keep.size()), vy(keep.size());
    Eigen::MatrixX3d rp(keep.size(), 3);
    for (int i = 0; i < keep.size(); ++i) {
      vl[i] = out.vertexLabel[keep[i]];
      vy[i] = out.vertexLayer[keep[i]];
      rp.row(i) = out.restPosition.row(keep[i]);
    }
    out.vertexLabel = vl;
    out.vertexLayer = vy;
    out.restPosition = rp;
    progress.end();
  }
  st.secondsDecimate = since(t0);

  // Face labels at the centroids, and which hidden layers lie under each visible one.
  t0 = Clock::now();
  Eigen::MatrixX3d C(mesh.numFaces(), 3);
  for (int f = 0; f < mesh.numFaces(); ++f)
    C.row(f) = (mesh.V.row(mesh.F(f, 0)) + mesh.V.row(mesh.F(f, 1)) + mesh.V.row(mesh.F(f, 2))) / 3;
  labelVertices(C, out.faceLabel, out.faceLayer, nullptr);
  const int ng = static_cast<int>(outfit.garments.size());
  Eigen::MatrixXd hidden = Eigen::MatrixXd::Zero(ng, ng);  // area of j under visible k
  {
    const std::vector<BodySample> s = field.samples(C);
    const Eigen::VectorXd area = faceAreas(mesh);
    for (int f = 0; f < mesh.numFaces(); ++f) {
      if (out.faceLayer[f] < 0) continue;
      // j lies under the visible garment where its body-following region covers the body.
      for (int j = 0; j < layers.size(); ++j) {
        const GarmentLayer& L = layers.layer(j);
        if (L.garment != out.faceLayer[f] && L.fitted &&
            L.region(layers.skeleton(), s[f].rest) > 0.002)
          hidden(out.faceLayer[f], L.garment) += area[f];
      }
    }
  }
  st.secondsLabels += since(t0);

  // === 5. Noise, and the true boundaries: found on the clean (decimated) surface, placed on the
  // noisy one. Holes are cut after: the truth keeps the stretches a hole swallows.
  t0 = Clock::now();
  TriMesh noisy = mesh;
  addNormalNoise(noisy, options.noise, options.seed);
  st.secondsCorrupt = since(t0);
  t0 = Clock::now();
  progress.begin("synth: boundaries");
  out.boundaries = computeBoundaries(mesh, noisy.V, out.vertexLabel, layers, field);
  progress.end();
  st.secondsBoundaries = since(t0);
  mesh = std::move(noisy);

  // === 6. Holes.
  t0 = Clock::now();
  if (options.holes > 0) {
    const double scale = std::max(posed.mesh.V.col(1).maxCoeff() - posed.mesh.V.col(1).minCoeff(),
                                  0.5) / 1.75;
    std::vector<Eigen::Vector3d> centres = holeCentres(posed, scale);
    centres.resize(options.holes);
    const HoleCut cut = cutHoles(mesh, centres, options.holeRadius);
    st.holes = cut.holes;
    auto pickRows = [](const Eigen::VectorXi& v, const Eigen::VectorXi& idx) {
      Eigen::VectorXi r(idx.size());
      for (int i = 0; i < idx.size(); ++i) r[i] = v[idx[i]];
      return r;
    };
    out.vertexLabel = pickRows(out.vertexLabel, cut.keptVertices);
    out.vertexLayer = pickRows(out.vertexLayer, cut.keptVertices);
    out.faceLabel = pickRows(out.faceLabel, cut.keptFaces);
    out.faceLayer = pickRows(out.faceLayer, cut.keptFaces);
    Eigen::MatrixX3d rp(cut.keptVertices.size(), 3);
    for (int i = 0; i < cut.keptVertices.size(); ++i)
      rp.row(i) = out.restPosition.row(cut.keptVertices[i]);
    out.restPosition = rp;
  }
  st.secondsCorrupt += since(t0);

  // === 7. Garments' truth.
  const Eigen::VectorXd area = faceAreas(mesh);
  for (int g = 0; g < ng; ++g) {
    const GarmentSpec& s = outfit.garments[g];
    TrueGarment t;
    t.name = garmentName(s);
    t.type = toString(s.type);
    t.label = labelOf(s.type);
    t.onePiece = isOnePiece(s.type);
    const ExpectedPattern pattern = expectedPattern(s.type);
    t.patternType = pattern.type;
    t.panels = pattern.panels;
    for (int f = 0; f < mesh.numFaces(); ++f)
      if (out.faceLayer[f] == g && out.faceLabel[f] != static_cast<int>(Label::Gap))
        t.visibleArea += area[f];
    for (int j = 0; j < ng; ++j)
      if (j != g && hidden(g, j) > 4e-4) t.occludes.push_back(garmentName(outfit.garments[j]));
    out.garments.push_back(std::move(t));
  }
  out.mesh = std::move(mesh);
  return out;
}

}  // namespace s2p
