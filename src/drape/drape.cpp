#include "drape/drape.h"

#include <fmt/format.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <numeric>
#include <random>
#include <tuple>

#include "core/error.h"
#include "drape/body_sdf.h"

namespace s2p {

const char* toString(DrapeStatus status) {
  switch (status) {
    case DrapeStatus::Settled:
      return "settled";
    case DrapeStatus::NotSettled:
      return "not settled";
    case DrapeStatus::Failed:
      return "failed";
  }
  return "?";
}

namespace {

using Eigen::Vector3d;

// === Constraints

struct TriangleConstraint {
  int v[3];
  double d00, d01, d10, d11;  // Dm⁻¹ of the 2D rest triangle (Dm = [r1−r0, r2−r0])
  double area;                // rest area, m²
};

struct BendConstraint {
  int v[4];      // edge (v0, v1), opposite vertices v2, v3
  double k[4];   // Bergou et al. 2006 cotangent weights: C = Σ k_i x_i = 0 when flat
  double alpha;  // compliance scale (A0 + A1)/3
};

struct LimitEdge {
  int a, b;     // garment vertices (their particles once welded)
  double rest;  // metres, the edge's length in the pattern
};

struct Contact {
  int v;                 // vertex
  int t;                 // triangle (row of the garment's F)
  double side;           // ±1: which side of the triangle the vertex was on when found
  bool layered = false;  // between two layers: the side is their order
};

// Greedy colouring of constraints (each a set of vertices) in their given order, so that no two
// constraints of one colour share a vertex. Constraints that find none of 64 colours free go
// into a last group solved serially (flag `serialLast`).
template <class VerticesOf>
std::vector<std::vector<int>> colourConstraints(int count, int numVertices, VerticesOf verticesOf,
                                                bool& serialLast) {
  std::vector<uint64_t> used(numVertices, 0);
  std::vector<std::vector<int>> groups;
  std::vector<int> serial;
  for (int c = 0; c < count; ++c) {
    const auto vs = verticesOf(c);
    uint64_t mask = 0;
    for (int v : vs) mask |= used[v];
    if (~mask == 0) {
      serial.push_back(c);
      continue;
    }
    const int colour = std::countr_one(mask);
    if (colour >= static_cast<int>(groups.size())) groups.resize(colour + 1);
    groups[colour].push_back(c);
    for (int v : vs) used[v] |= uint64_t(1) << colour;
  }
  serialLast = !serial.empty();
  if (serialLast) groups.push_back(std::move(serial));
  return groups;
}

int findRoot(std::vector<int>& parent, int v) {
  while (parent[v] != v) v = parent[v] = parent[parent[v]];
  return v;
}

// === The simulator

class ClothSim {
 public:
  ClothSim(const DrapeInput& input, const DrapeOptions& o, DrapeResult& result)
      : o_(o), result_(result) {
    build(input);
  }

  void run(Progress* progress, const std::string& label);

 private:
  const DrapeOptions& o_;
  DrapeResult& result_;
  std::unique_ptr<BodySdf> sdf_;

  int nv_ = 0;
  std::vector<Vector3d> x_, xprev_, vel_, xstep_;
  std::vector<double> w_;           // inverse masses (0: unreferenced vertex, fixed)
  Eigen::MatrixX3i F_;              // all panels' faces, garment vertex indices
  std::vector<std::string> names_;  // of the panels
  std::vector<TriangleConstraint> tris_;
  std::vector<BendConstraint> bends_;
  std::vector<LimitEdge> edges_;  // every panel edge once, for strain limiting
  std::vector<std::pair<int, int>> stitches_;
  std::vector<std::vector<int>> triColours_, bendColours_;
  bool triSerialLast_ = false, bendSerialLast_ = false;
  std::vector<double> triLambda_;  // 3 per triangle
  std::vector<Vector3d> bendLambda_;
  std::vector<int> weld_;            // representative of each vertex under the stitches
  std::vector<int> adjStart_, adj_;  // welded vertex adjacency (CSR over representatives)
  std::vector<Contact> contacts_;
  double contactRadius_ = 0;       // metres, of the last search
  std::vector<Vector3d> xsearch_;  // positions at the last contact search
  std::vector<int> searchOrder_;   // faces in Morton order of their pattern position (per panel):
                                   // neighbours query the same cells, in cache
  long long searches_ = 0;
  double meanEdge_ = 0.01;
  Eigen::AlignedBox3d scene_;  // leaving it is a failure

  // Per-step state of the schedule.
  Vector3d gravity_ = Vector3d::Zero();
  double damping_ = 0;
  double friction_ = 0;
  std::vector<double> stitchStart_;  // metres: each stitch's gap at the start
  std::vector<char> sewn_;           // 1 once a stitch's partners met: welded from then on
  std::vector<double> stitchEdge_;   // metres: the rest length of the seam's edges at a stitch
  std::vector<char> merged_;         // 1 once a sewn stitch's partners are one particle
  std::vector<char> nearOpen_;       // per weld representative: within sewContactRings of an
                                     // open stitch (no self-collision there)
  std::vector<int> layer_;           // per vertex: its panel's layer (ClothPanel::layer)
  std::vector<int> panelOfFace_;     // per face of F_
  std::vector<double> outward_;      // per panel: +1 when its faces' normals point away from
                                     // the body, −1 when towards it (the winding is free)
  bool layered_ = false;             // panels of more than one layer
  std::vector<int> part_;            // the particle each vertex is (itself until welded)
  std::vector<double> mass_;         // kg per particle (0: merged into another, or unreferenced)
  Eigen::MatrixX3i Fsim_;            // F_ on particles (what contacts are found against)
  double maxStart_ = 1e-9;           // metres: the widest stitch's start gap
  double sewTime_ = 0;               // seconds of sewing so far (both phases)
  double dts_ = 0;
  long long solves_ = 0;
  double lastStepSpeed_ = 0;  // m/s, fastest vertex over the last step
  double windowSpeed_ = 0;    // m/s, the largest net motion over the last rest window
  int windowFastest_ = 0;     // its vertex
  double peakStrain_ = 1;     // largest triangle stretch seen at the end of a step

