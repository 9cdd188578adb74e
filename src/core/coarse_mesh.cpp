#include "core/coarse_mesh.h"

#include <meshoptimizer.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/mesh_query.h"
#include "core/shapes.h"

namespace s2p {

namespace {

// meshoptimizer stops at this error relative to the mesh's extent even before the target count:
// 1e-3 of a person's 1.8 m is 2 mm, more than a collapse from 1M to 100k vertices needs on a
// scan's smooth surface, so in practice the count decides.
constexpr float kMaxRelativeError = 1e-3f;

// Faces of a worse shape than this (faceQuality) are dropped from the copy: a collapse can leave
// needles and caps (area 1e-15 m² beside a mean of 1e-5 at 1M → 100k) whose cotangents reach
// 1e8, and the biharmonic's L M⁻¹ L, which squares them, is then not numerically positive
// definite. At 1M → 100k about 1 % of the faces, each leaving a pinhole.
constexpr double kMinFaceQuality = 0.01;

// 4√3·area / Σ edge²: 1 for an equilateral triangle, 0 for a degenerate one.
double faceQuality(const TriMesh& mesh, int f) {
  const Eigen::Vector3d a = mesh.V.row(mesh.F(f, 0)), b = mesh.V.row(mesh.F(f, 1)),
                        c = mesh.V.row(mesh.F(f, 2));
  const double edges = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  return edges > 0 ? 2 * std::sqrt(3.0) * (b - a).cross(c - a).norm() / edges : 0.0;
}

// Edge k of face f (corner k to corner k + 1) as one number.
std::uint64_t directedEdge(const TriMesh& mesh, int f, int k) {
  return static_cast<std::uint64_t>(mesh.F(f, k)) << 32 |
         static_cast<std::uint32_t>(mesh.F(f, (k + 1) % 3));
}

// meshoptimizer's collapses do not check the link condition: they can fold two faces onto each
// other (the same three vertices twice) or leave an edge used twice in the same direction (a
// fold, or two sheets touching). Such faces are dropped, with slivers, until every
// edge is used at most once in each direction (manifold and consistently oriented, as the
// isolines need); they leave pinholes where the copy is only carried from. Returns the number
// of faces dropped.
int dropFolds(TriMesh& mesh) {
  std::vector<bool> keep(mesh.numFaces());
  for (int f = 0; f < mesh.numFaces(); ++f) keep[f] = faceQuality(mesh, f) >= kMinFaceQuality;
  // Faces sharing a key (their sorted corners: a fin; a directed edge: a fold) are dropped.
  const auto dropRepeated = [&keep](auto& keyFace) {
    std::sort(keyFace.begin(), keyFace.end());
    bool any = false;
    for (size_t i = 0; i + 1 < keyFace.size(); ++i)
      if (keyFace[i].first == keyFace[i + 1].first) {
        keep[keyFace[i].second] = keep[keyFace[i + 1].second] = false;
        any = true;
      }
    return any;
  };
  std::vector<std::pair<std::array<int, 3>, int>> corners(mesh.numFaces());
  for (int f = 0; f < mesh.numFaces(); ++f) {
    corners[f] = {{mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)}, f};
    std::sort(corners[f].first.begin(), corners[f].first.end());
  }
  dropRepeated(corners);
  std::vector<std::pair<std::uint64_t, int>> edges;
  for (int round = 0; round < 4; ++round) {  // dropping a fold may expose none: a round or two
    edges.clear();
    for (int f = 0; f < mesh.numFaces(); ++f)
      if (keep[f])
        for (int k = 0; k < 3; ++k) edges.emplace_back(directedEdge(mesh, f, k), f);
    if (!dropRepeated(edges)) break;
  }
  std::vector<int> kept;
  for (int f = 0; f < mesh.numFaces(); ++f)
    if (keep[f]) kept.push_back(f);
  Eigen::MatrixX3i F(static_cast<int>(kept.size()), 3);
  for (size_t i = 0; i < kept.size(); ++i) F.row(static_cast<int>(i)) = mesh.F.row(kept[i]);
  const int dropped = mesh.numFaces() - static_cast<int>(kept.size());
  mesh.F = std::move(F);
  return dropped;
}

// True when every edge of `mesh` is used at most once in each direction.
bool manifoldAndOriented(const TriMesh& mesh) {
  std::vector<std::uint64_t> directed;
  directed.reserve(3 * static_cast<size_t>(mesh.numFaces()));
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) directed.push_back(directedEdge(mesh, f, k));
  std::sort(directed.begin(), directed.end());
  return std::adjacent_find(directed.begin(), directed.end()) == directed.end();
}

