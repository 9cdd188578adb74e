#include "synth/raw_scan.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <queue>
#include <random>
#include <set>
#include <vector>

#include "core/error.h"
#include "core/labels.h"
#include "synth/synthesize.h"

namespace s2p {
namespace {

// Keeps the faces with keep[f] and the vertices they use, in order; every per-vertex and
// per-face array of the scan follows.
void keepFacesOf(SynthScan& s, const std::vector<bool>& keep) {
  TriMesh& m = s.scan.mesh;
  std::vector<int> newIndex(m.numVertices(), -1);
  int nf = 0;
  for (int f = 0; f < m.numFaces(); ++f)
    if (keep[f]) {
      ++nf;
      for (int k = 0; k < 3; ++k) newIndex[m.F(f, k)] = 0;
    }
  int nv = 0;
  for (int& i : newIndex)
    if (i == 0) i = nv++;
  Eigen::MatrixX3d V(nv, 3), colour(nv, 3), rest(nv, 3);
  Eigen::VectorXi vl(nv);
  for (int v = 0; v < m.numVertices(); ++v) {
    const int i = newIndex[v];
    if (i < 0) continue;
    V.row(i) = m.V.row(v);
    colour.row(i) = s.scan.colour.row(v);
    rest.row(i) = s.restPosition.row(v);
    vl[i] = s.vertexLabel[v];
  }
  Eigen::MatrixX3i F(nf, 3);
  Eigen::VectorXi fl(nf), fy(nf);
  for (int f = 0, j = 0; f < m.numFaces(); ++f) {
    if (!keep[f]) continue;
    for (int k = 0; k < 3; ++k) F(j, k) = newIndex[m.F(f, k)];
    fl[j] = s.faceLabel[f];
    fy[j] = s.faceLayer[f];
    ++j;
  }
  m.V = std::move(V);
  m.F = std::move(F);
  s.scan.colour = std::move(colour);
  s.restPosition = std::move(rest);
  s.vertexLabel = std::move(vl);
  s.faceLabel = std::move(fl);
  s.faceLayer = std::move(fy);
}

Eigen::Vector3d centroid(const TriMesh& m, int f) {
  return (m.V.row(m.F(f, 0)) + m.V.row(m.F(f, 1)) + m.V.row(m.F(f, 2))).transpose() / 3.0;
}

// Cuts discs of faces (all corners within the radius of the seed face's centroid, reached
// through shared vertices) around each seed in `seeds`; a disc that would touch faces already
// removed is skipped, so holes stay apart. Returns the holes cut.
int cutDiscs(SynthScan& s, const std::vector<std::pair<int, double>>& seeds) {
  const TriMesh& m = s.scan.mesh;
  std::vector<std::vector<int>> vertexFaces(m.numVertices());
  for (int f = 0; f < m.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) vertexFaces[m.F(f, k)].push_back(f);
  std::vector<bool> keep(m.numFaces(), true);
  std::vector<char> nearRemoved(m.numVertices(), 0);  // a vertex of a removed face
  int holes = 0;
  for (const auto& [seed, r] : seeds) {
    if (!keep[seed]) continue;
    const Eigen::Vector3d c = centroid(m, seed);
    std::vector<int> disc{seed};
    std::map<int, bool> seen{{seed, true}};
    bool clash = false;
    for (std::size_t i = 0; i < disc.size() && !clash; ++i)
      for (int k = 0; k < 3 && !clash; ++k) {
        const int v = m.F(disc[i], k);
        if (nearRemoved[v]) clash = true;
        for (int g : vertexFaces[v]) {
          if (seen.count(g)) continue;
          seen[g] = true;
          bool inside = true;
          for (int q = 0; q < 3; ++q)
            if ((m.V.row(m.F(g, q)).transpose() - c).norm() > r) inside = false;
          if (inside) disc.push_back(g);
        }
      }
    if (clash) continue;
    for (int f : disc) {
      keep[f] = false;
      for (int k = 0; k < 3; ++k) nearRemoved[m.F(f, k)] = 1;
    }
    ++holes;
  }
  keepFacesOf(s, keep);
  return holes;
}

// Floor remnants: patches of a 2 cm grid at floorGap under the lowest point, each an irregular
// disc about floorPatchSize wide centred beside the feet, without the cells under the feet.
int addFloor(SynthScan& s, const RawScanOptions& o, std::mt19937_64& rng) {
  TriMesh& m = s.scan.mesh;
  const double minY = m.V.col(1).minCoeff();
  std::vector<Eigen::Vector2d> feet;  // xz of the soles' vertices
  for (int v = 0; v < m.numVertices(); ++v)
    if (m.V(v, 1) < minY + 0.04) feet.emplace_back(m.V(v, 0), m.V(v, 2));
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const auto& p : feet) centre += p;
  centre /= std::max<std::size_t>(1, feet.size());
  std::uniform_real_distribution<double> u(0, 1);
  const double h = 0.02;
  const int n = std::max(2, static_cast<int>(std::ceil(o.floorPatchSize / h)));
  std::vector<Eigen::Vector3d> newV;
  std::vector<Eigen::Vector3i> newF;
  const Eigen::Vector3d floorColour(0.55, 0.53, 0.50);
  std::vector<Eigen::Vector3d> newColour;
  for (int p = 0; p < o.floorPatches; ++p) {
    const double angle = 2 * M_PI * (p + 0.3 * u(rng)) / o.floorPatches;
    const double reach = 0.12 + 0.08 * u(rng);
    const Eigen::Vector2d c = centre + reach * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    const double radius = 0.5 * o.floorPatchSize;
    const double wobble = 2 * M_PI * u(rng);
    auto cellKept = [&](int i, int j) {
      const Eigen::Vector2d q =
          c + Eigen::Vector2d((i + 0.5 - 0.5 * n) * h, (j + 0.5 - 0.5 * n) * h);
      const double a = std::atan2(q.y() - c.y(), q.x() - c.x());
      if ((q - c).norm() > radius * (0.75 + 0.25 * std::sin(3 * a + wobble))) return false;
      for (const auto& f : feet)
        if ((f - q).norm() < 0.02) return false;  // under a foot: no camera saw the floor there
      return true;
    };
    std::vector<int> index((n + 1) * (n + 1), -1);
    auto vertex = [&](int i, int j) {
      int& id = index[i * (n + 1) + j];
      if (id < 0) {
        id = static_cast<int>(m.numVertices() + newV.size());
        const Eigen::Vector2d q = c + Eigen::Vector2d((i - 0.5 * n) * h, (j - 0.5 * n) * h);
        newV.emplace_back(q.x(), minY - o.floorGap + 0.001 * (u(rng) - 0.5), q.y());
        newColour.push_back(floorColour * (0.92 + 0.16 * u(rng)));
      }
      return id;
    };
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        if (!cellKept(i, j)) continue;
        const int v00 = vertex(i, j), v01 = vertex(i, j + 1), v10 = vertex(i + 1, j),
                  v11 = vertex(i + 1, j + 1);
        newF.emplace_back(v00, v01, v10);  // normals +Y
        newF.emplace_back(v10, v01, v11);
      }
  }
  const int nv0 = m.numVertices(), nf0 = m.numFaces();
  const int nv = nv0 + static_cast<int>(newV.size()), nf = nf0 + static_cast<int>(newF.size());
  m.V.conservativeResize(nv, 3);
  s.scan.colour.conservativeResize(nv, 3);
  s.restPosition.conservativeResize(nv, 3);
  s.vertexLabel.conservativeResize(nv);
  for (std::size_t i = 0; i < newV.size(); ++i) {
    const int v = nv0 + static_cast<int>(i);
    m.V.row(v) = newV[i].transpose();
    s.scan.colour.row(v) = newColour[i].cwiseMin(1.0).transpose();
    s.restPosition.row(v).setZero();
    s.vertexLabel[v] = static_cast<int>(Label::Other);
  }
  m.F.conservativeResize(nf, 3);
  s.faceLabel.conservativeResize(nf);
  s.faceLayer.conservativeResize(nf);
  for (std::size_t i = 0; i < newF.size(); ++i) {
    const int f = nf0 + static_cast<int>(i);
    m.F.row(f) = newF[i].transpose();
    s.faceLabel[f] = static_cast<int>(Label::Other);
    s.faceLayer[f] = -1;
  }
  return static_cast<int>(newF.size());
}