  void build(const DrapeInput& input);
  void wrapSelfSewnPanels(const DrapeInput& input);
  void separateLayers(const DrapeInput& input);
  void orientPanels(const DrapeInput& input);
  double triangleOutward(const Vector3d& a, const Vector3d& b, const Vector3d& c,
                         const Vector3d& n, double panelSide) const;
  bool wrapAroundLimb(int panel, const std::vector<std::pair<int, int>>& pairs);
  bool step(std::string& why);
  void substep();
  void solveTriangle(const TriangleConstraint& c, double* lambda);
  void solveBend(const BendConstraint& c, Vector3d& lambda);
  void solveStitches();
  void limitStrain();
  int sewClosedStitches();
  void markNearOpenStitches();
  void weldSewn();
  void recolour();
  void syncMerged();
  void solveContacts();
  void solveBody(int v);
  void findContacts();
  bool searchDue() const;
  double stitchGap(double* mean, int* widest = nullptr) const;
  std::string where(int v) const;
  template <class Solve>
  void forColours(const std::vector<std::vector<int>>& groups, bool serialLast, Solve solve);
};

void ClothSim::build(const DrapeInput& input) {
  // Vertices of all panels, concatenated.
  result_.panelOffset.assign(1, 0);
  for (const ClothPanel& p : input.panels)
    result_.panelOffset.push_back(result_.panelOffset.back() + p.numVertices());
  nv_ = result_.panelOffset.back();
  for (const ClothPanel& p : input.panels) names_.push_back(p.name);
  x_.resize(nv_);
  int nf = 0;
  for (const ClothPanel& p : input.panels) nf += p.numFaces();
  F_.resize(nf, 3);
  std::vector<Eigen::Vector2d> rest(nv_);
  std::mt19937 rng(o_.seed);
  auto noise = [&] { return o_.jitter * (2.0 * rng() / double(std::mt19937::max()) - 1.0); };
  for (size_t p = 0, f0 = 0; p < input.panels.size(); ++p) {
    const ClothPanel& panel = input.panels[p];
    const int off = result_.panelOffset[p];
    for (int v = 0; v < panel.numVertices(); ++v) {
      x_[off + v] = panel.start.row(v).transpose();
      for (int a = 0; a < 3; ++a) x_[off + v][a] += noise();
      rest[off + v] = panel.rest2d.row(v).transpose();
    }
    F_.middleRows(f0, panel.numFaces()) = panel.F.array() + off;
    f0 += panel.numFaces();
    layer_.insert(layer_.end(), panel.numVertices(), panel.layer);
    panelOfFace_.insert(panelOfFace_.end(), panel.numFaces(), static_cast<int>(p));
    layered_ = layered_ || panel.layer != input.panels.front().layer;
  }
  xprev_ = x_;
  xstep_ = x_;
  vel_.assign(nv_, Vector3d::Zero());

  // Stretch/shear triangles and lumped masses.
  std::vector<double> mass(nv_, 0.0);
  double edgeSum = 0;
  std::vector<int> triFace;  // the face of each triangle constraint
  for (int f = 0; f < nf; ++f) {
    TriangleConstraint c;
    for (int k = 0; k < 3; ++k) c.v[k] = F_(f, k);
    Eigen::Matrix2d Dm;
    Dm.col(0) = rest[c.v[1]] - rest[c.v[0]];
    Dm.col(1) = rest[c.v[2]] - rest[c.v[0]];
    const double det = Dm.determinant();
    edgeSum += Dm.col(0).norm() + Dm.col(1).norm() + (rest[c.v[2]] - rest[c.v[1]]).norm();
    c.area = 0.5 * std::abs(det);
    if (!(c.area > 1e-12)) continue;  // degenerate in the pattern: carries no stretch
    const Eigen::Matrix2d D = Dm.inverse();
    c.d00 = D(0, 0), c.d01 = D(0, 1), c.d10 = D(1, 0), c.d11 = D(1, 1);
    tris_.push_back(c);
    triFace.push_back(f);
    for (int k = 0; k < 3; ++k) mass[c.v[k]] += o_.density * c.area / 3;
  }
  meanEdge_ = nf > 0 ? edgeSum / (3.0 * nf) : 0.01;
  std::vector<int> faceRank;
  // Faces panel by panel in Morton (Z-curve) order of their centroid in the pattern, which the
  // cloth keeps as neighbourhoods in 3D: the contact search, the triangles and the bending
  // stencils visit them in that order (and are coloured in it), neighbours after neighbours.
  {
    std::vector<std::pair<uint64_t, int>> keys(nf);
    int panel = 0;
    for (int f = 0; f < nf; ++f) {
      while (F_(f, 0) >= result_.panelOffset[panel + 1]) ++panel;
      const Eigen::Vector2d c = (rest[F_(f, 0)] + rest[F_(f, 1)] + rest[F_(f, 2)]) / 3;
      const auto cell = [&](double x) {
        return static_cast<uint64_t>(std::clamp(std::floor(x / meanEdge_) + 32768.0, 0.0, 65535.0));
      };
      uint64_t key = 0, cx = cell(c.x()), cy = cell(c.y());
      for (int b = 0; b < 16; ++b)
        key |= ((cx >> b) & 1) << (2 * b) | ((cy >> b) & 1) << (2 * b + 1);
      keys[f] = {static_cast<uint64_t>(panel) << 32 | key, f};
    }
    std::sort(keys.begin(), keys.end());
    searchOrder_.resize(nf);
    faceRank.resize(nf);
    for (int f = 0; f < nf; ++f) searchOrder_[f] = keys[f].second, faceRank[keys[f].second] = f;
  }
  {
    std::vector<int> order(tris_.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](int l, int r) { return faceRank[triFace[l]] < faceRank[triFace[r]]; });
    std::vector<TriangleConstraint> sorted;
    sorted.reserve(tris_.size());
    for (int i : order) sorted.push_back(tris_[i]);
    tris_.swap(sorted);
  }

  w_.resize(nv_);
  for (int v = 0; v < nv_; ++v) w_[v] = mass[v] > 0 ? 1.0 / mass[v] : 0.0;
  mass_ = mass;
  part_.resize(nv_);
  std::iota(part_.begin(), part_.end(), 0);
  Fsim_ = F_;

  // Bending: interior edges of each panel (seams are hinges).
  struct HalfEdge {
    int a, b, opposite, face;
  };
  std::vector<HalfEdge> he;
  he.reserve(3 * nf);
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F_(f, k), b = F_(f, (k + 1) % 3), c = F_(f, (k + 2) % 3);
      he.push_back({std::min(a, b), std::max(a, b), c, f});
    }
  std::sort(he.begin(), he.end(), [](const HalfEdge& l, const HalfEdge& r) {
    return std::tie(l.a, l.b, l.face) < std::tie(r.a, r.b, r.face);
  });
  auto cot = [](const Eigen::Vector2d& u, const Eigen::Vector2d& v) {
    const double cross = std::abs(u.x() * v.y() - u.y() * v.x());
    return cross > 1e-14 ? u.dot(v) / cross : std::numeric_limits<double>::quiet_NaN();
  };
  for (size_t i = 0; i < he.size(); ++i)
    if (i == 0 || he[i].a != he[i - 1].a || he[i].b != he[i - 1].b)
      edges_.push_back({he[i].a, he[i].b, (rest[he[i].a] - rest[he[i].b]).norm()});
  std::vector<int> bendFace;  // the rank of each bending stencil's first face
  for (size_t i = 0; i + 1 < he.size(); ++i) {
    if (he[i].a != he[i + 1].a || he[i].b != he[i + 1].b) continue;
    if (i + 2 < he.size() && he[i + 2].a == he[i].a && he[i + 2].b == he[i].b) {
      while (i + 1 < he.size() && he[i + 1].a == he[i].a && he[i + 1].b == he[i].b) ++i;
      continue;  // non-manifold edge: no bending across it
    }
    BendConstraint c;
    c.v[0] = he[i].a, c.v[1] = he[i].b, c.v[2] = he[i].opposite, c.v[3] = he[i + 1].opposite;
    const Eigen::Vector2d &x0 = rest[c.v[0]], &x1 = rest[c.v[1]], &x2 = rest[c.v[2]],
                          &x3 = rest[c.v[3]];
    const Eigen::Vector2d e0 = x1 - x0, e1 = x2 - x0, e2 = x3 - x0, e3 = x2 - x1, e4 = x3 - x1;
    const double c01 = cot(e0, e1), c02 = cot(e0, e2), c03 = cot(-e0, e3), c04 = cot(-e0, e4);
    c.k[0] = c03 + c04, c.k[1] = c01 + c02, c.k[2] = -c01 - c03, c.k[3] = -c02 - c04;
    const double a0 = 0.5 * std::abs(e0.x() * e1.y() - e0.y() * e1.x());
    const double a1 = 0.5 * std::abs(e0.x() * e2.y() - e0.y() * e2.x());
    c.alpha = (a0 + a1) / 3;
    ++i;
    if (!(std::isfinite(c.k[0] + c.k[1] + c.k[2] + c.k[3]) && a0 > 1e-12 && a1 > 1e-12)) continue;
    bends_.push_back(c);
    bendFace.push_back(std::min(faceRank[he[i - 1].face], faceRank[he[i].face]));
  }

