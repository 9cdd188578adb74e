#include "segment/mrf.h"

#include <maxflow-3.0/maxflow/graph.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <string>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/mesh_topology.h"
#include "core/row_tree.h"
#include "segment/body_offset.h"

namespace s2p {

namespace {

using Graph = maxflow::Graph<double, double, double>;

// Squared Euclidean distance from every vertex to the nearest of `points` (#V).
Eigen::VectorXd nearestSquaredDistance(const Eigen::MatrixX3d& V, const Eigen::MatrixX3d& points) {
  const RowCloud cloud{&points};
  const RowTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  Eigen::VectorXd d2(V.rows());
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    const Eigen::Vector3d q = V.row(v).transpose();
    std::uint32_t index = 0;
    double dist = 0;
    tree.knnSearch(q.data(), 1, &index, &dist);
    d2[v] = dist;
  }
  return d2;
}

void validate(const TriMesh& mesh, const Eigen::MatrixX3d& srgb,
              const std::vector<MrfRegion>& regions, const MrfOptions& o) {
  validateMesh(mesh, "MRF segmentation mesh");
  if (srgb.rows() != mesh.numVertices())
    throw InputError("MRF segmentation: " + std::to_string(srgb.rows()) + " colours for " +
                     std::to_string(mesh.numVertices()) +
                     " vertices; pass one sRGB colour per vertex");
  for (Eigen::Index v = 0; v < srgb.rows(); ++v)
    if (!srgb.row(v).allFinite())
      throw InputError("MRF segmentation: the colour of vertex " + std::to_string(v) +
                       " is not finite; repair or drop the scan's colours");
  if (regions.size() < 2)
    throw InputError("MRF segmentation: " + std::to_string(regions.size()) +
                     " labelled region(s); at least two labels are needed");
  std::set<int> seen;
  for (size_t r = 0; r < regions.size(); ++r) {
    const MrfRegion& region = regions[r];
    const std::string name =
        "region " + std::to_string(r) + " (label " + std::to_string(region.label) + ")";
    if (!seen.insert(region.label).second)
      throw InputError("MRF segmentation: " + name +
                       " repeats another region's label; merge their points into one region");
    if (region.points.empty())
      throw InputError("MRF segmentation: " + name +
                       " has no points (all of them ill-projected?); drop the label or project "
                       "more points");
    for (size_t i = 0; i < region.points.size(); ++i) {
      const SurfacePoint& p = region.points[i];
      if (p.face < 0 || p.face >= mesh.numFaces() || !p.bary.allFinite())
        throw InputError("MRF segmentation: point " + std::to_string(i) + " of " + name +
                         " is off the mesh (face " + std::to_string(p.face) + " of " +
                         std::to_string(mesh.numFaces()) + ", or non-finite weights)");
    }
  }
  const auto finite = [](double x) { return std::isfinite(x); };
  if (!(finite(o.smoothness) && o.smoothness >= 0))
    throw InputError("MRF segmentation: smoothness must be finite and ≥ 0");
  if (!(finite(o.contrast) && o.contrast >= 0))
    throw InputError("MRF segmentation: contrast σ must be finite and ≥ 0 (0: off)");
  if (!(finite(o.spacing) && o.spacing > 0))
    throw InputError("MRF segmentation: spacing must be a positive number of metres");
  if (!(finite(o.priorLength) && o.priorLength > 0))
    throw InputError("MRF segmentation: priorLength must be a positive number of metres");
  if (!(finite(o.priorWeight) && o.priorWeight >= 0))
    throw InputError("MRF segmentation: priorWeight must be finite and ≥ 0");
  if (!(o.posteriorFloor >= 0 && o.posteriorFloor < 1))
    throw InputError("MRF segmentation: posteriorFloor must be in [0, 1)");
  if (o.maxSweeps < 0) throw InputError("MRF segmentation: maxSweeps must be ≥ 0");
  if (!(finite(o.offsetNoise) && o.offsetNoise > 0) ||
      !(o.offsetOutliers > 0 && o.offsetOutliers < 1) ||
      !(finite(o.offsetRange) && o.offsetRange > 0) ||
      !(finite(o.riserSlope) && o.riserSlope >= 0))
    throw InputError(
        "MRF segmentation: offsetNoise and offsetRange must be positive metres, offsetOutliers "
        "in (0, 1) and riserSlope ≥ 0");
}

void validateOffset(const TriMesh& mesh, const Eigen::VectorXd& offset,
                    const std::vector<MrfRegion>& regions) {
  if (offset.size() == 0) return;
  if (offset.size() != mesh.numVertices() || !offset.allFinite())
    throw InputError("MRF segmentation: " + std::to_string(offset.size()) + " offsets for " +
                     std::to_string(mesh.numVertices()) +
                     " vertices, or not finite; pass one per vertex, or none for colour alone");
  const auto skin = std::count_if(regions.begin(), regions.end(),
                                  [](const MrfRegion& r) { return r.bareSkin; });
  if (skin == 0 || skin == static_cast<long>(regions.size()))
    throw InputError("MRF segmentation: the offset cue needs a region of bare skin and one "
                     "that covers it; mark the skin's region bareSkin");
}

// The Gaussian part of the offset likelihood of one kind of region: the median and the
// MAD-estimated spread (floored at `noise`) of the offsets at its points' nearest corners.
OffsetModel fitOffsetModel(const TriMesh& mesh, const Eigen::VectorXd& offset,
                           const std::vector<MrfRegion>& regions, bool bareSkin, double noise) {
  std::vector<double> o;
  for (const MrfRegion& r : regions)
    if (r.bareSkin == bareSkin)
      for (const double x : offsetsAt(mesh, offset, r.points)) o.push_back(x);
  const auto median = [](std::vector<double> v) {
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
  };
  OffsetModel m;
  m.mean = median(o);
  for (double& x : o) x = std::abs(x - m.mean);
  m.sigma = std::max(1.4826 * median(o), noise);
  return m;
}

// log p(o) = log((1 − η) N(o; μ, σ²) + η / R), #V.
Eigen::VectorXd offsetLogLikelihood(const Eigen::VectorXd& offset, const OffsetModel& m,
                                    const MrfOptions& options) {
  const double eta = options.offsetOutliers;
  const double peak = (1 - eta) / (m.sigma * std::sqrt(2 * M_PI));
  Eigen::VectorXd out(offset.size());
  for (Eigen::Index v = 0; v < offset.size(); ++v) {
    const double z = (offset[v] - m.mean) / m.sigma;
    out[v] = std::log(peak * std::exp(-0.5 * z * z) + eta / options.offsetRange);
  }
  return out;
}

double logSumExp(const Eigen::RowVectorXd& a) {
  const double m = a.maxCoeff();
  if (!std::isfinite(m)) return m;
  return m + std::log((a.array() - m).exp().sum());
}

// E(f) of a Potts labelling problem.
struct Energy {
  const Eigen::MatrixXd& unary;   // #V×K
  const Eigen::MatrixX2i& edges;  // #E×2
  const Eigen::VectorXd& weight;  // #E