std::optional<CoarseMesh> simplifyOnce(const TriMesh& fine, const std::vector<float>& pos,
                                       const std::vector<unsigned>& idx, size_t targetIndices) {
  std::vector<unsigned> out(idx.size());
  const size_t n = meshopt_simplify(out.data(), idx.data(), idx.size(), pos.data(),
                                    static_cast<size_t>(fine.numVertices()), 3 * sizeof(float),
                                    targetIndices, kMaxRelativeError, 0, nullptr);
  CoarseMesh c;
  c.mesh.V = fine.V;
  c.mesh.F.resize(static_cast<int>(n / 3), 3);
  for (size_t i = 0; i < n; ++i)
    c.mesh.F(static_cast<int>(i / 3), static_cast<int>(i % 3)) = static_cast<int>(out[i]);
  // A few folds and slivers are dropped (0.2 % of the faces on an icosphere decimated
  // eightfold, about 1 % on a 1M scan decimated tenfold); many mean the copy is not the scan's
  // surface any more.
  const int dropped = dropFolds(c.mesh);
  if (50 * dropped > c.mesh.numFaces() + dropped || !manifoldAndOriented(c.mesh))
    return std::nullopt;
  c.fineVertex = removeUnreferencedVertices(c.mesh);
  return c;
}

}  // namespace

std::optional<CoarseMesh> decimatedCopy(const TriMesh& fine, int targetVertices) {
  if (targetVertices < 1000)
    throw InputError("coarse copy: a target of " + std::to_string(targetVertices) +
                     " vertices is too few for a person (at least 1000)");
  const int nV = fine.numVertices();
  if (static_cast<double>(nV) <= 1.5 * targetVertices) return std::nullopt;
  std::vector<float> pos(3 * static_cast<size_t>(nV));
  for (int v = 0; v < nV; ++v)
    for (int k = 0; k < 3; ++k) pos[3 * v + k] = static_cast<float>(fine.V(v, k));
  std::vector<unsigned> idx(3 * static_cast<size_t>(fine.numFaces()));
  for (int f = 0; f < fine.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) idx[3 * f + k] = static_cast<unsigned>(fine.F(f, k));
  // A closed surface has about two faces per vertex; a second, gentler attempt when the first
  // leaves a fold.
  size_t targetIndices = 6 * static_cast<size_t>(targetVertices);
  for (int attempt = 0; attempt < 2; ++attempt, targetIndices = targetIndices * 3 / 2)
    if (std::optional<CoarseMesh> c = simplifyOnce(fine, pos, idx, targetIndices)) return c;
  return std::nullopt;
}

CoarseToFine::CoarseToFine(const TriMesh& coarse, const TriMesh& fine) {
  const MeshQuery query(coarse);
  const std::vector<ClosestHit> hits = query.closestPoints(fine.V);
  const int n = fine.numVertices();
  corner_.resize(n, 3);
  weight_.resize(n, 3);
  distance_.resize(n);
  for (int v = 0; v < n; ++v) {
    corner_.row(v) = coarse.F.row(hits[v].face);
    weight_.row(v) = hits[v].bary.transpose();
    distance_[v] = hits[v].distance;
  }
}

Eigen::VectorXd CoarseToFine::carry(const Eigen::VectorXd& coarseField) const {
  Eigen::VectorXd out(corner_.rows());
  for (int v = 0; v < corner_.rows(); ++v)
    out[v] = weight_(v, 0) * coarseField[corner_(v, 0)] +
             weight_(v, 1) * coarseField[corner_(v, 1)] +
             weight_(v, 2) * coarseField[corner_(v, 2)];
  return out;
}

}  // namespace s2p