// Splits the faces into `charts` charts (nearest of seeds spread by farthest-point sampling over
// the face centroids) and gives every vertex one copy per chart among its faces.
int splitCharts(SynthScan& s, int charts, std::mt19937_64& rng) {
  TriMesh& m = s.scan.mesh;
  const int nf = m.numFaces();
  Eigen::MatrixX3d C(nf, 3);
  for (int f = 0; f < nf; ++f) C.row(f) = centroid(m, f).transpose();
  std::vector<int> seeds{static_cast<int>(rng() % static_cast<std::uint64_t>(nf))};
  Eigen::VectorXd dist = (C.rowwise() - C.row(seeds[0])).rowwise().norm();
  Eigen::VectorXi chart = Eigen::VectorXi::Zero(nf);
  for (int k = 1; k < charts; ++k) {
    int far = 0;
    dist.maxCoeff(&far);
    seeds.push_back(far);
    const Eigen::VectorXd d = (C.rowwise() - C.row(far)).rowwise().norm();
    for (int f = 0; f < nf; ++f)
      if (d[f] < dist[f]) dist[f] = d[f], chart[f] = k;
  }
  std::map<std::pair<int, int>, int> copyOf;  // (vertex, chart) → copy
  std::vector<int> firstChart(m.numVertices(), -1);
  std::vector<int> origin;
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int v = m.F(f, k);
      if (firstChart[v] < 0) firstChart[v] = chart[f];
      if (firstChart[v] == chart[f]) continue;
      auto [it, added] =
          copyOf.try_emplace({v, chart[f]}, m.numVertices() + static_cast<int>(origin.size()));
      if (added) origin.push_back(v);
      m.F(f, k) = it->second;
    }
  const int nv0 = m.numVertices(), nv = nv0 + static_cast<int>(origin.size());
  m.V.conservativeResize(nv, 3);
  s.scan.colour.conservativeResize(nv, 3);
  s.restPosition.conservativeResize(nv, 3);
  s.vertexLabel.conservativeResize(nv);
  for (std::size_t i = 0; i < origin.size(); ++i) {
    const int v = nv0 + static_cast<int>(i), o = origin[i];
    m.V.row(v) = m.V.row(o);
    s.scan.colour.row(v) = s.scan.colour.row(o);
    s.restPosition.row(v) = s.restPosition.row(o);
    s.vertexLabel[v] = s.vertexLabel[o];
  }
  return static_cast<int>(origin.size());
}

}  // namespace