  {
    std::vector<int> order(bends_.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](int l, int r) { return bendFace[l] < bendFace[r]; });
    std::vector<BendConstraint> sorted;
    sorted.reserve(bends_.size());
    for (int i : order) sorted.push_back(bends_[i]);
    bends_.swap(sorted);
  }

  // Rest length of the boundary edges at each vertex (mean), for the stitches' pull.
  std::vector<double> boundaryLength(nv_, 0.0);
  std::vector<int> boundaryEdges(nv_, 0);
  for (size_t i = 0; i < he.size();) {
    size_t j = i + 1;
    while (j < he.size() && he[j].a == he[i].a && he[j].b == he[i].b) ++j;
    if (j - i == 1) {
      const double l = (rest[he[i].a] - rest[he[i].b]).norm();
      for (int v : {he[i].a, he[i].b}) boundaryLength[v] += l, ++boundaryEdges[v];
    }
    i = j;
  }
  auto edgeAt = [&](int v) {
    return boundaryEdges[v] > 0 ? boundaryLength[v] / boundaryEdges[v] : meanEdge_;
  };

  // Stitches and the welded vertex graph (partners are one point once sewn).
  weld_.resize(nv_);
  std::iota(weld_.begin(), weld_.end(), 0);
  for (const ClothStitch& s : input.stitches) {
    const int a = result_.panelOffset[s.panelA] + s.vertexA;
    const int b = result_.panelOffset[s.panelB] + s.vertexB;
    stitches_.emplace_back(a, b);
    stitchEdge_.push_back(0.5 * (edgeAt(a) + edgeAt(b)));
    const int ra = findRoot(weld_, a), rb = findRoot(weld_, b);
    if (ra != rb) weld_[std::max(ra, rb)] = std::min(ra, rb);
  }
  for (int v = 0; v < nv_; ++v) weld_[v] = findRoot(weld_, v);
  std::vector<std::pair<int, int>> edges;
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = weld_[F_(f, k)], b = weld_[F_(f, (k + 1) % 3)];
      edges.emplace_back(a, b);
      edges.emplace_back(b, a);
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  adjStart_.assign(nv_ + 1, 0);
  for (const auto& e : edges) ++adjStart_[e.first + 1];
  std::partial_sum(adjStart_.begin(), adjStart_.end(), adjStart_.begin());
  adj_.resize(edges.size());
  for (size_t i = 0; i < edges.size(); ++i) adj_[i] = edges[i].second;

  recolour();
  triLambda_.assign(3 * tris_.size(), 0.0);
  bendLambda_.assign(bends_.size(), Vector3d::Zero());
  result_.numConstraints = static_cast<int>(tris_.size() + bends_.size() + stitches_.size());
  result_.numColours = static_cast<int>(triColours_.size() + bendColours_.size());

  // The body's signed distance over the garment's reach.
  Eigen::AlignedBox3d cloth;
  for (const Vector3d& p : x_) cloth.extend(p);
  BodySdfOptions so;
  so.voxel = o_.sdfVoxel;
  so.exteriorBand = std::max(0.02, 4 * o_.sdfVoxel);
  so.interiorBand = std::max(0.02, 4 * o_.sdfVoxel);
  const double reach = 0.5;  // metres the cloth may fall or spread beyond its start box
  so.region.min = cloth.min() - Vector3d::Constant(reach);
  so.region.max = cloth.max() + Vector3d::Constant(reach);
  sdf_ = std::make_unique<BodySdf>(input.body, so);

  scene_ = cloth;
  for (int v = 0; v < input.body.numVertices(); ++v)
    scene_.extend(Vector3d(input.body.V.row(v).transpose()));
  const double grow = std::max(1.0, scene_.diagonal().norm());
  scene_.min().array() -= grow;
  scene_.max().array() += grow;

  // Vertices that start inside the body (as placed): counted per panel and warned.
  for (size_t p = 0; p < input.panels.size() && !o_.startsDraped; ++p) {
    int inside = 0;
    for (int v = result_.panelOffset[p]; v < result_.panelOffset[p + 1]; ++v)
      inside += sdf_->sample(x_[v]).distance < 0;
    if (inside > 0)
      result_.warnings.push_back(fmt::format(
          "drape: panel '{}' starts with {} of {} vertices inside the body (pushed out before "
          "sewing; check the placement)",
          input.panels[p].name, inside, input.panels[p].numVertices()));
    result_.startInsideBody += inside;
  }
  if (!o_.startsDraped) {
    separateLayers(input);
    wrapSelfSewnPanels(input);
  }
  // Then every vertex closer than the thickness (as placed, or wrapped against the body where a
  // sleeve meets the torso) is moved out before the first step.
  for (int v = 0; v < nv_; ++v) {
    const SdfSample s = sdf_->sample(x_[v]);
    if (s.distance < o_.bodyThickness) x_[v] += (o_.bodyThickness - s.distance) * s.normal;
  }
  orientPanels(input);
  xprev_ = x_;
  xstep_ = x_;
  for (const auto& [a, b] : stitches_) stitchStart_.push_back((x_[a] - x_[b]).norm());
  for (double g : stitchStart_) maxStart_ = std::max(maxStart_, g);
  sewn_.assign(stitches_.size(), 0);
  merged_.assign(stitches_.size(), 0);
  markNearOpenStitches();
}

// The outward normal of panel p as placed (flat: its faces' area vector, turned away from the
// body's closest point to its centroid); zero for a panel too curved or too small to have one.
namespace {
Vector3d placedNormal(const std::vector<Vector3d>& x, const Eigen::MatrixX3i& F, int f0, int f1,
                      const Vector3d& centroid, const BodySdf& sdf) {
  Vector3d n = Vector3d::Zero();
  for (int f = f0; f < f1; ++f) n += (x[F(f, 1)] - x[F(f, 0)]).cross(x[F(f, 2)] - x[F(f, 0)]);
  if (n.norm() < 1e-12) return Vector3d::Zero();
  n.normalize();
  const Vector3d closest = sdf.query().closestPoint(centroid).point;
  return (centroid - closest).dot(n) < 0 ? Vector3d(-n) : n;
}
}  // namespace

// Panels of an outer layer that overlap a lower layer's panels in height start layerGap further
// out along their normal (rigidly), so that each garment starts on its own side of the other.
void ClothSim::separateLayers(const DrapeInput& input) {
  if (!layered_ || !(o_.layerGap > 0)) return;
  const int np = static_cast<int>(input.panels.size());
  std::vector<double> lo(np, 1e30), hi(np, -1e30);
  std::vector<Vector3d> centroid(np, Vector3d::Zero());
  for (int p = 0; p < np; ++p) {
    for (int v = result_.panelOffset[p]; v < result_.panelOffset[p + 1]; ++v) {
      lo[p] = std::min(lo[p], x_[v].y()), hi[p] = std::max(hi[p], x_[v].y());
      centroid[p] += x_[v];
    }
    centroid[p] /= std::max(1, input.panels[p].numVertices());
  }
  int f0 = 0;
  for (int p = 0; p < np; ++p) {
    const int f1 = f0 + input.panels[p].numFaces();
    bool over = false;
    for (int q = 0; q < np && !over; ++q)
      over = input.panels[q].layer < input.panels[p].layer && lo[p] < hi[q] && lo[q] < hi[p];
    if (over) {
      const Vector3d n = placedNormal(x_, F_, f0, f1, centroid[p], *sdf_);
      for (int v = result_.panelOffset[p]; v < result_.panelOffset[p + 1]; ++v)
        x_[v] += o_.layerGap * input.panels[p].layer * n;
    }
    f0 = f1;
  }
}

// Which way each panel's faces face: the sign of Σ n_f·(c_f − closest body point) over a sample
// of its faces as they start. A panel keeps its side of the body while it drapes, so the sign
// holds; contacts between layers use it to tell outside from inside.
void ClothSim::orientPanels(const DrapeInput& input) {
  const int np = static_cast<int>(input.panels.size());
  outward_.assign(np, 1.0);
  if (!layered_) return;
  int f0 = 0;
  for (int p = 0; p < np; ++p) {
    const int nf = input.panels[p].numFaces(), stride = std::max(1, nf / 64);
    double sum = 0;
    for (int f = f0; f < f0 + nf; f += stride) {
      const Vector3d &a = x_[F_(f, 0)], &b = x_[F_(f, 1)], &c = x_[F_(f, 2)];
      const Vector3d centroid = (a + b + c) / 3;
      const Vector3d away = centroid - sdf_->query().closestPoint(centroid).point;
      sum += (b - a).cross(c - a).normalized().dot(away.normalized());
    }
    outward_[p] = sum < 0 ? -1.0 : 1.0;
    f0 += nf;
  }
}

// Which side of triangle (a, b, c) with unit normal n faces away from the body: +1 along n,
// −1 against it; `panelSide` (orientPanels) where the triangle stands on edge to the body (its
// normal within 60° of the body's surface plane, a fold's wall). A layer's contacts take their
// side per triangle: where the cloth folds back on itself (a waistband bunched at the hip) its
// triangles face the other way from the panel's, and the panel's sign pushed the outer layer
// through the fold and into the body (plus_size's fine drape: 3.9–4.4× within 5–20 steps).
double ClothSim::triangleOutward(const Vector3d& a, const Vector3d& b, const Vector3d& c,
                                 const Vector3d& n, double panelSide) const {
  const Vector3d centroid = (a + b + c) / 3;
  const SdfSample s = sdf_->sample(centroid);
  const Vector3d away = s.distance < sdf_->exteriorBand()
                            ? s.normal
                            : (centroid - sdf_->query().closestPoint(centroid).point).normalized();
  const double cosine = n.dot(away);
  if (!std::isfinite(cosine) || std::abs(cosine) < 0.5) return panelSide;
  return cosine > 0 ? 1.0 : -1.0;
}

// A panel sewn to itself across its width (a one-piece sleeve's underarm seam, a trouser leg's
// inseam) is placed flat over its limb (placement.h), the seam's two edges 30–40 cm apart on
// either side. The stitches pull straight across, so the two halves fold up and meet above the
// limb: a closed tube with no limb in it (the long sleeves of longsleeve_shorts, 12 cm open
// after 600 steps). Such a panel is wrapped around its limb before sewing instead, as a tailor
// arranges a sleeve round the arm: isometrically (the arc across the panel keeps its flat
// width) about an axis along the seam, as deep under the panel as the middle of the limb below
// it; the seam then starts under the limb, a few centimetres open.
void ClothSim::wrapSelfSewnPanels(const DrapeInput& input) {
  for (size_t p = 0; p < input.panels.size(); ++p) {
    std::vector<std::pair<int, int>> pairs;  // garment vertices
    for (const ClothStitch& st : input.stitches)
      if (st.panelA == static_cast<int>(p) && st.panelB == static_cast<int>(p))
        pairs.emplace_back(result_.panelOffset[p] + st.vertexA,
                           result_.panelOffset[p] + st.vertexB);
    if (pairs.size() >= 3 && wrapAroundLimb(static_cast<int>(p), pairs))
      result_.wrappedPanels.push_back(names_[p]);
  }
}

