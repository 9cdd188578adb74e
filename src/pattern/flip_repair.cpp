#include "pattern/flip_repair.h"

#include <Eigen/SparseLU>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace s2p {

double signedFaceArea(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& F, int f) {
  const Eigen::Vector2d a = uv.row(F(f, 0)).transpose();
  const Eigen::Vector2d b = uv.row(F(f, 1)).transpose() - a;
  const Eigen::Vector2d c = uv.row(F(f, 2)).transpose() - a;
  return 0.5 * (b.x() * c.y() - b.y() * c.x());
}

int countInvertedFaces(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& F) {
  int count = 0;
  for (int f = 0; f < F.rows(); ++f)
    if (!(signedFaceArea(uv, F, f) > 0.0)) ++count;
  return count;
}

namespace {

// n·x ≥ c.
struct HalfPlane {
  Eigen::Vector2d n;
  double c;
};

bool satisfies(const HalfPlane& h, const Eigen::Vector2d& x) {
  const double lhs = h.n.dot(x);
  return lhs - h.c >= -1e-12 * (std::abs(lhs) + std::abs(h.c));
}

// The point closest to p where every half-plane holds, or none when they have no common point.
// The minimiser of |x − p|² over a convex polygon is p itself, p's projection on one edge's
// line, or a vertex (two lines' intersection): every candidate is tried.
std::optional<Eigen::Vector2d> closestFeasible(const Eigen::Vector2d& p,
                                               const std::vector<HalfPlane>& planes) {
  std::optional<Eigen::Vector2d> best;
  double bestDistance = 0.0;
  const auto consider = [&](const Eigen::Vector2d& x) {
    const double d = (x - p).squaredNorm();
    if (best && d >= bestDistance) return;
    for (const HalfPlane& h : planes)
      if (!satisfies(h, x)) return;
    best = x;
    bestDistance = d;
  };
  consider(p);
  if (best) return best;
  for (size_t i = 0; i < planes.size(); ++i) {
    const HalfPlane& h = planes[i];
    const double nn = h.n.squaredNorm();
    if (nn > 0.0) consider(p + ((h.c - h.n.dot(p)) / nn) * h.n);
    for (size_t j = i + 1; j < planes.size(); ++j) {
      // Cramer's rule for n_i·x = c_i, n_j·x = c_j.
      const Eigen::Vector2d& a = h.n;
      const Eigen::Vector2d& b = planes[j].n;
      const double det = a.x() * b.y() - a.y() * b.x();
      if (std::abs(det) <= 1e-14 * a.squaredNorm() * b.squaredNorm()) continue;
      consider(Eigen::Vector2d(h.c * b.y() - planes[j].c * a.y(),
                               a.x() * planes[j].c - b.x() * h.c) /
               det);
    }
  }
  return best;
}

struct Adjacency {
  std::vector<std::vector<int>> faces;       // per vertex, its faces
  std::vector<std::vector<int>> neighbours;  // per vertex, the vertices it shares an edge with
};

Adjacency adjacencyOf(const Eigen::MatrixX3i& F, int nV) {
  Adjacency adj;
  adj.faces.resize(nV);
  adj.neighbours.resize(nV);
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      adj.faces[F(f, k)].push_back(f);
      adj.neighbours[F(f, k)].push_back(F(f, (k + 1) % 3));
      adj.neighbours[F(f, k)].push_back(F(f, (k + 2) % 3));
    }
  for (std::vector<int>& n : adj.neighbours) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
  }
  return adj;
}

class FlipRepairer {
 public:
  FlipRepairer(Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& F, const Eigen::VectorXd& area3d,
               const FlipRepairOptions& options)
      : uv_(uv),
        F_(F),
        options_(options),
        adj_(adjacencyOf(F, static_cast<int>(uv.rows()))),
        outlineNeighbours_(outlineNeighboursOf(F, static_cast<int>(uv.rows()))),
        moved_(uv.rows(), 0) {
    // Each face's margin: its 3D area (floored at 1 % of the mean face) at the panel's own
    // 2D/3D scale, times areaMargin.
    const int nF = static_cast<int>(F.rows());
    double total2d = 0.0, total3d = 0.0;
    for (int f = 0; f < nF; ++f) total2d += signedFaceArea(uv, F, f);
    total3d = area3d.sum();
    const double scale = total3d > 0.0 && total2d > 0.0 ? total2d / total3d : 1.0;
    const double floor = nF > 0 ? 0.01 * total3d / nF : 0.0;
    margin_.resize(nF);
    for (int f = 0; f < nF; ++f)
      margin_[f] = options.areaMargin * scale * std::max(area3d(f), floor);
  }

