#include "body/mannequin.h"

#include "body/level_set_mesh.h"

#include <openvdb/openvdb.h>
#include <tbb/parallel_for.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <numeric>
#include <string>
#include <unordered_map>

#include "core/error.h"

namespace s2p {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct ParamInfo {
  const char* name;
  const char* description;
  double MannequinMeasurements::*field;
  // The range the fit may use (cm from the base body): 10 below the base, and further above it
  // where people are: adult waists reach 130 cm (the base is 82), and a fit held at +10 leaves a
  // fuller body too thin under its clothes (the suite's plus_size, waist +18: its trousers,
  // sized for the true waist, slid 10 cm down the fitted one in the drape check).
  double min, max;
};

const std::array<ParamInfo, kMannequinShapes>& paramInfo() {
  static const std::array<ParamInfo, kMannequinShapes> info = {{
      {"height", "height, floor to head top; +1 = +1 cm", &MannequinMeasurements::height, -10,
       25},
      {"chest", "chest girth (horizontal tape at chest level); +1 = +1 cm",
       &MannequinMeasurements::chest, -10, 40},
      {"waist", "waist girth (horizontal tape at waist level); +1 = +1 cm",
       &MannequinMeasurements::waist, -10, 45},
      {"hip", "hip girth (horizontal tape at the fullest buttocks); +1 = +1 cm",
       &MannequinMeasurements::hip, -10, 40},
      {"shoulder", "distance between the shoulder joints; +1 = +1 cm",
       &MannequinMeasurements::shoulder, -10, 10},
      {"arm", "arm length, shoulder joint to elbow to wrist; +1 = +1 cm",
       &MannequinMeasurements::armLength, -10, 10},
      {"inseam", "inseam, floor to crotch; +1 = +1 cm", &MannequinMeasurements::inseam, -10, 15},
      {"neck", "neck girth; +1 = +1 cm", &MannequinMeasurements::neck, -10, 12},
      {"thigh", "thigh girth 5 cm below the crotch; +1 = +1 cm", &MannequinMeasurements::thigh,
       -10, 25},
      {"upper_arm", "upper-arm girth at mid shoulder-elbow; +1 = +1 cm",
       &MannequinMeasurements::upperArm, -10, 16},
  }};
  return info;
}

std::vector<std::vector<int>> vertexNeighbours(const TriMesh& mesh) {
  std::vector<std::vector<int>> nb(mesh.numVertices());
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      nb[a].push_back(b);
      nb[b].push_back(a);
    }
  for (auto& n : nb) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  return nb;
}

// Keeps the face-connected component with the most faces.
void keepLargestComponent(TriMesh& mesh) {
  const int nv = mesh.numVertices();
  std::vector<int> parent(nv);
  std::iota(parent.begin(), parent.end(), 0);
  std::function<int(int)> find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 1; k < 3; ++k) parent[find(mesh.F(f, k))] = find(mesh.F(f, 0));
  std::unordered_map<int, int> count;
  for (int f = 0; f < mesh.numFaces(); ++f) ++count[find(mesh.F(f, 0))];
  int best = -1, bestCount = -1;
  for (const auto& [root, c] : count)
    if (c > bestCount || (c == bestCount && root < best)) best = root, bestCount = c;
  Eigen::MatrixX3i F(bestCount, 3);
  int n = 0;
  for (int f = 0; f < mesh.numFaces(); ++f)
    if (find(mesh.F(f, 0)) == best) F.row(n++) = mesh.F.row(f);
  mesh.F = F;
  std::vector<int> newIndex(nv, -1);
  int m = 0;
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k)
      if (newIndex[mesh.F(f, k)] < 0) newIndex[mesh.F(f, k)] = 0;
  for (int v = 0; v < nv; ++v)
    if (newIndex[v] == 0) newIndex[v] = m++;
  Eigen::MatrixX3d V(m, 3);
  for (int v = 0; v < nv; ++v)
    if (newIndex[v] >= 0) V.row(newIndex[v]) = mesh.V.row(v);
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) mesh.F(f, k) = newIndex[mesh.F(f, k)];
  mesh.V = V;
}