nlohmann::json rawScanOptionsToJson(const RawScanOptions& o) {
  return {{"small_holes", o.smallHoles},
          {"small_hole_radius", o.smallHoleRadius},
          {"unseen_under_hem", o.unseenUnderHem},
          {"unseen_below_hem", o.unseenBelowHem},
          {"hem_holes", o.hemHoles},
          {"floor_patches", o.floorPatches},
          {"floor_patch_size", o.floorPatchSize},
          {"floor_gap", o.floorGap},
          {"texture_charts", o.textureCharts},
          {"quantisation", o.quantisation},
          {"detach_shoes", o.detachShoes},
          {"fins", o.fins}};
}

RawScanOptions rawScanOptionsFromJson(const nlohmann::json& j) {
  RawScanOptions o;
  if (!j.is_object()) throw InputError("synth options: raw_scan must be a JSON object");
  o.smallHoles = j.value("small_holes", o.smallHoles);
  o.smallHoleRadius = j.value("small_hole_radius", o.smallHoleRadius);
  o.unseenUnderHem = j.value("unseen_under_hem", o.unseenUnderHem);
  o.unseenBelowHem = j.value("unseen_below_hem", o.unseenBelowHem);
  o.hemHoles = j.value("hem_holes", o.hemHoles);
  o.floorPatches = j.value("floor_patches", o.floorPatches);
  o.floorPatchSize = j.value("floor_patch_size", o.floorPatchSize);
  o.floorGap = j.value("floor_gap", o.floorGap);
  o.textureCharts = j.value("texture_charts", o.textureCharts);
  o.quantisation = j.value("quantisation", o.quantisation);
  o.detachShoes = j.value("detach_shoes", o.detachShoes);
  o.fins = j.value("fins", o.fins);
  validateRawScanOptions(o);
  return o;
}