// The shortest self-seam wrapped, × the square root of its panel's area. A tube of length L and
// girth W has L / √(L·W) = √(L/W): a cap sleeve's 0.4, a short sleeve's 0.5, a long one's 1.2
// (the suite); a third is a seam a ninth of the way round, no tube's length (the crescents of
// sleeves the scan fused to the trunk: 0.06–0.27).
constexpr double kWrapMinSeam = 1.0 / 3;

// Wraps panel p (flat, sewn to itself by `pairs` across its width) around the limb under it;
// false (the panel untouched) when it is not flat, the seam does not join its two sides, or no
// limb lies under it.
bool ClothSim::wrapAroundLimb(int p, const std::vector<std::pair<int, int>>& pairs) {
  const int v0 = result_.panelOffset[p], v1 = result_.panelOffset[p + 1];
  Vector3d areaVector = Vector3d::Zero(), centroid = Vector3d::Zero();
  double area = 0;
  for (int f = 0; f < F_.rows(); ++f) {
    if (F_(f, 0) < v0 || F_(f, 0) >= v1) continue;
    const Vector3d c = (x_[F_(f, 1)] - x_[F_(f, 0)]).cross(x_[F_(f, 2)] - x_[F_(f, 0)]);
    areaVector += 0.5 * c;
    area += 0.5 * c.norm();
  }
  if (!(area > 0) || areaVector.norm() < 0.98 * area) return false;  // not laid flat
  for (int v = v0; v < v1; ++v) centroid += x_[v];
  centroid /= v1 - v0;
  Vector3d n = areaVector.normalized();
  const auto mid = [&](const std::pair<int, int>& s) { return 0.5 * (x_[s.first] + x_[s.second]); };
  Vector3d along = mid(pairs.back()) - mid(pairs.front());
  along -= along.dot(n) * n;
  if (along.norm() < 1e-6) return false;
  // A seam much shorter than the panel is no tube's length: walking's sleeves, where the scan
  // fused the sleeve to the trunk and only its outer half is cloth, are crescents sewn to
  // themselves along 14–60 mm of underarm, wrapped about an axis that short seam could not set
  // (the drape failed at its first step, 3.5× at the sleeve's top).
  if (along.norm() < kWrapMinSeam * std::sqrt(area)) return false;
  along.normalize();
  Vector3d across = n.cross(along);
  // The seam joins the panel's two sides: each pair's partners on opposite sides, far apart.
  double halfWidth = 0;
  for (int v = v0; v < v1; ++v)
    halfWidth = std::max(halfWidth, std::abs((x_[v] - centroid).dot(across)));
  int acrossPairs = 0;
  for (const auto& s : pairs) {
    const double wa = (x_[s.first] - centroid).dot(across),
                 wb = (x_[s.second] - centroid).dot(across);
    acrossPairs += wa * wb < 0 && std::min(std::abs(wa), std::abs(wb)) > 0.25 * halfWidth;
  }
  if (4 * acrossPairs < 3 * static_cast<int>(pairs.size())) return false;
  // The limb under the middle half of the seam: entered and left along −n (or +n: the side the
  // body is on); its axis half way, its radius half the way through.
  struct Limb {
    double depth = -1, radius = 0;  // metres below the panel
  };
  const auto limbUnder = [&](const Vector3d& from, const Vector3d& dir) {
    const double step = 0.5 * o_.sdfVoxel, reach = 0.3;
    double entry = -1;
    for (double t = 0; t <= reach; t += step) {
      const bool inside = sdf_->sample(from + t * dir).distance < 0;
      if (entry < 0 && inside) entry = t;
      if (entry >= 0 && !inside) return Limb{0.5 * (entry + t), 0.5 * (t - entry)};
    }
    return Limb{};
  };
  std::vector<double> depths, radii;
  for (int side = 0; side < 2 && depths.empty(); ++side) {
    if (side == 1) n = -n, across = -across;
    for (size_t k = pairs.size() / 4; k < pairs.size() - pairs.size() / 4; ++k) {
      const Limb limb = limbUnder(mid(pairs[k]), -n);
      if (limb.depth > 0) depths.push_back(limb.depth), radii.push_back(limb.radius);
    }
    if (2 * depths.size() < pairs.size() / 2) depths.clear(), radii.clear();
  }
  if (depths.empty()) return false;
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  const double depth = median(depths), limbRadius = median(radii);
  // The axis under the seam's middle line; the panel wrapped close round the limb, but no
  // tighter than leaves its two sides a tenth of the circumference apart.
  double middle = 0;
  for (const auto& s : pairs) middle += (mid(s) - centroid).dot(across);
  middle /= static_cast<double>(pairs.size());
  const Vector3d origin = centroid + middle * across - depth * n;
  double span = 0;
  for (int v = v0; v < v1; ++v) span = std::max(span, std::abs((x_[v] - origin).dot(across)));
  constexpr double kWrapClearance = 0.01;  // metres between the wrapped panel and the limb
  const double radius = std::max(limbRadius + kWrapClearance, span / (0.9 * std::numbers::pi));
  for (int v = v0; v < v1; ++v) {
    const Vector3d d = x_[v] - origin;
    const double angle = d.dot(across) / radius;
    const double r = radius + d.dot(n) - depth;  // the panel's own thickness off its plane
    x_[v] = origin + d.dot(along) * along + r * (std::cos(angle) * n + std::sin(angle) * across);
  }
  return true;
}

template <class Solve>
void ClothSim::forColours(const std::vector<std::vector<int>>& groups, bool serialLast,
                          Solve solve) {
  for (size_t g = 0; g < groups.size(); ++g) {
    const std::vector<int>& group = groups[g];
    if (serialLast && g + 1 == groups.size()) {
      for (int c : group) solve(c);
      continue;
    }
    tbb::parallel_for(tbb::blocked_range<size_t>(0, group.size(), 256),
                      [&](const tbb::blocked_range<size_t>& r) {
                        for (size_t i = r.begin(); i < r.end(); ++i) solve(group[i]);
                      });
  }
}

// Strain-based stretch and shear of one triangle (three scalar XPBD constraints in turn).
void ClothSim::solveTriangle(const TriangleConstraint& c, double* lambda) {
  Vector3d& x0 = x_[c.v[0]];
  Vector3d& x1 = x_[c.v[1]];
  Vector3d& x2 = x_[c.v[2]];
  const double w0 = w_[c.v[0]], w1 = w_[c.v[1]], w2 = w_[c.v[2]];
  const double inv = 1.0 / (c.area * dts_ * dts_);
  for (int k = 0; k < 3; ++k) {
    const Vector3d e1 = x1 - x0, e2 = x2 - x0;
    const Vector3d fu = e1 * c.d00 + e2 * c.d10, fv = e1 * c.d01 + e2 * c.d11;
    double C, alpha;
    Vector3d g1, g2;
    if (k < 2) {
      const Vector3d& f = k == 0 ? fu : fv;
      const double l = f.norm();
      if (l < 1e-12) continue;
      const Vector3d n = f / l;
      C = l - 1;
      g1 = n * (k == 0 ? c.d00 : c.d01);
      g2 = n * (k == 0 ? c.d10 : c.d11);
      alpha = o_.stretchCompliance * inv;
    } else {
      C = fu.dot(fv);
      g1 = fv * c.d00 + fu * c.d01;
      g2 = fv * c.d10 + fu * c.d11;
      alpha = o_.shearCompliance * inv;
    }
    const Vector3d g0 = -(g1 + g2);
    const double denom =
        w0 * g0.squaredNorm() + w1 * g1.squaredNorm() + w2 * g2.squaredNorm() + alpha;
    if (denom < 1e-20) continue;
    const double dl = (-C - alpha * lambda[k]) / denom;
    lambda[k] += dl;
    x0 += w0 * dl * g0;
    x1 += w1 * dl * g1;
    x2 += w2 * dl * g2;
  }
}

// Isometric bending (Bergou et al. 2006): the vector constraint Σ k_i x_i = 0 is linear, its
// gradient k_i·I, so each coordinate is an independent scalar XPBD update with one denominator.
void ClothSim::solveBend(const BendConstraint& c, Vector3d& lambda) {
  Vector3d C = Vector3d::Zero();
  double denom = 0;
  for (int i = 0; i < 4; ++i) {
    C += c.k[i] * x_[c.v[i]];
    denom += w_[c.v[i]] * c.k[i] * c.k[i];
  }
  const double alpha = o_.bendingCompliance * c.alpha / (dts_ * dts_);
  denom += alpha;
  if (denom < 1e-20) return;
  const Vector3d dl = (-C - alpha * lambda) / denom;
  lambda += dl;
  for (int i = 0; i < 4; ++i) x_[c.v[i]] += w_[c.v[i]] * c.k[i] * dl;
}

