#include "segment/non_garment.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "core/colour.h"
#include "core/error.h"
#include "core/laplacian.h"
#include "core/mesh_topology.h"
#include "core/row_tree.h"
#include "segment/geodesic.h"
#include "segment/isoline.h"
#include "segment/vertex_regions.h"

namespace s2p {

namespace {

using Vec3 = Eigen::Vector3d;

// Degrees around the vertical axis through `axis` that the points `vertices` of `V` cover: 360
// minus the widest empty sector between them.
double angularSpan(const Eigen::MatrixX3d& V, const std::vector<int>& vertices, const Vec3& axis) {
  std::vector<double> a;
  for (int v : vertices) a.push_back(std::atan2(V(v, 2) - axis.z(), V(v, 0) - axis.x()));
  if (a.size() < 2) return 0;
  std::sort(a.begin(), a.end());
  double gap = 2 * M_PI - (a.back() - a.front());
  for (size_t i = 1; i < a.size(); ++i) gap = std::max(gap, a[i] - a[i - 1]);
  return (2 * M_PI - gap) * 180 / M_PI;
}

double nearestComponent(const GaussianMixture& g, const Vec3& lab) {
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < g.components(); ++k)
    best = std::min(best, deltaE2000(lab, g.means.row(k).transpose()));
  return best;
}

}  // namespace