// Empty when the mesh is a closed, consistently oriented 2-manifold; else what is wrong.
std::string closedManifoldProblem(const TriMesh& mesh) {
  std::map<std::pair<int, int>, int> directed;
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      if (a == b) return "degenerate face " + std::to_string(f);
      if (++directed[{a, b}] > 1)
        return "edge used twice in one direction at face " + std::to_string(f);
    }
  for (const auto& [e, c] : directed)
    if (!directed.count({e.second, e.first}))
      return "boundary edge " + std::to_string(e.first) + "-" + std::to_string(e.second);
  // One fan per vertex: walking around v through faces must visit all its faces.
  std::vector<std::vector<std::pair<int, int>>> fan(mesh.numVertices());  // (next, prev)
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k)
      fan[mesh.F(f, k)].emplace_back(mesh.F(f, (k + 1) % 3), mesh.F(f, (k + 2) % 3));
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const auto& fv = fan[v];
    if (fv.empty()) continue;
    std::unordered_map<int, int> byPrev;
    for (size_t i = 0; i < fv.size(); ++i) byPrev[fv[i].second] = static_cast<int>(i);
    size_t steps = 0;
    int cur = 0;
    do {
      auto it = byPrev.find(fv[cur].first);
      if (it == byPrev.end()) return "open fan at vertex " + std::to_string(v);
      cur = it->second;
      ++steps;
    } while (cur != 0 && steps <= fv.size());
    if (steps != fv.size()) return "non-manifold vertex " + std::to_string(v);
  }
  return {};
}

}  // namespace

// === Measurements ↔ shape vector

MannequinMeasurements mannequinMeasurements(const MannequinMeasurements& base,
                                            const Eigen::VectorXd& shape) {
  if (shape.size() != kMannequinShapes)
    throw InputError("mannequin: shape vector has " + std::to_string(shape.size()) +
                     " entries, expected " + std::to_string(kMannequinShapes));
  MannequinMeasurements m = base;
  for (int i = 0; i < kMannequinShapes; ++i) m.*(paramInfo()[i].field) += 0.01 * shape[i];
  return m;
}

Eigen::VectorXd mannequinShapeFor(const MannequinMeasurements& base,
                                  const MannequinMeasurements& target) {
  Eigen::VectorXd beta(kMannequinShapes);
  for (int i = 0; i < kMannequinShapes; ++i)
    beta[i] = 100.0 * (target.*(paramInfo()[i].field) - base.*(paramInfo()[i].field));
  return beta;
}

// === Meshing