// Colours for the parallel Gauss–Seidel sweeps (again after every weld: particles changed).
void ClothSim::recolour() {
  triColours_ = colourConstraints(
      static_cast<int>(tris_.size()), nv_,
      [&](int c) {
        return std::array<int, 3>{tris_[c].v[0], tris_[c].v[1], tris_[c].v[2]};
      },
      triSerialLast_);
  bendColours_ = colourConstraints(
      static_cast<int>(bends_.size()), nv_,
      [&](int c) {
        const auto& b = bends_[c];
        return std::array<int, 4>{b.v[0], b.v[1], b.v[2], b.v[3]};
      },
      bendSerialLast_);
}

// Merges the partners of newly sewn stitches into one particle (masses summed, position and
// velocity mass-weighted) and puts every constraint on the particles. A sewn seam is one line of
// cloth: both panels' triangles act on the same particles, and its gap is exactly zero (a
// projection of the partners to their mean after the triangles leaves each substep's last
// triangle correction between them).
void ClothSim::weldSewn() {
  bool changed = false;
  for (size_t i = 0; i < stitches_.size(); ++i) {
    if (!sewn_[i] || merged_[i]) continue;
    merged_[i] = 1;
    int a = findRoot(part_, stitches_[i].first), b = findRoot(part_, stitches_[i].second);
    if (a == b) continue;
    if (b < a) std::swap(a, b);
    const double m = mass_[a] + mass_[b];
    if (!(m > 0)) continue;
    x_[a] = (mass_[a] * x_[a] + mass_[b] * x_[b]) / m;
    vel_[a] = (mass_[a] * vel_[a] + mass_[b] * vel_[b]) / m;
    xprev_[a] = (mass_[a] * xprev_[a] + mass_[b] * xprev_[b]) / m;
    mass_[a] = m;
    mass_[b] = 0;
    w_[a] = 1.0 / m;
    w_[b] = 0;
    part_[b] = a;
    changed = true;
  }
  if (!changed) return;
  for (int v = 0; v < nv_; ++v) part_[v] = findRoot(part_, v);
  for (int f = 0; f < Fsim_.rows(); ++f)
    for (int k = 0; k < 3; ++k) Fsim_(f, k) = part_[F_(f, k)];
  // A stitch between two vertices of one triangle (or bending stencil) collapses it: dropped.
  std::vector<TriangleConstraint> tris;
  for (TriangleConstraint c : tris_) {
    for (int& v : c.v) v = part_[v];
    if (c.v[0] != c.v[1] && c.v[1] != c.v[2] && c.v[0] != c.v[2]) tris.push_back(c);
  }
  tris_.swap(tris);
  std::vector<BendConstraint> bends;
  for (BendConstraint c : bends_) {
    for (int& v : c.v) v = part_[v];
    bool distinct = true;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) distinct = distinct && c.v[i] != c.v[j];
    if (distinct) bends.push_back(c);
  }
  bends_.swap(bends);
  recolour();
  triLambda_.assign(3 * tris_.size(), 0.0);
  bendLambda_.assign(bends_.size(), Vector3d::Zero());
  syncMerged();
}

// Vertices merged into another particle take its position.
void ClothSim::syncMerged() {
  for (int v = 0; v < nv_; ++v)
    if (part_[v] != v) x_[v] = x_[part_[v]];
}

// Sewing (a seam is sewn once its partners meet, as in GarmentCode's and the commercial tools'
// simulators). An open stitch holds its partners at most L0·max(0, 1 − sewSpeed·t / Lmax) apart
// (L0 their start distance, Lmax the widest stitch's): every stitch arrives at the same time, as
// under GarmentCode's zero-length stitch springs, whose pull is proportional to the gap. At one
// speed for all, short seams closed first: a crotch's centre-front and centre-back seams (3 cm
// apart at the start) were sewn long before the inseams (27 cm), and the two crotch points they
// made then met under the body 2–3 cm apart in depth, the cloth between them at the strain limit
// (bag, skin_tone_top, jacket_layered; 12–22 mm on the demo's coarse mesh). Arriving together,
// the four corners meet where the inseams bring them. A stitch pulls its partners by at most
// sewPull of its seam's edge length per substep beyond where the cloth left them. A hard
// schedule alone runs ahead of a cloth that has to be dragged (over a shoulder, around the
// body): the stitched row is then torn from the next one (3× at 10 mm, where a substep's single
// sweep moves the cloth a shorter way); bounded, the row leads the cloth by at most a fraction
// of an edge. A stitch whose gap fell below sewTolerance is sewn: its partners become one
// particle (weldSewn).
void ClothSim::solveStitches() {
  for (size_t i = 0; i < stitches_.size(); ++i) {
    if (merged_[i]) continue;
    const int a = part_[stitches_[i].first], b = part_[stitches_[i].second];
    const double wsum = w_[a] + w_[b];
    if (a == b || wsum <= 0) continue;
    const Vector3d d = x_[b] - x_[a];
    const double len = d.norm();
    const double target = stitchStart_[i] * std::max(0.0, 1.0 - o_.sewSpeed * sewTime_ / maxStart_);
    if (len <= target) continue;
    const double pull = std::min(len - target, o_.sewPull * stitchEdge_[i]);
    const double s = pull / len / wsum;
    x_[a] += (w_[a] * s) * d;
    x_[b] -= (w_[b] * s) * d;
  }
}

// Strain limiting (Provot 1995): edges longer than strainLimit × their pattern length are
// shortened to it, in Gauss–Seidel passes over the overstretched ones (found anew each pass, in
// edge order: deterministic). One sweep per substep carries a load about one row: where a
// strip's weight turns into a seam corner, the corner alone stretched 3× at 10 mm (the load
// needs (carried mass / vertex mass)·g·Δt² of violation, and the vertex mass falls as edge²).
// The passes carry it across the overstretched region within the substep. The stitches are
// pulled after it: a seam whose two sides differ by a little (10 % of a 30 mm edge is 3 mm) is
// eased in rather than held open by the limit.
void ClothSim::limitStrain() {
  if (!(o_.strainLimit > 0)) return;
  constexpr int kChunks = 64;
  const int ne = static_cast<int>(edges_.size());
  std::vector<std::vector<int>> found(kChunks);
  for (int pass = 0; pass < o_.strainLimitPasses; ++pass) {
    tbb::parallel_for(0, kChunks, [&](int chunk) {
      std::vector<int>& out = found[chunk];
      out.clear();
      const int e0 = static_cast<int>(int64_t(ne) * chunk / kChunks);
      const int e1 = static_cast<int>(int64_t(ne) * (chunk + 1) / kChunks);
      for (int e = e0; e < e1; ++e) {
        const LimitEdge& l = edges_[e];
        const double limit = o_.strainLimit * l.rest;
        if ((x_[part_[l.a]] - x_[part_[l.b]]).squaredNorm() > limit * limit) out.push_back(e);
      }
    });
    bool any = false;
    for (const auto& chunk : found)
      for (int e : chunk) {
        const LimitEdge& l = edges_[e];
        const int a = part_[l.a], b = part_[l.b];
        const double wsum = w_[a] + w_[b];
        if (a == b || wsum <= 0) continue;
        const Vector3d d = x_[b] - x_[a];
        const double len = d.norm(), limit = o_.strainLimit * l.rest;
        if (len <= limit) continue;
        const double s = (len - limit) / len / wsum;
        x_[a] += (w_[a] * s) * d;
        x_[b] -= (w_[b] * s) * d;
        any = true;
      }
    solves_ += ne;
    if (!any) break;
  }
}

// Marks the cloth within sewContactRings edges (of the welded graph) of an open stitch.
void ClothSim::markNearOpenStitches() {
  nearOpen_.assign(nv_, 0);
  if (o_.sewContactRings <= 0) return;
  std::vector<int> front, next;
  for (size_t i = 0; i < stitches_.size(); ++i)
    if (!sewn_[i])
      for (int v : {weld_[stitches_[i].first], weld_[stitches_[i].second]})
        if (!nearOpen_[v]) nearOpen_[v] = 1, front.push_back(v);
  for (int ring = 0; ring < o_.sewContactRings && !front.empty(); ++ring) {
    next.clear();
    for (int v : front)
      for (int q = adjStart_[v]; q < adjStart_[v + 1]; ++q)
        if (!nearOpen_[adj_[q]]) nearOpen_[adj_[q]] = 1, next.push_back(adj_[q]);
    front.swap(next);
  }
}

// Stitches whose partners met are sewn (welded from then on); the number still open.
int ClothSim::sewClosedStitches() {
  int open = 0;
  for (size_t i = 0; i < stitches_.size(); ++i) {
    if (sewn_[i]) continue;
    const auto [a, b] = stitches_[i];
    if ((x_[a] - x_[b]).norm() < o_.sewTolerance)
      sewn_[i] = 1;
    else
      ++open;
  }
  return open;
}