  FlipRepairResult run() {
    FlipRepairResult result;
    result.invertedBefore = countInvertedFaces(uv_, F_);
    int inverted = result.invertedBefore;
    for (int ring = 0; inverted > 0 && ring <= options_.maxRings; ++ring) {
      if (ring > 0) smoothAround(ring);
      for (int pass = 0; inverted > 0 && pass < options_.maxPasses; ++pass) {
        if (movePass() == 0) break;
        inverted = countInvertedFaces(uv_, F_);
      }
      inverted = countInvertedFaces(uv_, F_);
    }
    result.invertedAfter = inverted;
    result.verticesMoved = static_cast<int>(std::count(moved_.begin(), moved_.end(), 1));
    return result;
  }

 private:
  bool invertedFace(int f) const { return !(signedFaceArea(uv_, F_, f) > 0.0); }

  std::vector<int> verticesOfInvertedFaces() const {
    std::vector<int> vs;
    for (int f = 0; f < F_.rows(); ++f)
      if (invertedFace(f))
        for (int k = 0; k < 3; ++k) vs.push_back(F_(f, k));
    std::sort(vs.begin(), vs.end());
    vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
    return vs;
  }

  // 2·area(v, a, b) = a×b + v×(a − b) ≥ 2·margin, for each face (v, a, b) around v.
  std::vector<HalfPlane> kernelOf(int v, double marginFactor) const {
    std::vector<HalfPlane> planes;
    for (int f : adj_.faces[v]) {
      int k = 0;
      while (F_(f, k) != v) ++k;
      const Eigen::Vector2d a = uv_.row(F_(f, (k + 1) % 3)).transpose();
      const Eigen::Vector2d b = uv_.row(F_(f, (k + 2) % 3)).transpose();
      const Eigen::Vector2d w = a - b;
      const double aCrossB = a.x() * b.y() - a.y() * b.x();
      planes.push_back({Eigen::Vector2d(w.y(), -w.x()), 2.0 * marginFactor * margin_[f] - aCrossB});
    }
    return planes;
  }

  // Every vertex of an inverted face to the closest point of its kernel (the full margin, or a
  // thousandth of it where the full one leaves no room). Returns how many moved.
  int movePass() {
    int count = 0;
    for (int v : verticesOfInvertedFaces()) {
      bool stillInverted = false;
      for (int f : adj_.faces[v]) stillInverted |= invertedFace(f);
      if (!stillInverted) continue;
      for (double factor : {1.0, 1e-3}) {
        const std::optional<Eigen::Vector2d> x =
            closestFeasible(uv_.row(v).transpose(), kernelOf(v, factor));
        if (!x) continue;
        uv_.row(v) = x->transpose();
        mark(v);
        ++count;
        break;
      }
    }
    return count;
  }

  // Where every vertex of a fold has an empty kernel, the fold is opened by Tutte's embedding
  // of the patch within `rings` rings of it: each inner vertex of the patch at the mean of its
  // neighbours, the ring around the patch held. The panel's own boundary vertices are held
  // first (the mean of a boundary vertex's neighbours lies inside and would pull the outline
  // in); a fold on the outline itself is opened with them free, each at the mean of its two
  // neighbours along the outline (the outline straightened locally). A convex patch rim gives a
  // flip-free patch (Tutte 1963); a result that does not lower the count of inverted faces is
  // undone.
  void smoothAround(int rings) {
    const std::vector<int> patch = patchAround(rings);
    for (const bool freeOutline : {false, true})
      if (tutteOn(patch, freeOutline)) return;
  }