  double operator()(const Eigen::VectorXi& f) const {
    double e = 0;
    for (Eigen::Index v = 0; v < unary.rows(); ++v) e += unary(v, f[v]);
    for (Eigen::Index k = 0; k < edges.rows(); ++k)
      if (f[edges(k, 0)] != f[edges(k, 1)]) e += weight[k];
    return e;
  }
};

// One expansion move of label alpha: every vertex keeps its label or switches to alpha, the
// optimal choice by one min cut (Boykov, Veksler and Zabih 2001, §4; Kolmogorov and Zabih's
// construction of the binary energy, submodular because Potts is a metric).
Eigen::VectorXi expand(const Energy& en, const Eigen::VectorXi& f, int alpha, Graph& g) {
  const int n = static_cast<int>(f.size());
  g.reset();
  g.add_node(n);
  Eigen::VectorXd e0(n), e1(n);  // cost of keeping f_u (x = 0) and of switching (x = 1)
  for (int u = 0; u < n; ++u) {
    e0[u] = en.unary(u, f[u]);
    e1[u] = f[u] == alpha ? e0[u] : en.unary(u, alpha);
  }
  for (Eigen::Index k = 0; k < en.edges.rows(); ++k) {
    const int u = en.edges(k, 0), v = en.edges(k, 1);
    const double w = en.weight[k];
    const bool ua = f[u] == alpha, va = f[v] == alpha;
    if (w <= 0 || (ua && va)) continue;
    if (ua) {  // u is alpha either way: v pays w unless it switches
      e0[v] += w;
    } else if (va) {
      e0[u] += w;
    } else {
      // E(x_u, x_v): E00 = w[f_u ≠ f_v], E01 = E10 = w, E11 = 0, decomposed as
      // E00 + (E10 − E00) x_u + (E11 − E10) x_v + (E01 + E10 − E00 − E11)(1 − x_u) x_v.
      const double a = f[u] != f[v] ? w : 0.0;
      e0[u] += a;
      e1[u] += w;
      e0[v] += w;  // (E11 − E10) x_v = −w x_v, shifted by +w so both costs stay ≥ 0
      g.add_edge(u, v, 2 * w - a, 0.0);
    }
  }
  for (int u = 0; u < n; ++u) {
    const double m = std::min(e0[u], e1[u]);
    g.add_tweights(u, e1[u] - m, e0[u] - m);  // source side = keep (x = 0), sink = switch
  }
  g.maxflow();
  Eigen::VectorXi out = f;
  for (int u = 0; u < n; ++u)
    if (g.what_segment(u, Graph::SOURCE) == Graph::SINK) out[u] = alpha;
  return out;
}

}  // namespace