void validateRawScanOptions(const RawScanOptions& o) {
  auto in = [](double x, double lo, double hi) { return std::isfinite(x) && x >= lo && x <= hi; };
  if (o.smallHoles < 0 || o.smallHoles > 400)
    throw InputError("synth raw scan: small_holes must be in [0, 400]");
  if (!in(o.smallHoleRadius, 0.003, 0.05))
    throw InputError("synth raw scan: small_hole_radius must be in [0.003, 0.05] m");
  if (!in(o.unseenBelowHem, 0, 0.3))
    throw InputError("synth raw scan: unseen_below_hem must be in [0, 0.3] m");
  if (o.hemHoles < 0 || o.hemHoles > 40)
    throw InputError("synth raw scan: hem_holes must be in [0, 40]");
  if (o.floorPatches < 0 || o.floorPatches > 8)
    throw InputError("synth raw scan: floor_patches must be in [0, 8]");
  if (!in(o.floorPatchSize, 0.05, 1.0))
    throw InputError("synth raw scan: floor_patch_size must be in [0.05, 1] m");
  if (!in(o.floorGap, 0.001, 0.1))
    throw InputError("synth raw scan: floor_gap must be in [0.001, 0.1] m");
  if (o.textureCharts < 0 || o.textureCharts > 500)
    throw InputError("synth raw scan: texture_charts must be in [0, 500]");
  if (!in(o.quantisation, 0, 0.01))
    throw InputError("synth raw scan: quantisation must be in [0, 0.01] m");
  if (o.fins < 0 || o.fins > 200) throw InputError("synth raw scan: fins must be in [0, 200]");
}