// Self-collision: keep each found vertex on its side of its triangle, selfThickness away.
void ClothSim::solveContacts() {
  const double h = o_.selfThickness;
  for (const Contact& c : contacts_) {
    if (nearOpen_[weld_[c.v]] || nearOpen_[weld_[F_(c.t, 0)]] || nearOpen_[weld_[F_(c.t, 1)]] ||
        nearOpen_[weld_[F_(c.t, 2)]])
      continue;
    const int i0 = Fsim_(c.t, 0), i1 = Fsim_(c.t, 1), i2 = Fsim_(c.t, 2);
    const Vector3d &a = x_[i0], &b = x_[i1], &cc = x_[i2], &p = x_[c.v];
    const Vector3d nn = (b - a).cross(cc - a);
    const double area2 = nn.norm();
    if (area2 < 1e-14) continue;
    const Vector3d n = nn / area2;
    // Barycentric coordinates of p's projection.
    const Vector3d q = p - n.dot(p - a) * n;
    const double ba = (b - q).cross(cc - q).dot(n) / area2;
    const double bb = (cc - q).cross(a - q).dot(n) / area2;
    const double bc = 1 - ba - bb;
    if (ba < -0.05 || bb < -0.05 || bc < -0.05) continue;
    Vector3d bary(std::max(ba, 0.0), std::max(bb, 0.0), std::max(bc, 0.0));
    bary /= bary.sum();
    const Vector3d s = bary[0] * a + bary[1] * b + bary[2] * cc;
    const double C = c.side * n.dot(p - s) - h;
    // Apart, or crossed further than the two could have moved since the search (then the side
    // is no longer known): no correction.
    if (C >= 0 || C < -contactRadius_ - h) continue;
    const double denom = w_[c.v] + bary[0] * bary[0] * w_[i0] + bary[1] * bary[1] * w_[i1] +
                         bary[2] * bary[2] * w_[i2];
    if (denom < 1e-20) continue;
    // A vertex found on the wrong side of another layer goes back through it a thickness per
    // pass, not at once: pushed the whole way (up to the search radius, an edge at 10 mm) it
    // tore the triangles around it (plus_size's waistband, 3.5× within three steps).
    const double dl = (c.layered ? std::min(-C, h) : -C) / denom;
    const Vector3d dir = c.side * n;
    x_[c.v] += w_[c.v] * dl * dir;
    x_[i0] -= w_[i0] * bary[0] * dl * dir;
    x_[i1] -= w_[i1] * bary[1] * dl * dir;
    x_[i2] -= w_[i2] * bary[2] * dl * dir;
  }
}

// Body: distance ≥ thickness along the SDF gradient, Coulomb friction on the tangential motion
// of this substep. Cloth near a stitch still open slides as while sewing (sewFriction): the seam
// closes by sliding over the body, and the drape's friction would hold it open (the demo's
// crotch stayed 21 mm open under the drape's 0.5).
void ClothSim::solveBody(int v) {
  if (w_[v] == 0) return;
  const SdfSample s = sdf_->sample(x_[v]);
  if (s.distance >= o_.bodyThickness) return;
  const double pen = o_.bodyThickness - s.distance;
  x_[v] += pen * s.normal;
  const Vector3d dx = x_[v] - xprev_[v];
  const Vector3d tangential = dx - dx.dot(s.normal) * s.normal;
  const double lt = tangential.norm();
  const double mu = nearOpen_[weld_[v]] ? std::min(friction_, o_.sewFriction) : friction_;
  if (lt > 0) x_[v] -= tangential * std::min(mu * pen / lt, 1.0);
}