TriMesh meshMannequinImplicit(const MannequinImplicit& body, double voxel) {
  if (!(voxel > 0.002 && voxel < 0.1))
    throw InputError("mannequin: voxel size " + std::to_string(voxel) + " m is outside 2–100 mm");
  openvdb::initialize();
  Eigen::Vector3d lo = body.boxMin();
  const Eigen::Vector3d hi = body.boxMax();
  const Eigen::Vector3i n = ((hi - lo) / voxel).array().ceil().cast<int>() + 1;
  lo.x() = -0.5 * (n.x() - 1) * voxel;  // samples symmetric about x = 0: a mirror-symmetric mesh
  const double band = 3 * voxel;
  constexpr int kBlock = 8;
  const Eigen::Vector3i nb = (n.array() + kBlock - 1) / kBlock;
  std::vector<float> value(static_cast<size_t>(n.prod()), static_cast<float>(band));
  const double blockRadius = 0.5 * std::sqrt(3.0) * kBlock * voxel;
  tbb::parallel_for(0, nb.prod(), [&](int b) {
    const int bx = b % nb.x(), by = (b / nb.x()) % nb.y(), bz = b / (nb.x() * nb.y());
    const Eigen::Vector3d c = lo + voxel * (Eigen::Vector3d(bx, by, bz) * kBlock +
                                            Eigen::Vector3d::Constant(0.5 * (kBlock - 1)));
    if (body.lowerBound(c) - blockRadius > band + 0.05) return;
    for (int k = bz * kBlock; k < std::min((bz + 1) * kBlock, n.z()); ++k)
      for (int j = by * kBlock; j < std::min((by + 1) * kBlock, n.y()); ++j)
        for (int i = bx * kBlock; i < std::min((bx + 1) * kBlock, n.x()); ++i) {
          const double f = body.value(lo + voxel * Eigen::Vector3d(i, j, k));
          value[(static_cast<size_t>(k) * n.y() + j) * n.x() + i] =
              static_cast<float>(std::clamp(f, -band, band));
        }
  });
  auto grid = openvdb::FloatGrid::create(static_cast<float>(band));
  auto acc = grid->getAccessor();
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) {
        const float f = value[(static_cast<size_t>(k) * n.y() + j) * n.x() + i];
        if (std::abs(f) < band)
          acc.setValueOn(openvdb::Coord(i, j, k), f);
        else if (f < 0)
          acc.setValueOff(openvdb::Coord(i, j, k), -static_cast<float>(band));
      }
  // Index-space points (the grid has the identity transform) mapped to the box.
  TriMesh mesh = levelSetToMesh(*grid);
  mesh.V = ((voxel * mesh.V).rowwise() + lo.transpose()).eval();
  keepLargestComponent(mesh);
  // Outward orientation: positive enclosed volume.
  double volume = 0;
  for (int i = 0; i < mesh.numFaces(); ++i)
    volume += mesh.V.row(mesh.F(i, 0))
                  .dot(Eigen::Vector3d(mesh.V.row(mesh.F(i, 1)))
                           .cross(Eigen::Vector3d(mesh.V.row(mesh.F(i, 2)))));
  if (volume < 0) mesh.F.col(1).swap(mesh.F.col(2));

  // Project onto the exact surface, then tangential relaxation passes re-projected.
  const auto nbs = vertexNeighbours(mesh);
  const int nv = mesh.numVertices();
  tbb::parallel_for(0, nv, [&](int v) { mesh.V.row(v) = body.project(mesh.V.row(v).transpose()); });
  for (int pass = 0; pass < 4; ++pass) {
    const Eigen::MatrixX3d N = vertexNormals(mesh);
    Eigen::MatrixX3d next = mesh.V;
    tbb::parallel_for(0, nv, [&](int v) {
      Eigen::Vector3d c = Eigen::Vector3d::Zero();
      for (int w : nbs[v]) c += mesh.V.row(w).transpose();
      c /= static_cast<double>(nbs[v].size());
      Eigen::Vector3d d = c - mesh.V.row(v).transpose();
      const Eigen::Vector3d nrm = N.row(v).transpose();
      d -= d.dot(nrm) * nrm;
      next.row(v) = body.project(mesh.V.row(v).transpose() + 0.6 * d, 3);
    });
    mesh.V = next;
  }
  return mesh;
}

// === The model