  std::vector<int> patchAround(int rings) const {
    std::vector<char> inPatch(uv_.rows(), 0);
    std::vector<int> patch = verticesOfInvertedFaces(), frontier = patch;
    for (int v : patch) inPatch[v] = 1;
    for (int r = 0; r < rings; ++r) {
      std::vector<int> next;
      for (int v : frontier)
        for (int u : adj_.neighbours[v])
          if (!inPatch[u]) {
            inPatch[u] = 1;
            next.push_back(u);
          }
      patch.insert(patch.end(), next.begin(), next.end());
      frontier = std::move(next);
    }
    return patch;
  }

  bool tutteOn(const std::vector<int>& patch, bool freeOutline) {
    const int nV = static_cast<int>(uv_.rows());
    std::vector<int> freeVertex, index(nV, -1);
    for (int v : patch)
      if (freeOutline || outlineNeighbours_[v].empty()) {
        index[v] = static_cast<int>(freeVertex.size());
        freeVertex.push_back(v);
      }
    if (freeVertex.empty()) return false;
    const int n = static_cast<int>(freeVertex.size());
    std::vector<Eigen::Triplet<double>> triplets;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 2);
    for (int i = 0; i < n; ++i) {
      const int v = freeVertex[i];
      const std::vector<int>& around =
          outlineNeighbours_[v].empty() ? adj_.neighbours[v] : outlineNeighbours_[v];
      triplets.emplace_back(i, i, static_cast<double>(around.size()));
      for (int u : around) {
        if (index[u] < 0)
          rhs.row(i) += uv_.row(u);
        else
          triplets.emplace_back(i, index[u], -1.0);
      }
    }
    // Not symmetric once outline rows are in (they see two neighbours only): LU.
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(triplets.begin(), triplets.end());
    Eigen::SparseLU<Eigen::SparseMatrix<double>> solver;
    solver.compute(A);
    if (solver.info() != Eigen::Success) return false;
    const Eigen::MatrixXd x = solver.solve(rhs);
    if (solver.info() != Eigen::Success || !x.allFinite()) return false;
    const Eigen::MatrixX2d before = uv_;
    const int invertedBefore = countInvertedFaces(uv_, F_);
    for (int i = 0; i < n; ++i) uv_.row(freeVertex[i]) = x.row(i);
    if (countInvertedFaces(uv_, F_) >= invertedBefore) {
      uv_ = before;
      return false;
    }
    for (int v : freeVertex) mark(v);
    return true;
  }

  // Per vertex, its neighbours along the panel's outline (edges used by one face); empty for
  // inner vertices.
  static std::vector<std::vector<int>> outlineNeighboursOf(const Eigen::MatrixX3i& F, int nV) {
    std::vector<std::pair<int, int>> edges;
    for (int f = 0; f < F.rows(); ++f)
      for (int k = 0; k < 3; ++k) edges.push_back(std::minmax(F(f, k), F(f, (k + 1) % 3)));
    std::sort(edges.begin(), edges.end());
    std::vector<std::vector<int>> out(nV);
    for (size_t i = 0; i < edges.size(); ++i) {
      const bool single = (i == 0 || edges[i - 1] != edges[i]) &&
                          (i + 1 == edges.size() || edges[i + 1] != edges[i]);
      if (!single) continue;
      out[edges[i].first].push_back(edges[i].second);
      out[edges[i].second].push_back(edges[i].first);
    }
    return out;
  }

  void mark(int v) { moved_[v] = 1; }

  Eigen::MatrixX2d& uv_;
  const Eigen::MatrixX3i& F_;
  FlipRepairOptions options_;
  Adjacency adj_;
  std::vector<double> margin_;
  std::vector<std::vector<int>> outlineNeighbours_;
  std::vector<char> moved_;
};

}  // namespace

FlipRepairResult repairFlips(Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& F,
                             const Eigen::VectorXd& area3d, const FlipRepairOptions& options) {
  if (F.rows() == 0 || countInvertedFaces(uv, F) == 0) return {};
  return FlipRepairer(uv, F, area3d, options).run();
}

}  // namespace s2p