MrfResult mrfSegmentation(const TriMesh& mesh, const Eigen::MatrixX3d& srgb,
                          const std::vector<MrfRegion>& regions, const MrfOptions& options,
                          const Eigen::VectorXd& offset) {
  validate(mesh, srgb, regions, options);
  validateOffset(mesh, offset, regions);
  const int nv = mesh.numVertices();
  const int nl = static_cast<int>(regions.size());

  // The boundary optimiser's colour model: the same smoothing, CIELAB and one GMM per region
  // with the same seeds.
  std::vector<std::vector<SurfacePoint>> points;
  for (const MrfRegion& r : regions) points.push_back(r.points);
  RegionColours colour = fitRegionColours(mesh, srgb, points, options.colour);

  // Data term: −log of the robust posterior with equal label priors (as posteriorDisplacement),
  // of the colour and, when given, the offset (independent given the label).
  Eigen::MatrixXd logp(nv, nl);
  for (int l = 0; l < nl; ++l) logp.col(l) = colour.models[l].logDensity(colour.lab);
  MrfResult result;
  if (offset.size() > 0) {
    result.skinOffset = fitOffsetModel(mesh, offset, regions, true, options.offsetNoise);
    result.clothedOffset = fitOffsetModel(mesh, offset, regions, false, options.offsetNoise);
    const Eigen::VectorXd skin = offsetLogLikelihood(offset, result.skinOffset, options);
    const Eigen::VectorXd clothed = offsetLogLikelihood(offset, result.clothedOffset, options);
    for (int l = 0; l < nl; ++l) logp.col(l) += regions[l].bareSkin ? skin : clothed;
  }
  const double eps = options.posteriorFloor;
  Eigen::MatrixXd cost(nv, nl);
  for (int v = 0; v < nv; ++v) {
    const double all = logSumExp(logp.row(v));
    for (int l = 0; l < nl; ++l) {
      const double p = std::isfinite(all) ? std::exp(logp(v, l) - all) : 1.0 / nl;
      cost(v, l) = -std::log(std::max(eps / nl + (1 - eps) * p, 1e-300));
    }
  }

  // Prior: quadratic in the Euclidean distance to the label's nearest region point.
  if (options.priorWeight > 0) {
    const double s = options.priorWeight / (options.priorLength * options.priorLength);
    for (int l = 0; l < nl; ++l) {
      Eigen::MatrixX3d pts(static_cast<Eigen::Index>(regions[l].points.size()), 3);
      for (size_t i = 0; i < regions[l].points.size(); ++i)
        pts.row(static_cast<Eigen::Index>(i)) = regions[l].points[i].position(mesh).transpose();
      cost.col(l) += s * nearestSquaredDistance(mesh.V, pts);
    }
  }

  // Vertex weights A_u / s²; a vertex without area (unreferenced) keeps weight 1 so that its
  // label is still its own data + prior minimum.
  const double s2 = options.spacing * options.spacing;
  Eigen::VectorXd a = vertexAreas(mesh, MassType::Barycentric);
  for (int v = 0; v < nv; ++v) a[v] = a[v] > 0 ? a[v] / s2 : 1.0;
  const Eigen::MatrixXd unary = a.asDiagonal() * cost;

  // Edge weights λ (|uv| / s) c_uv.
  const MeshTopology topology(mesh.F, nv);
  const Eigen::MatrixX2i& edges = topology.edges();
  const Eigen::Index ne = edges.rows();
  Eigen::VectorXd weight(ne);
  for (Eigen::Index k = 0; k < ne; ++k) {
    const int u = edges(k, 0), v = edges(k, 1);
    double c = 1.0;
    if (options.contrast > 0) {
      const double dE2 = (colour.lab.row(u) - colour.lab.row(v)).squaredNorm();
      c = std::exp(-dE2 / (2 * options.contrast * options.contrast));
    }
    if (offset.size() > 0 && options.riserSlope > 0) {
      const double slope =
          (offset[u] - offset[v]) / std::max((mesh.V.row(u) - mesh.V.row(v)).norm(), 1e-12);
      c *= std::exp(-slope * slope / (2 * options.riserSlope * options.riserSlope));
    }
    weight[k] = options.smoothness * (mesh.V.row(u) - mesh.V.row(v)).norm() / options.spacing * c;
  }

  const PottsResult potts =
      minimisePotts(unary, edges, weight, options.smoothness > 0 ? options.maxSweeps : 0);
  result.vertexLabel.resize(nv);
  for (int v = 0; v < nv; ++v) result.vertexLabel[v] = regions[potts.label[v]].label;
  result.models = std::move(colour.models);
  result.energy = potts.energy;
  result.sweeps = potts.sweeps;
  result.sweepEnergies = potts.sweepEnergies;
  return result;
}