HeldObjects findHeldObjects(const TriMesh& mesh, const Eigen::VectorXd& offset, const Vec3& axis,
                            double garmentLevel, const HeldObjectOptions& options, double ceiling,
                            double floor, const Eigen::MatrixX3d* lab) {
  const int nV = mesh.numVertices();
  if (offset.size() != nV)
    throw InputError(fmt::format("findHeldObjects: {} offsets for {} vertices", offset.size(), nV));
  if (lab && lab->rows() != nV)
    throw InputError(fmt::format("findHeldObjects: {} colours for {} vertices", lab->rows(), nV));
  const double edge =
      (std::isfinite(garmentLevel) ? std::max(garmentLevel, 0.0) : 0.0) + options.edgeMargin;
  HeldObjects out;
  out.field = (offset.array() - edge).min(-1e-4).matrix();
  const MeshTopology topo(mesh.F, nV);
  const Eigen::VectorXd area = vertexAreas(mesh);
  const auto& E = topo.edges();
  // Seeds: far off the body; each connected set one candidate.
  const VertexRegions seeds = vertexRegions(topo, [&](int e) {
    return offset[E(e, 0)] > options.seedOffset && offset[E(e, 1)] > options.seedOffset;
  });
  std::vector<std::vector<int>> members(seeds.count);
  for (int v = 0; v < nV; ++v)
    if (offset[v] > options.seedOffset) members[seeds.region[v]].push_back(v);
  std::vector<int> kept;  // seed vertices of the candidates
  std::vector<int> objectOf(nV, -1);
  int candidates = 0;
  for (const std::vector<int>& m : members) {
    double a = 0;
    for (int v : m) a += area[v];
    if (m.empty() || a < options.minSeedArea) continue;
    if (std::any_of(m.begin(), m.end(), [&](int v) { return mesh.V(v, 1) > ceiling; })) {
      ++out.headSeeds;
      continue;
    }
    if (std::any_of(m.begin(), m.end(), [&](int v) { return mesh.V(v, 1) < floor; })) {
      ++out.footSeeds;
      continue;
    }
    for (int v : m) objectOf[v] = candidates;
    kept.insert(kept.end(), m.begin(), m.end());
    ++candidates;
  }
  if (kept.empty()) return out;
  // Grow each candidate from its seed over the scan above the edge level, within `reach`.
  const RowCloud cloud{&mesh.V, &kept};
  RowTree tree(3, cloud);
  tree.buildIndex();
  const auto nearSeed = [&](int v) {
    std::uint32_t idx = 0;
    double d2 = 0;
    const Vec3 p = mesh.V.row(v).transpose();
    tree.knnSearch(p.data(), 1, &idx, &d2);
    return d2 <= options.reach * options.reach;
  };
  std::vector<std::vector<int>> adj(nV);
  for (int e = 0; e < topo.numEdges(); ++e) {
    adj[E(e, 0)].push_back(E(e, 1));
    adj[E(e, 1)].push_back(E(e, 0));
  }
  std::vector<int> stack = kept;
  while (!stack.empty()) {
    const int v = stack.back();
    stack.pop_back();
    for (int w : adj[v])
      if (objectOf[w] < 0 && offset[w] > edge && nearSeed(w)) {
        objectOf[w] = objectOf[v];
        stack.push_back(w);
      }
  }
  // Candidates that grew into each other are one (the front and back of a long skirt, far off
  // the legs, joined around its sides); one reaching further than maxSpan around the body hangs
  // all around it: a garment, not an object at one side.
  std::vector<int> group(candidates);
  for (int c = 0; c < candidates; ++c) group[c] = c;
  const std::function<int(int)> root = [&](int c) {
    return group[c] == c ? c : group[c] = root(group[c]);
  };
  for (int e = 0; e < topo.numEdges(); ++e) {
    const int a = objectOf[E(e, 0)], b = objectOf[E(e, 1)];
    if (a >= 0 && b >= 0 && root(a) != root(b)) group[root(a)] = root(b);
  }
  std::vector<std::vector<int>> grown(candidates);
  for (int v = 0; v < nV; ++v)
    if (objectOf[v] >= 0) grown[root(objectOf[v])].push_back(v);
  std::vector<int> objectIndex(candidates, -1);
  for (int c = 0; c < candidates; ++c) {
    if (grown[c].empty()) continue;
    const double span = angularSpan(mesh.V, grown[c], axis);
    if (span > options.maxSpan) {
      ++out.rejectedSeeds;
      continue;
    }
    objectIndex[c] = static_cast<int>(out.objects.size());
    HeldObject o;
    o.span = span;
    out.objects.push_back(o);
  }
  for (int v = 0; v < nV; ++v)
    if (objectOf[v] >= 0) objectOf[v] = objectIndex[root(objectOf[v])];
  for (int v = 0; v < nV; ++v) {
    if (objectOf[v] < 0) continue;
    HeldObject& o = out.objects[objectOf[v]];
    o.area += area[v];
    o.centroid += area[v] * mesh.V.row(v).transpose();
    o.maxOffset = std::max(o.maxOffset, offset[v]);
  }
  if (out.objects.empty()) return out;
  // The object's sides stand on the garment beside it: the offset climbs from that garment's
  // own level by as much as one walks up the side, so the edge found at `edge` lies edge − level
  // up the side, and is moved down by that geodesic distance (exact for sides square on the
  // garment, short of the crease for sides meeting it at a shallower angle).
  const std::vector<std::vector<int>> besideVertices =
      besideSets(mesh.V, objectOf, static_cast<int>(out.objects.size()), options.besideBand,
                 [&](int v) { return offset[v] <= edge; });
  std::vector<std::vector<double>> beside(out.objects.size());
  for (size_t i = 0; i < beside.size(); ++i)
    for (int v : besideVertices[i]) beside[i].push_back(offset[v]);
  if (lab) {
    // An object in the colour of the garment it stands on is a lump of that garment: left out.
    std::vector<std::vector<int>> own(out.objects.size());
    for (int v = 0; v < nV; ++v)
      if (objectOf[v] >= 0) own[objectOf[v]].push_back(v);
    std::vector<int> keptIndex(out.objects.size(), -1);
    std::vector<HeldObject> keptObjects;
    std::vector<std::vector<double>> keptBeside;
    for (size_t i = 0; i < out.objects.size(); ++i) {
      if (!besideVertices[i].empty()) {
        out.objects[i].besideDeltaE =
            deltaE2000(medianColour(*lab, own[i]), medianColour(*lab, besideVertices[i]));
        if (out.objects[i].besideDeltaE < options.sameColourDeltaE) {
          out.garmentColoured.push_back(out.objects[i].besideDeltaE);
          continue;
        }
      }
      keptIndex[i] = static_cast<int>(keptObjects.size());
      keptObjects.push_back(out.objects[i]);
      keptBeside.push_back(std::move(beside[i]));
    }
    for (int v = 0; v < nV; ++v)
      if (objectOf[v] >= 0) objectOf[v] = keptIndex[objectOf[v]];
    out.objects = std::move(keptObjects);
    beside = std::move(keptBeside);
    if (out.objects.empty()) return out;
  }
  const FastMarchingDistance marching(mesh);
  for (size_t i = 0; i < out.objects.size(); ++i) {
    HeldObject& o = out.objects[i];
    if (o.area > 0) o.centroid /= o.area;
    std::vector<double>& b = beside[i];
    o.besideLevel = edge - options.edgeMargin;
    if (!b.empty()) {
      std::nth_element(b.begin(), b.begin() + b.size() / 2, b.end());
      o.besideLevel = b[b.size() / 2];
    }
    o.lowered = std::max(edge - o.besideLevel, 0.0);
    Eigen::VectorXd own(nV);
    for (int v = 0; v < nV; ++v)
      own[v] = objectOf[v] == static_cast<int>(i) ? std::max(offset[v] - edge, 1e-6)
                                                  : std::min(offset[v] - edge, -1e-6);
    const Isoline iso = extractIsoline(mesh, own);
    const Eigen::VectorXd sd = marching.signedDistance(iso, own);
    for (int v = 0; v < nV; ++v) {
      const double f = std::isfinite(sd[v]) ? sd[v] + o.lowered : -1.0;
      out.field[v] = std::max(out.field[v], f);
    }
  }
  return out;
}