// Vertex–triangle pairs closer than selfThickness + selfSkin, from a spatial hash of the
// vertices (counting sort: deterministic); found in fixed chunks of triangles concatenated in
// order. The list holds until a vertex has moved half the skin (a Verlet list): a pair farther
// apart than the radius at the search cannot come within selfThickness before one of them
// (or a triangle corner) has moved that far.
void ClothSim::findContacts() {
  contacts_.clear();
  xsearch_ = x_;
  if (!o_.selfCollision || nv_ == 0) return;
  ++searches_;
  contactRadius_ = o_.selfThickness + o_.selfSkin;
  const double radius = contactRadius_;
  const double cell = std::max(radius, meanEdge_);
  const size_t tableSize = std::bit_ceil(static_cast<size_t>(4 * nv_));
  auto hash = [&](int x, int y, int z) {
    return (static_cast<size_t>(x) * 73856093u ^ static_cast<size_t>(y) * 19349663u ^
            static_cast<size_t>(z) * 83492791u) &
           (tableSize - 1);
  };
  struct Entry {
    int cx, cy, cz, v;
  };
  std::vector<int> start(tableSize + 1, 0);
  std::vector<Entry> entries(nv_);
  std::vector<size_t> bucket(nv_);
  for (int v = 0; v < nv_; ++v) {
    const Eigen::Vector3i c = (x_[v] / cell).array().floor().cast<int>();
    entries[v] = {c.x(), c.y(), c.z(), v};
    bucket[v] = hash(c.x(), c.y(), c.z());
    ++start[bucket[v] + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  {
    std::vector<Entry> sorted(nv_);
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (int v = 0; v < nv_; ++v) sorted[fill[bucket[v]]++] = entries[v];
    entries.swap(sorted);
  }
  const int nf = static_cast<int>(F_.rows());
  constexpr int kChunks = 64;
  std::vector<std::vector<Contact>> found(kChunks);
  tbb::parallel_for(0, kChunks, [&](int chunk) {
    const int f0 = static_cast<int>(int64_t(nf) * chunk / kChunks);
    const int f1 = static_cast<int>(int64_t(nf) * (chunk + 1) / kChunks);
    std::vector<Contact>& out = found[chunk];
    for (int i = f0; i < f1; ++i) {
      const int f = searchOrder_[i];
      const int t[3] = {Fsim_(f, 0), Fsim_(f, 1), Fsim_(f, 2)};
      const int r[3] = {weld_[t[0]], weld_[t[1]], weld_[t[2]]};
      const Vector3d &a = x_[t[0]], &b = x_[t[1]], &c = x_[t[2]];
      const Vector3d nn = (b - a).cross(c - a);
      if (nn.squaredNorm() < 1e-20) continue;
      const Vector3d n = nn.normalized();
      const double invArea2 = 1.0 / nn.norm();
      const Vector3d lo = a.cwiseMin(b).cwiseMin(c) - Vector3d::Constant(radius);
      const Vector3d hi = a.cwiseMax(b).cwiseMax(c) + Vector3d::Constant(radius);
      const Eigen::Vector3i clo = (lo / cell).array().floor().cast<int>();
      const Eigen::Vector3i chi = (hi / cell).array().floor().cast<int>();
      double outward = 0;  // this triangle's own outward side (triangleOutward), when needed
      for (int i = clo.x(); i <= chi.x(); ++i)
        for (int j = clo.y(); j <= chi.y(); ++j)
          for (int k = clo.z(); k <= chi.z(); ++k) {
            const size_t hk = hash(i, j, k);
            for (int e = start[hk]; e < start[hk + 1]; ++e) {
              const Entry& en = entries[e];
              if (en.cx != i || en.cy != j || en.cz != k) continue;
              const int v = en.v;
              if (w_[v] == 0) continue;
              const Vector3d& p = x_[v];
              const double d = n.dot(p - a);
              if (std::abs(d) >= radius) continue;
              // Only a vertex over (or nearly over) the triangle: the same sheet's in-plane
              // neighbours project outside it and are no contact.
              const Vector3d q = p - d * n;
              const double ba = (b - q).cross(c - q).dot(n) * invArea2;
              if (ba < -0.25) continue;
              const double bb = (c - q).cross(a - q).dot(n) * invArea2;
              if (bb < -0.25 || 1 - ba - bb < -0.25) continue;
              const int rv = weld_[v];
              if (rv == r[0] || rv == r[1] || rv == r[2]) continue;
              bool near = false;  // a vertex of the triangle is a (welded) neighbour of v
              for (int q = adjStart_[rv]; q < adjStart_[rv + 1] && !near; ++q)
                near = adj_[q] == r[0] || adj_[q] == r[1] || adj_[q] == r[2];
              if (near) continue;
              const int lt = layer_[t[0]];  // the triangle's layer (one panel's)
              if (layered_ && layer_[v] != lt && outward == 0)
                outward = triangleOutward(a, b, c, n, outward_[panelOfFace_[f]]);
              if (layered_ && layer_[v] != lt)
                out.push_back({v, f, (layer_[v] > lt ? 1.0 : -1.0) * outward, true});
              else
                out.push_back({v, f, d >= 0 ? 1.0 : -1.0});
            }
          }
    }
  });
  for (const auto& chunk : found) contacts_.insert(contacts_.end(), chunk.begin(), chunk.end());
}

// Whether a vertex has moved half the skin since the last contact search.
bool ClothSim::searchDue() const {
  if (!o_.selfCollision) return false;
  if (static_cast<int>(xsearch_.size()) != nv_) return true;
  const double limit = 0.25 * o_.selfSkin * o_.selfSkin;
  return tbb::parallel_reduce(
      tbb::blocked_range<int>(0, nv_, 2048), false,
      [&](const tbb::blocked_range<int>& r, bool due) {
        for (int v = r.begin(); v < r.end() && !due; ++v)
          due = (x_[v] - xsearch_[v]).squaredNorm() > limit;
        return due;
      },
      [](bool a, bool b) { return a || b; });
}

void ClothSim::substep() {
  const double decay = std::exp(-damping_ * dts_);
  tbb::parallel_for(tbb::blocked_range<int>(0, nv_, 1024), [&](const tbb::blocked_range<int>& r) {
    for (int v = r.begin(); v < r.end(); ++v) {
      xprev_[v] = x_[v];
      if (w_[v] == 0) continue;
      Vector3d vel = (vel_[v] + gravity_ * dts_) * decay;
      const double s = vel.norm();
      if (s > o_.maxSpeed) vel *= o_.maxSpeed / s;
      x_[v] += vel * dts_;
    }
  });
  std::fill(triLambda_.begin(), triLambda_.end(), 0.0);
  std::fill(bendLambda_.begin(), bendLambda_.end(), Vector3d::Zero());
  sewTime_ += dts_;
  for (int it = 0; it < o_.iterations; ++it) {
    forColours(triColours_, triSerialLast_,
               [&](int c) { solveTriangle(tris_[c], &triLambda_[3 * c]); });
    forColours(bendColours_, bendSerialLast_, [&](int c) { solveBend(bends_[c], bendLambda_[c]); });
    limitStrain();
    solveStitches();
    solveContacts();
    tbb::parallel_for(tbb::blocked_range<int>(0, nv_, 1024), [&](const tbb::blocked_range<int>& r) {
      for (int v = r.begin(); v < r.end(); ++v) solveBody(v);
    });
    solves_ += 3LL * static_cast<long long>(tris_.size()) + static_cast<long long>(bends_.size()) +
               static_cast<long long>(stitches_.size() + contacts_.size()) + nv_;
  }
  tbb::parallel_for(tbb::blocked_range<int>(0, nv_, 1024), [&](const tbb::blocked_range<int>& r) {
    for (int v = r.begin(); v < r.end(); ++v) vel_[v] = (x_[v] - xprev_[v]) / dts_;
  });
}

// One step (frame); false (with the reason) when the state is no longer a cloth.
bool ClothSim::step(std::string& why) {
  dts_ = o_.timeStep / o_.substeps;
  xstep_ = x_;
  for (int s = 0; s < o_.substeps; ++s) {
    if (searchDue()) findContacts();
    substep();
  }
  syncMerged();
  double maxSpeed = 0;
  bool finiteState = true, inScene = true;
  for (int v = 0; v < nv_; ++v) {
    if (!x_[v].allFinite()) {
      finiteState = false;
      break;
    }
    inScene = inScene && scene_.contains(x_[v]);
    maxSpeed = std::max(maxSpeed, (x_[v] - xstep_[v]).norm() / o_.timeStep);
  }
  if (!finiteState) {
    why = "a vertex position became NaN or infinite";
    return false;
  }
  if (maxSpeed > o_.explodeSpeed) {
    why = fmt::format("a vertex moved at {:.1f} m/s (explosion threshold {:.1f} m/s)", maxSpeed,
                      o_.explodeSpeed);
    return false;
  }
  if (!inScene) {
    why = "the cloth left the scene (fell through the body or was flung away)";
    return false;
  }
  double maxStrain = 0;
  int worst = -1;
  for (size_t t = 0; t < tris_.size(); ++t) {
    const TriangleConstraint& c = tris_[t];
    const Vector3d e1 = x_[c.v[1]] - x_[c.v[0]], e2 = x_[c.v[2]] - x_[c.v[0]];
    const double strain =
        std::max((e1 * c.d00 + e2 * c.d10).norm(), (e1 * c.d01 + e2 * c.d11).norm());
    if (strain > maxStrain) maxStrain = strain, worst = static_cast<int>(t);
  }
  peakStrain_ = std::max(peakStrain_, maxStrain);
  if (maxStrain > o_.explodeStrain) {
    why = fmt::format("a triangle is stretched {:.1f}× its pattern size (threshold {:.1f}×) at {}",
                      maxStrain, o_.explodeStrain, where(tris_[worst].v[0]));
    return false;
  }
  lastStepSpeed_ = maxSpeed;
  return true;
}

double ClothSim::stitchGap(double* mean, int* widest) const {
  double mx = 0, sum = 0;
  for (size_t i = 0; i < stitches_.size(); ++i) {
    const double g = (x_[stitches_[i].first] - x_[stitches_[i].second]).norm();
    if (g > mx) {
      mx = g;
      if (widest) *widest = static_cast<int>(i);
    }
    sum += g;
  }
  if (mean) *mean = stitches_.empty() ? 0 : sum / stitches_.size();
  return mx;
}

// "panel 'name' vertex v at (x, y, z)" for a garment vertex.
std::string ClothSim::where(int v) const {
  const auto it = std::upper_bound(result_.panelOffset.begin(), result_.panelOffset.end(), v);
  const int p = static_cast<int>(it - result_.panelOffset.begin()) - 1;
  return fmt::format("panel '{}' vertex {} at ({:.3f}, {:.3f}, {:.3f})", names_[p],
                     v - result_.panelOffset[p], x_[v].x(), x_[v].y(), x_[v].z());
}

void ClothSim::run(Progress* progress, const std::string& label) {
  DrapeResult& r = result_;
  std::string why;
  bool ok = true;
  std::vector<Vector3d> good = x_;  // the last finite state, returned on failure
  auto doStep = [&] {
    ok = step(why);
    if (ok) good = x_;
    return ok;
  };

  // A start that is already a drape has its seams closed: sewn before the first step.
  if (o_.startsDraped) {
    sewClosedStitches();
    markNearOpenStitches();
    weldSewn();
  }

  // Phase 1: sew, gravity off, seams closing at most sewSpeed.
  gravity_.setZero();
  damping_ = o_.sewDamping;
  friction_ = o_.sewFriction;
  if (stitches_.empty()) {
    r.warnings.push_back(
        fmt::format("drape: the pattern has no stitches; the panels are draped unsewn"));
    r.seamsClosed = true;
  } else {
    if (progress)
      progress->begin(
          fmt::format("{}: sew {} stitch pairs ({} vertices)", label, stitches_.size(), nv_),
          o_.sewMaxSteps);
    int closedFor = -1, lastOpen = static_cast<int>(stitches_.size()), progressStep = 0;
    while (r.sewSteps < o_.sewMaxSteps) {
      ++r.sewSteps;
      if (progress) progress->update(r.sewSteps);
      if (!doStep()) break;
      const int open = sewClosedStitches();
      markNearOpenStitches();
      weldSewn();
      if (open < lastOpen) lastOpen = open, progressStep = r.sewSteps;
      if (open == 0) {
        if (++closedFor >= o_.sewSettleSteps) break;
      } else {
        closedFor = -1;
        // Stalled: the last few seams close under gravity (GarmentCode's schedule turns gravity
        // on after a fixed few frames). Not while the targets still close: stitches arrive
        // together, so none is sewn before the schedule ends.
        const bool scheduled = o_.sewSpeed * sewTime_ < maxStart_;
        if (!scheduled && r.sewSteps - progressStep >= o_.sewStallSteps) break;
      }
    }
  }

  r.maxSewStrain = peakStrain_;

  // Phase 2: drape under gravity until every vertex is slower than restSpeed for restSteps.
  if (ok) {
    gravity_ = o_.gravity;
    damping_ = o_.damping;
    friction_ = o_.friction;
    // Stitches keep closing at sewSpeed: a seam still open after the sewing budget does not snap.
    for (Vector3d& v : vel_) v.setZero();
    // At rest: every vertex's net motion over a window of restSteps steps is below restSpeed,
    // in two windows running. Over a window, not a step: a vertex held between two constraints
    // (a cloth stretched over the body's edge) trembles in place by a fraction of a millimetre
    // per step and never goes anywhere; a cloth that is still falling or swinging does.
    std::vector<Vector3d> windowStart = x_;
    const double window = std::max(1, o_.restSteps) * o_.timeStep;  // seconds
    int calm = 0;
    if (progress)
      progress->begin(fmt::format("{}: drape until at rest ({} vertices)", label, nv_),
                      o_.drapeMaxSteps);
    while (r.drapeSteps < o_.drapeMaxSteps) {
      ++r.drapeSteps;
      if (progress) progress->update(r.drapeSteps);
      if (!doStep()) break;
      sewClosedStitches();
      markNearOpenStitches();
      weldSewn();
      if (r.drapeSteps % std::max(1, o_.restSteps) != 0) continue;
      windowSpeed_ = 0;
      for (int v = 0; v < nv_; ++v) {
        const double speed = (x_[v] - windowStart[v]).norm() / window;
        if (speed > windowSpeed_) windowSpeed_ = speed, windowFastest_ = v;
      }
      windowStart = x_;
      r.restWindows.push_back({r.drapeSteps, windowSpeed_, where(windowFastest_)});
      calm = windowSpeed_ < o_.restSpeed ? calm + 1 : 0;
      if (calm >= 2 && r.drapeSteps >= o_.drapeMinSteps) {
        r.settled = true;
        break;
      }
    }
    if (ok && !r.settled)
      r.warnings.push_back(fmt::format(
          "drape: the cloth did not come to rest in the drape budget of {} steps ({} still "
          "moved at {:.3f} m/s over the last {} steps; at rest below {:.3f} m/s)",
          o_.drapeMaxSteps, where(windowFastest_), windowSpeed_, o_.restSteps, o_.restSpeed));
  }

  // The seams: every stitch sewn by the end of the run (stitches go on closing while draping).
  if (!stitches_.empty()) {
    int widest = 0, open = 0;
    const double gap = stitchGap(nullptr, &widest);
    for (char s : sewn_) open += !s;
    r.seamsClosed = ok && open == 0;
    if (ok && !r.seamsClosed)
      r.warnings.push_back(fmt::format(
          "drape: the seams did not close in {} sewing and {} drape steps ({} of {} stitch "
          "pairs open, the widest {:.1f} mm: {} to {})",
          r.sewSteps, r.drapeSteps, open, stitches_.size(), 1e3 * gap,
          where(stitches_[widest].first), where(stitches_[widest].second)));
  }

  // Outputs and figures.
  if (!ok) x_ = good;
  r.garment.V.resize(nv_, 3);
  for (int v = 0; v < nv_; ++v) r.garment.V.row(v) = x_[v].transpose();
  r.garment.F = F_;
  r.panels.clear();
  for (size_t p = 0; p + 1 < r.panelOffset.size(); ++p)
    r.panels.push_back(
        r.garment.V.middleRows(r.panelOffset[p], r.panelOffset[p + 1] - r.panelOffset[p]));
  r.maxStitchGap = stitchGap(&r.meanStitchGap);
  r.maxStrain = peakStrain_;
  for (char sewn : merged_) r.sewnStitches += sewn;
  // Penetrations with the exact distance where the grid says the vertex is near or inside.
  std::vector<double> depth(nv_, 0.0);
  tbb::parallel_for(tbb::blocked_range<int>(0, nv_, 256), [&](const tbb::blocked_range<int>& rr) {
    for (int v = rr.begin(); v < rr.end(); ++v) {
      if (!x_[v].allFinite() || sdf_->sample(x_[v]).distance > o_.bodyThickness) continue;
      depth[v] = std::max(0.0, -sdf_->exact(x_[v]).distance);
    }
  });
  for (double d : depth) {
    r.bodyPenetrations += d > 0;
    r.maxPenetration = std::max(r.maxPenetration, d);
  }
  if (r.garment.V.allFinite()) r.selfIntersections = countSelfIntersections(r.garment, weld_);
  r.constraintSolves = solves_;
  r.contactSearches = searches_;
  if (!ok) {
    r.status = DrapeStatus::Failed;
    r.failure = fmt::format("drape failed at step {} ({} sewing, {} draping): {}",
                            r.sewSteps + r.drapeSteps, r.sewSteps, r.drapeSteps, why);
    r.warnings.push_back(r.failure);
  } else {
    r.status = r.seamsClosed && r.settled ? DrapeStatus::Settled : DrapeStatus::NotSettled;
  }
  // GarmentCode's quality gates.
  if (ok && r.bodyPenetrations > 35)
    r.warnings.push_back(fmt::format(
        "drape: {} vertices inside the body (GarmentCode's gate: at most 35)", r.bodyPenetrations));
  if (ok && r.selfIntersections > 300)
    r.warnings.push_back(
        fmt::format("drape: {} self-intersecting triangle pairs (GarmentCode's gate: at most 300)",
                    r.selfIntersections));
}

void validate(const DrapeInput& in, const DrapeOptions& o) {
  if (in.panels.empty()) throw InputError("drape: the pattern has no panels");
  for (size_t p = 0; p < in.panels.size(); ++p) {
    const ClothPanel& panel = in.panels[p];
    const std::string name = fmt::format("drape: panel {} '{}'", p, panel.name);
    if (panel.numFaces() == 0 || panel.numVertices() < 3)
      throw InputError(name + " has no triangles");
    if (panel.start.rows() != panel.rest2d.rows())
      throw InputError(
          fmt::format("{}: {} flat vertices but {} placed ones; both must list the "
                      "same vertices in the same order",
                      name, panel.rest2d.rows(), panel.start.rows()));
    if (!panel.rest2d.allFinite() || !panel.start.allFinite())
      throw InputError(name + " has a non-finite (NaN or infinite) vertex coordinate");
    if (panel.F.minCoeff() < 0 || panel.F.maxCoeff() >= panel.numVertices())
      throw InputError(fmt::format("{}: a face refers to a vertex outside 0..{}", name,
                                   panel.numVertices() - 1));
  }
  for (size_t i = 0; i < in.stitches.size(); ++i) {
    const ClothStitch& s = in.stitches[i];
    const int np = static_cast<int>(in.panels.size());
    auto bad = [&](int panel, int vertex) {
      return panel < 0 || panel >= np || vertex < 0 || vertex >= in.panels[panel].numVertices();
    };
    if (bad(s.panelA, s.vertexA) || bad(s.panelB, s.vertexB))
      throw InputError(
          fmt::format("drape: stitch {} ({}:{} – {}:{}) refers to a panel or vertex "
                      "that does not exist",
                      i, s.panelA, s.vertexA, s.panelB, s.vertexB));
    if (s.panelA == s.panelB && s.vertexA == s.vertexB)
      throw InputError(fmt::format("drape: stitch {} sews vertex {} of panel {} to itself", i,
                                   s.vertexA, s.panelA));
  }
  auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  auto nonNegative = [](double v) { return std::isfinite(v) && v >= 0; };
  if (!positive(o.timeStep) || o.substeps < 1 || o.iterations < 1 || !positive(o.selfSkin) ||
      o.sewContactRings < 0)
    throw InputError(
        "drape: the time step and the self-collision skin must be positive, substeps and "
        "iterations at least 1, sewContactRings ≥ 0");
  if (!nonNegative(o.stretchCompliance) || !nonNegative(o.shearCompliance) ||
      !nonNegative(o.bendingCompliance) || !positive(o.density))
    throw InputError("drape: compliances must be ≥ 0 and the density > 0");
  if (!nonNegative(o.bodyThickness) || !nonNegative(o.selfThickness) || !nonNegative(o.friction) ||
      !nonNegative(o.sewFriction) || !nonNegative(o.damping) || !nonNegative(o.sewDamping) ||
      !positive(o.maxSpeed) || !positive(o.sewSpeed) || !positive(o.sewPull) ||
      !positive(o.sewTolerance) || !o.gravity.allFinite())
    throw InputError(
        "drape: thicknesses, friction, damping must be ≥ 0; speeds and the sewing "
        "tolerance > 0; gravity finite");
  if (o.sewMaxSteps < 0 || o.drapeMaxSteps < 0 || o.sewStallSteps < 1)
    throw InputError("drape: step budgets must be ≥ 0, sewStallSteps ≥ 1");
  if (!(o.strainLimit == 0 || o.strainLimit >= 1) || o.strainLimitPasses < 0)
    throw InputError(
        "drape: the strain limit must be 0 (off) or at least 1 (× the pattern length), its "
        "passes ≥ 0");
}

}  // namespace

DrapeResult runDrape(const DrapeInput& input, const DrapeOptions& options, Progress* progress,
                     const std::string& label) {
  const auto t0 = std::chrono::steady_clock::now();
  validate(input, options);
  validateMesh(input.body, "drape body");
  DrapeResult result;
  ClothSim sim(input, options, result);
  sim.run(progress, label);
  if (progress) progress->end();
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  result.constraintSolvesPerSecond =
      result.seconds > 0 ? static_cast<double>(result.constraintSolves) / result.seconds : 0;
  return result;
}

}  // namespace s2p