RawScanStats degradeScan(SynthScan& s, const RawScanOptions& o, std::uint64_t seed) {
  validateRawScanOptions(o);
  RawScanStats st;
  std::mt19937_64 rng(seed ^ 0x5EEDF00DCAFEull);
  std::uniform_real_distribution<double> u(0, 1);
  const int lower = static_cast<int>(Label::Lower), gap = static_cast<int>(Label::Gap),
            skin = static_cast<int>(Label::Skin);

  // === The legs under a free-hanging hem: the gap cap and the thighs' skin from
  // unseenBelowHem under the hem's lowest point up to the garment's top; legs are told from
  // hands by their rest position lying within the lower garment's rest-pose width.
  if (o.unseenUnderHem) {
    TriMesh& m = s.scan.mesh;
    double hemY = INFINITY, topY = -INFINITY, restMinX = INFINITY, restMaxX = -INFINITY;
    for (int v = 0; v < m.numVertices(); ++v)
      if (s.vertexLabel[v] == lower) {
        hemY = std::min(hemY, m.V(v, 1));
        topY = std::max(topY, m.V(v, 1));
        restMinX = std::min(restMinX, s.restPosition(v, 0));
        restMaxX = std::max(restMaxX, s.restPosition(v, 0));
      }
    std::vector<bool> keep(m.numFaces(), true);
    for (int f = 0; f < m.numFaces(); ++f) {
      if (s.faceLabel[f] == gap) keep[f] = false;
      if (s.faceLabel[f] != skin) continue;
      const double y = centroid(m, f).y();
      double rx = 0;
      for (int k = 0; k < 3; ++k) rx += s.restPosition(m.F(f, k), 0) / 3;
      if (y > hemY - o.unseenBelowHem && y < topY && rx > restMinX && rx < restMaxX)
        keep[f] = false;
    }
    st.unseenFaces = static_cast<int>(std::count(keep.begin(), keep.end(), false));
    keepFacesOf(s, keep);
    auto& b = s.truth.boundaries;
    b.erase(std::remove_if(
                b.begin(), b.end(),
                [](const TrueBoundary& t) { return t.a == Label::Gap || t.b == Label::Gap; }),
            b.end());
  }

  // === Holes: along the hem first, then anywhere.
  {
    const TriMesh& m = s.scan.mesh;
    std::vector<std::pair<int, double>> seeds;
    if (o.hemHoles > 0) {
      double hemY = INFINITY;
      for (int f = 0; f < m.numFaces(); ++f)
        if (s.faceLabel[f] == lower) hemY = std::min(hemY, centroid(m, f).y());
      std::vector<int> hem;
      for (int f = 0; f < m.numFaces(); ++f)
        if (s.faceLabel[f] == lower && centroid(m, f).y() < hemY + 0.03) hem.push_back(f);
      for (int i = 0; i < o.hemHoles && !hem.empty(); ++i)
        seeds.emplace_back(hem[rng() % hem.size()], o.smallHoleRadius * (0.6 + 0.8 * u(rng)));
    }
    for (int i = 0; i < o.smallHoles && m.numFaces() > 0; ++i)
      seeds.emplace_back(static_cast<int>(rng() % static_cast<std::uint64_t>(m.numFaces())),
                         o.smallHoleRadius * (0.6 + 0.8 * u(rng)));
    if (!seeds.empty()) st.holes = cutDiscs(s, seeds);
  }

  // === Shoes apart: every shoe face with a corner shared with a face of another label goes.
  if (o.detachShoes) {
    const TriMesh& m = s.scan.mesh;
    const int shoes = static_cast<int>(Label::Shoes);
    std::vector<char> touchesOther(m.numVertices(), 0);
    for (int f = 0; f < m.numFaces(); ++f)
      if (s.faceLabel[f] != shoes)
        for (int k = 0; k < 3; ++k) touchesOther[m.F(f, k)] = 1;
    std::vector<bool> keep(m.numFaces(), true);
    for (int f = 0; f < m.numFaces(); ++f)
      if (s.faceLabel[f] == shoes)
        for (int k = 0; k < 3; ++k)
          if (touchesOther[m.F(f, k)]) keep[f] = false;
    st.detachedFaces = static_cast<int>(std::count(keep.begin(), keep.end(), false));
    keepFacesOf(s, keep);
  }

  // === Fins: a triangle 6 mm high standing along the normal on an edge of a random face.
  if (o.fins > 0) {
    TriMesh& m = s.scan.mesh;
    const int nf0 = m.numFaces(), nv0 = m.numVertices();
    std::vector<std::pair<int, int>> edges;
    std::set<std::pair<int, int>> used;
    for (int i = 0; i < 20 * o.fins && static_cast<int>(edges.size()) < o.fins; ++i) {
      const int f = static_cast<int>(rng() % static_cast<std::uint64_t>(nf0));
      const int k = static_cast<int>(rng() % 3);
      const int a = m.F(f, k), b = m.F(f, (k + 1) % 3);
      if (used.insert({std::min(a, b), std::max(a, b)}).second) edges.emplace_back(a, b);
    }
    const Eigen::MatrixX3d N = vertexNormals(m);
    const int n = static_cast<int>(edges.size());
    m.V.conservativeResize(nv0 + n, 3);
    s.scan.colour.conservativeResize(nv0 + n, 3);
    s.restPosition.conservativeResize(nv0 + n, 3);
    s.vertexLabel.conservativeResize(nv0 + n);
    m.F.conservativeResize(nf0 + n, 3);
    s.faceLabel.conservativeResize(nf0 + n);
    s.faceLayer.conservativeResize(nf0 + n);
    for (int i = 0; i < n; ++i) {
      const auto [a, b] = edges[i];
      const int v = nv0 + i, f = nf0 + i;
      const Eigen::RowVector3d normal = (N.row(a) + N.row(b)).normalized();
      m.V.row(v) = 0.5 * (m.V.row(a) + m.V.row(b)) + 0.006 * normal;
      s.scan.colour.row(v) = s.scan.colour.row(a);
      s.restPosition.row(v) = s.restPosition.row(a);
      s.vertexLabel[v] = s.vertexLabel[a];
      m.F.row(f) << a, b, v;
      s.faceLabel[f] = s.vertexLabel[a];
      s.faceLayer[f] = -1;
      for (int g = 0; g < nf0; ++g)  // the layer of a face on that edge
        if ((m.F.row(g).array() == a).any() && (m.F.row(g).array() == b).any()) {
          s.faceLayer[f] = s.faceLayer[g];
          s.faceLabel[f] = s.faceLabel[g];
          break;
        }
    }
    st.fins = n;
  }

  if (o.floorPatches > 0) st.floorFaces = addFloor(s, o, rng);
  if (o.textureCharts > 1) {
    st.charts = o.textureCharts;
    st.duplicatedVertices = splitCharts(s, o.textureCharts, rng);
  }
  if (o.quantisation > 0)
    s.scan.mesh.V = ((s.scan.mesh.V / o.quantisation).array().round() * o.quantisation).matrix();
  return st;
}

}  // namespace s2p