std::vector<int> hairSeeds(const TriMesh& mesh, const Eigen::MatrixX3d& lab,
                           const std::vector<Vec3>& facePoints, const SkinModel& skin,
                           const HairOptions& options) {
  std::vector<int> out;
  if (facePoints.empty() || lab.rows() != mesh.numVertices()) return out;
  Vec3 centre = Vec3::Zero();
  double bottom = std::numeric_limits<double>::infinity();
  for (const Vec3& p : facePoints) {
    centre += p;
    bottom = std::min(bottom, p.y());
  }
  centre /= static_cast<double>(facePoints.size());
  const Eigen::VectorXd area = vertexAreas(mesh);
  double seedArea = 0;
  for (int v = 0; v < mesh.numVertices(); ++v) {
    const Vec3 p = mesh.V.row(v).transpose();
    if (p.y() < bottom) continue;
    if (std::hypot(p.x() - centre.x(), p.z() - centre.z()) > options.headRadius) continue;
    if (deltaE2000(lab.row(v).transpose(), skin.mean) <= skin.threshold) continue;
    out.push_back(v);
    seedArea += area[v];
  }
  if (seedArea < options.minSeedArea) out.clear();
  return out;
}

Eigen::VectorXd hairField(const TriMesh& mesh, const Eigen::MatrixX3d& lab,
                          const GaussianMixture& hair, const GaussianMixture& skin,
                          const Vec3& headCentre, const HairOptions& options) {
  const int nV = mesh.numVertices();
  if (lab.rows() != nV)
    throw InputError(fmt::format("hairField: {} colours for {} vertices", lab.rows(), nV));
  Eigen::VectorXd indicator(nV);
  for (int v = 0; v < nV; ++v) {
    const Vec3 c = lab.row(v).transpose();
    const bool near = (mesh.V.row(v).transpose() - headCentre).norm() <= options.reach;
    indicator[v] = near && nearestComponent(hair, c) < nearestComponent(skin, c) ? 1.0 : -1.0;
  }
  if (nV == 0) return indicator;
  return smoothOnSurface(mesh, indicator, options.smoothing).col(0);
}

}  // namespace s2p