namespace {

// Mesh section with the plane through `p` ⟂ `n`: the loop enclosing p as (vertex, weight)
// pairs whose weighted mean is the arc-length centroid of the loop. Empty when none encloses p.
std::vector<std::pair<int, double>> sectionRing(const TriMesh& mesh, const Eigen::Vector3d& p,
                                                const Eigen::Vector3d& n) {
  const int nv = mesh.numVertices();
  Eigen::VectorXd s(nv);
  for (int v = 0; v < nv; ++v) s[v] = (mesh.V.row(v).transpose() - p).dot(n);
  // Each crossed face yields a segment between two crossed edges (keys a*nv+b, a<b).
  std::unordered_map<long long, std::vector<long long>> adj;
  auto key = [&](int a, int b) {
    return static_cast<long long>(std::min(a, b)) * nv + std::max(a, b);
  };
  for (int f = 0; f < mesh.numFaces(); ++f) {
    std::vector<long long> e;
    for (int k = 0; k < 3; ++k) {
      const int a = mesh.F(f, k), b = mesh.F(f, (k + 1) % 3);
      if ((s[a] >= 0) != (s[b] >= 0)) e.push_back(key(a, b));
    }
    if (e.size() == 2) {
      adj[e[0]].push_back(e[1]);
      adj[e[1]].push_back(e[0]);
    }
  }
  Eigen::Vector3d e1 = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  e1 = (e1 - e1.dot(n) * n).normalized();
  const Eigen::Vector3d e2 = n.cross(e1);
  auto point = [&](long long k) {
    const int a = static_cast<int>(k / nv), b = static_cast<int>(k % nv);
    const double l = s[a] / (s[a] - s[b]);
    return Eigen::Vector3d((1 - l) * mesh.V.row(a) + l * mesh.V.row(b));
  };
  std::unordered_map<long long, bool> seen;
  std::vector<long long> best;
  double bestArea = 1e9;
  for (const auto& [start, _] : adj) {
    if (seen[start]) continue;
    std::vector<long long> loop;
    long long prev = -1, cur = start;
    while (!seen[cur]) {
      seen[cur] = true;
      loop.push_back(cur);
      const auto& nx = adj[cur];
      long long next = -1;
      for (long long c : nx)
        if (c != prev && !seen[c]) next = c;
      if (next < 0) break;
      prev = cur;
      cur = next;
    }
    // Point-in-polygon (crossing number) and area in the plane.
    bool inside = false;
    double area = 0;
    for (size_t i = 0; i < loop.size(); ++i) {
      const Eigen::Vector3d a3 = point(loop[i]) - p, b3 = point(loop[(i + 1) % loop.size()]) - p;
      const Eigen::Vector2d a(a3.dot(e1), a3.dot(e2)), b(b3.dot(e1), b3.dot(e2));
      area += 0.5 * (a.x() * b.y() - a.y() * b.x());
      if ((a.y() > 0) != (b.y() > 0) && a.x() + (b.x() - a.x()) * (0 - a.y()) / (b.y() - a.y()) > 0)
        inside = !inside;
    }
    if (inside && std::abs(area) < bestArea) bestArea = std::abs(area), best = loop;
  }
  std::map<int, double> w;
  double total = 0;
  for (size_t i = 0; i < best.size(); ++i) {
    const long long k = best[i];
    const double len = 0.5 * ((point(best[(i + 1) % best.size()]) - point(k)).norm() +
                              (point(best[(i + best.size() - 1) % best.size()]) - point(k)).norm());
    const int a = static_cast<int>(k / nv), b = static_cast<int>(k % nv);
    const double l = s[a] / (s[a] - s[b]);
    w[a] += (1 - l) * len;
    w[b] += l * len;
    total += len;
  }
  std::vector<std::pair<int, double>> out;
  for (const auto& [v, x] : w) out.emplace_back(v, x / total);
  return out;
}

// Min-norm change of the weights so that their mean is exactly `joint` (and they sum to 1).
std::vector<std::pair<int, double>> exactMean(const TriMesh& mesh,
                                              std::vector<std::pair<int, double>> w,
                                              const Eigen::Vector3d& joint) {
  const int m = static_cast<int>(w.size());
  Eigen::MatrixXd A(4, m);
  Eigen::VectorXd w0(m);
  for (int i = 0; i < m; ++i) {
    A.col(i) << mesh.V.row(w[i].first).transpose(), 1.0;
    w0[i] = w[i].second;
  }
  Eigen::Vector4d b;
  b << joint, 1.0;
  const Eigen::Vector4d lambda = (A * A.transpose()).ldlt().solve(b - A * w0);
  const Eigen::VectorXd wc = w0 + A.transpose() * lambda;
  for (int i = 0; i < m; ++i) w[i].second = wc[i];
  return w;
}

// Vertices within 2 mm of the extreme of `score` among `candidates`, equal weights.
std::vector<std::pair<int, double>> extremeVertices(const std::vector<int>& candidates,
                                                    const std::function<double(int)>& score) {
  double best = -1e9;
  for (int v : candidates) best = std::max(best, score(v));
  std::vector<int> pick;
  for (int v : candidates)
    if (score(v) >= best - 0.002) pick.push_back(v);
  std::vector<std::pair<int, double>> out;
  for (int v : pick) out.emplace_back(v, 1.0 / static_cast<double>(pick.size()));
  return out;
}

struct Attachment {
  std::array<int, 4> prim{{-1, -1, -1, -1}};
  std::array<double, 4> weight{{0, 0, 0, 0}};
  std::array<LoftCoords, 4> coords;
};

// Soft assignment of a surface point to the primitives it lies on (softmin of their fields).
Attachment attach(const MannequinImplicit& body, const Eigen::Vector3d& p, double tau) {
  const int np = body.numPrimitives();
  std::vector<std::pair<double, int>> d(np);
  for (int k = 0; k < np; ++k) d[k] = {body.primitiveValue(k, p), k};
  std::partial_sort(d.begin(), d.begin() + 4, d.end());
  Attachment a;
  double total = 0;
  for (int i = 0; i < 4; ++i) {
    const double w = std::exp(-(d[i].first - d[0].first) / tau);
    if (w < 1e-4) break;
    a.prim[i] = d[i].second;
    a.weight[i] = w;
    a.coords[i] = body.coords(d[i].second, p);
    total += w;
  }
  for (double& w : a.weight) w /= total;
  return a;
}

}  // namespace