PottsResult minimisePotts(const Eigen::MatrixXd& unary, const Eigen::MatrixX2i& edges,
                          const Eigen::VectorXd& weight, int maxSweeps) {
  const Eigen::Index nv = unary.rows(), nl = unary.cols();
  if (nv == 0 || nl == 0 || !unary.allFinite())
    throw InputError("Potts labelling: the unary costs (" + std::to_string(nv) + "×" +
                     std::to_string(nl) + ") must be non-empty and finite");
  if (weight.size() != edges.rows())
    throw InputError("Potts labelling: " + std::to_string(weight.size()) + " weights for " +
                     std::to_string(edges.rows()) + " edges");
  for (Eigen::Index k = 0; k < edges.rows(); ++k) {
    if (edges(k, 0) < 0 || edges(k, 0) >= nv || edges(k, 1) < 0 || edges(k, 1) >= nv)
      throw InputError("Potts labelling: edge " + std::to_string(k) +
                       " refers to a vertex outside 0.." + std::to_string(nv - 1));
    if (!(std::isfinite(weight[k]) && weight[k] >= 0))
      throw InputError("Potts labelling: the weight of edge " + std::to_string(k) +
                       " must be finite and ≥ 0");
  }
  if (maxSweeps < 0) throw InputError("Potts labelling: maxSweeps must be ≥ 0");
  const Energy en{unary, edges, weight};

  PottsResult result;
  Eigen::VectorXi f(nv);
  for (Eigen::Index v = 0; v < nv; ++v) unary.row(v).minCoeff(&f[v]);
  double energy = en(f);
  result.sweepEnergies.push_back(energy);
  if (maxSweeps > 0 && nl > 1) {
    Graph graph(static_cast<int>(nv), static_cast<int>(edges.rows()), [](const char* msg) {
      throw SolverError(std::string("Potts labelling: max-flow graph failed: ") + msg);
    });
    for (int sweep = 0; sweep < maxSweeps; ++sweep) {
      bool improved = false;
      for (int alpha = 0; alpha < nl; ++alpha) {
        Eigen::VectorXi g = expand(en, f, alpha, graph);
        const double e = en(g);
        if (e < energy - 1e-12 * std::max(1.0, std::abs(energy))) {  // a strict decrease only
          f = std::move(g);
          energy = e;
          improved = true;
        }
      }
      result.sweeps = sweep + 1;
      result.sweepEnergies.push_back(energy);
      if (!improved) break;
    }
  }
  result.label = std::move(f);
  result.energy = energy;
  return result;
}

Eigen::VectorXi faceLabelsFromVertices(const TriMesh& mesh, const Eigen::VectorXi& vertexLabel) {
  if (vertexLabel.size() != mesh.numVertices())
    throw InputError("face labels: " + std::to_string(vertexLabel.size()) + " vertex labels for " +
                     std::to_string(mesh.numVertices()) + " vertices");
  Eigen::VectorXi out(mesh.numFaces());
  for (int f = 0; f < mesh.numFaces(); ++f) {
    int c[3];
    for (int k = 0; k < 3; ++k) {
      c[k] = mesh.F(f, k);
      if (c[k] < 0 || c[k] >= mesh.numVertices())
        throw InputError("face labels: face " + std::to_string(f) + " refers to vertex " +
                         std::to_string(c[k]) + ", outside the mesh");
    }
    const int a = vertexLabel[c[0]], b = vertexLabel[c[1]], d = vertexLabel[c[2]];
    if (a == b || a == d) {
      out[f] = a;
    } else if (b == d) {
      out[f] = b;
    } else {
      out[f] = vertexLabel[*std::min_element(c, c + 3)];
    }
  }
  return out;
}

}  // namespace s2p