BodyModel makeMannequin(const MannequinOptions& options) {
  if (options.targetVertices < 2000 || options.targetVertices > 200000)
    throw InputError("mannequin: targetVertices " + std::to_string(options.targetVertices) +
                     " is outside 2000–200000; the default body uses 15000");
  const MannequinImplicit body(options.base);
  const double s = options.base.height / 1.75;

  // --- template: mesh once, correcting the voxel size to hit the target vertex count
  double voxel = std::sqrt(2.6 * s * s / options.targetVertices);
  TriMesh mesh = meshMannequinImplicit(body, voxel);
  for (int retry = 0; retry < 2; ++retry) {
    const double ratio = static_cast<double>(mesh.numVertices()) / options.targetVertices;
    if (ratio > 0.9 && ratio < 1.1) break;
    voxel *= std::sqrt(ratio);
    mesh = meshMannequinImplicit(body, voxel);
  }
  for (int retry = 0; retry < 3; ++retry) {
    const std::string problem = closedManifoldProblem(mesh);
    if (problem.empty()) break;
    if (retry == 2)
      throw TopologyError("mannequin: the template is not a closed 2-manifold (" + problem +
                          "); try another targetVertices");
    voxel *= 0.985;
    mesh = meshMannequinImplicit(body, voxel);
  }
  const int nv = mesh.numVertices();

  BodyModel model;
  model.source = "mannequin";
  model.rest = mesh;

  // --- shape blend shapes: central differences of vertices carried by primitive coordinates
  std::vector<Attachment> att(nv);
  tbb::parallel_for(0, nv,
                    [&](int v) { att[v] = attach(body, mesh.V.row(v).transpose(), 0.005 * s); });
  model.shapeDirs.setZero(3 * nv, kMannequinShapes);
  for (int p = 0; p < kMannequinShapes; ++p) {
    model.shapeParams.push_back(
        {paramInfo()[p].name, paramInfo()[p].description, paramInfo()[p].min, paramInfo()[p].max});
    Eigen::MatrixX3d moved[2];
    for (int sign = 0; sign < 2; ++sign) {
      Eigen::VectorXd beta = Eigen::VectorXd::Zero(kMannequinShapes);
      beta[p] = sign == 0 ? 1.0 : -1.0;
      const MannequinImplicit varied(mannequinMeasurements(options.base, beta), &body);
      moved[sign].resize(nv, 3);
      tbb::parallel_for(0, nv, [&](int v) {
        Eigen::Vector3d q = Eigen::Vector3d::Zero();
        for (int i = 0; i < 4 && att[v].prim[i] >= 0; ++i)
          q += att[v].weight[i] * varied.position(att[v].prim[i], att[v].coords[i]);
        moved[sign].row(v) = varied.project(q, 4);
      });
    }
    const Eigen::MatrixX3d d = 0.5 * (moved[0] - moved[1]);
    for (int v = 0; v < nv; ++v)
      for (int k = 0; k < 3; ++k) model.shapeDirs(3 * v + k, p) = d(v, k);
  }

  // --- skeleton and joint regressor: each joint as a ring of vertices around it
  const auto& names = mannequinJointNames();
  const auto& parents = mannequinParents();
  const auto& J = body.joints();
  for (int j = 0; j < kMjCount; ++j) {
    model.parents.push_back(parents[j]);
    model.jointNames.push_back(names[j]);
  }
  std::vector<Eigen::Triplet<double>> reg;
  for (int j = 0; j < kMjCount; ++j) {
    const Eigen::Vector3d pj = J.row(j).transpose();
    Eigen::Vector3d normal = Eigen::Vector3d::UnitY();
    switch (j) {
      case kMjNeck:
      case kMjHead:
        normal = (J.row(kMjHead) - J.row(kMjNeck)).transpose().normalized();
        break;
      case kMjLeftShoulder:
      case kMjRightShoulder:
        normal = Eigen::Vector3d::UnitX();
        break;
      case kMjLeftElbow:
      case kMjLeftWrist:
      case kMjLeftHand:
        normal = (J.row(kMjLeftWrist) - J.row(kMjLeftElbow)).transpose().normalized();
        break;
      case kMjRightElbow:
      case kMjRightWrist:
      case kMjRightHand:
        normal = (J.row(kMjRightWrist) - J.row(kMjRightElbow)).transpose().normalized();
        break;
      case kMjLeftHip:
      case kMjLeftKnee:
      case kMjLeftAnkle:
        normal = (J.row(kMjLeftAnkle) - J.row(kMjLeftHip)).transpose().normalized();
        break;
      case kMjRightHip:
      case kMjRightKnee:
      case kMjRightAnkle:
        normal = (J.row(kMjRightAnkle) - J.row(kMjRightHip)).transpose().normalized();
        break;
      case kMjLeftToe:
      case kMjRightToe:
        normal = Eigen::Vector3d::UnitZ();
        break;
      default:
        break;
    }
    auto ring = sectionRing(mesh, pj, normal);
    if (ring.size() < 4) {  // fallback: the 8 nearest vertices
      std::vector<std::pair<double, int>> dist(nv);
      for (int v = 0; v < nv; ++v) dist[v] = {(mesh.V.row(v).transpose() - pj).norm(), v};
      std::partial_sort(dist.begin(), dist.begin() + 8, dist.end());
      ring.clear();
      for (int i = 0; i < 8; ++i) ring.emplace_back(dist[i].second, 1.0 / 8);
    }
    for (const auto& [v, w] : exactMean(mesh, ring, pj)) reg.emplace_back(j, v, w);
  }
  model.jointRegressor.resize(kMjCount, nv);
  model.jointRegressor.setFromTriplets(reg.begin(), reg.end());

  // --- skinning weights: each primitive's bone ladder, blended softly, smoothed, top 4
  std::vector<Attachment> attSkin(nv);
  tbb::parallel_for(
      0, nv, [&](int v) { attSkin[v] = attach(body, mesh.V.row(v).transpose(), 0.012 * s); });
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(nv, kMjCount);
  for (int v = 0; v < nv; ++v)
    for (int i = 0; i < 4 && attSkin[v].prim[i] >= 0; ++i) {
      const Loft& l = body.primitive(attSkin[v].prim[i]);
      const double c =
          (mesh.V.row(v).transpose() - l.origin).dot(l.axis) / (l.length > 0 ? l.length : l.capEnd);
      const auto& b = l.bones;
      const double w = attSkin[v].weight[i];
      if (c <= b.front().first) {
        W(v, b.front().second) += w;
      } else if (c >= b.back().first) {
        W(v, b.back().second) += w;
      } else {
        size_t k = 0;
        while (b[k + 1].first < c) ++k;
        double x = (c - b[k].first) / (b[k + 1].first - b[k].first);
        x = x * x * (3 - 2 * x);
        W(v, b[k].second) += w * (1 - x);
        W(v, b[k + 1].second) += w * x;
      }
    }
  const auto nbs = vertexNeighbours(mesh);
  for (int pass = 0; pass < 8; ++pass) {
    Eigen::MatrixXd next = W;
    for (int v = 0; v < nv; ++v) {
      Eigen::RowVectorXd mean = Eigen::RowVectorXd::Zero(kMjCount);
      for (int w : nbs[v]) mean += W.row(w);
      next.row(v) = 0.5 * W.row(v) + 0.5 * mean / static_cast<double>(nbs[v].size());
    }
    W = next;
  }
  std::vector<Eigen::Triplet<double>> sk;
  for (int v = 0; v < nv; ++v) {
    std::vector<std::pair<double, int>> row;
    for (int j = 0; j < kMjCount; ++j)
      if (W(v, j) > 1e-4) row.emplace_back(W(v, j), j);
    std::sort(row.rbegin(), row.rend());
    row.resize(std::min<size_t>(row.size(), 4));
    double total = 0;
    for (const auto& r : row) total += r.first;
    for (const auto& r : row) sk.emplace_back(v, r.second, r.first / total);
  }
  model.weights.resize(nv, kMjCount);
  model.weights.setFromTriplets(sk.begin(), sk.end());
  model.poseDirs.resize(0, 0);

  // --- canonical map: joints, and surface landmarks chosen by rule
  for (int c = 0; c <= static_cast<int>(Canonical::RightAnkle); ++c) model.canonical[c].joint = c;
  std::vector<int> all(nv), leftFoot, rightFoot, leftArm, rightArm, head;
  std::iota(all.begin(), all.end(), 0);
  const double neckY = J(kMjHead, 1);
  for (int v = 0; v < nv; ++v) {
    const Eigen::Vector3d p = mesh.V.row(v).transpose();
    if (p.y() < 0.12 * s) (p.x() > 0 ? leftFoot : rightFoot).push_back(v);
    if (std::abs(p.x()) > options.base.shoulder / 2 + 0.05 * s && p.y() > 0.4 * s)
      (p.x() > 0 ? leftArm : rightArm).push_back(v);
    if (p.y() > neckY) head.push_back(v);
  }
  auto V = [&](int v) { return Eigen::Vector3d(mesh.V.row(v).transpose()); };
  for (bool left : {true, false}) {
    const int jw = left ? kMjLeftWrist : kMjRightWrist, je = left ? kMjLeftElbow : kMjRightElbow;
    const Eigen::Vector3d wrist = J.row(jw).transpose();
    const Eigen::Vector3d dir = (J.row(jw) - J.row(je)).transpose().normalized();
    model.canonical[static_cast<int>(left ? Canonical::LeftHandTip : Canonical::RightHandTip)]
        .vertices =
        extremeVertices(left ? leftArm : rightArm, [&](int v) { return (V(v) - wrist).dot(dir); });
    const auto& foot = left ? leftFoot : rightFoot;
    model.canonical[static_cast<int>(left ? Canonical::LeftToeTip : Canonical::RightToeTip)]
        .vertices = extremeVertices(foot, [&](int v) { return V(v).z(); });
    model.canonical[static_cast<int>(left ? Canonical::LeftHeel : Canonical::RightHeel)].vertices =
        extremeVertices(foot, [&](int v) { return V(v).y() < 0.04 * s ? -V(v).z() : -1e9; });
  }
  model.canonical[static_cast<int>(Canonical::HeadTop)].vertices =
      extremeVertices(head, [&](int v) { return V(v).y(); });
  model.canonical[static_cast<int>(Canonical::Nose)].vertices =
      extremeVertices(head, [&](int v) { return V(v).z(); });
  return model;
}

}  // namespace s2p
