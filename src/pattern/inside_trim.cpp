#include "pattern/inside_trim.h"

#include <fmt/format.h>

#include <algorithm>
#include <queue>
#include <vector>

#include "core/error.h"
#include "core/mesh_query.h"
#include "core/mesh_topology.h"
#include "core/shapes.h"

namespace s2p {

std::optional<InsideTrim> trimInsideSeenThroughOpenings(const TriMesh& garment,
                                                        const Eigen::VectorXi& faceOrigin,
                                                        const TriMesh& body,
                                                        const InsideTrimOptions& options) {
  const int nF = garment.numFaces();
  if (body.numFaces() == 0) throw InputError("inside trim: the body has no faces");
  if (faceOrigin.size() != nF)
    throw InputError(
        fmt::format("inside trim: {} face origins for {} faces", faceOrigin.size(), nF));
  if (nF == 0) return std::nullopt;
  const Eigen::MatrixX3d normals = faceNormals(garment);
  const Eigen::VectorXd areas = faceAreas(garment);
  const Eigen::MatrixX3d bodyNormals = faceNormals(body);
  Eigen::MatrixX3d centroids(nF, 3);
  for (int f = 0; f < nF; ++f)
    centroids.row(f) = (garment.V.row(garment.F(f, 0)) + garment.V.row(garment.F(f, 1)) +
                        garment.V.row(garment.F(f, 2))) /
                       3.0;
  const std::vector<ClosestHit> hits = MeshQuery(body).closestPoints(centroids);
  std::vector<bool> facing(static_cast<size_t>(nF));
  for (int f = 0; f < nF; ++f)
    facing[static_cast<size_t>(f)] =
        normals.row(f).dot(bodyNormals.row(hits[static_cast<size_t>(f)].face)) < -options.facingCos;

  // Flood from the border over faces turned to the body.
  const MeshTopology topo(garment.F, garment.numVertices());
  std::vector<bool> inside(static_cast<size_t>(nF), false);
  std::queue<int> queue;
  for (int e = 0; e < topo.numEdges(); ++e) {
    if (!topo.isBoundaryEdge(e)) continue;
    const int f = topo.edgeFaces(e)[0];
    if (facing[static_cast<size_t>(f)] && !inside[static_cast<size_t>(f)]) {
      inside[static_cast<size_t>(f)] = true;
      queue.push(f);
    }
  }
  while (!queue.empty()) {
    const int f = queue.front();
    queue.pop();
    for (int k = 0; k < 3; ++k)
      for (const int g : topo.edgeFaces(topo.faceEdges()(f, k)))
        if (facing[static_cast<size_t>(g)] && !inside[static_cast<size_t>(g)]) {
          inside[static_cast<size_t>(g)] = true;
          queue.push(g);
        }
  }
  double insideArea = 0;
  for (int f = 0; f < nF; ++f)
    if (inside[static_cast<size_t>(f)]) insideArea += areas[f];
  if (insideArea < options.minArea) return std::nullopt;

  // The rest, its largest piece. Where the trimmed border passes through a vertex twice (a bow
  // tie), the faces at that vertex go too, and the largest piece is taken again.
  std::vector<bool> keep(static_cast<size_t>(nF));
  for (int f = 0; f < nF; ++f) keep[static_cast<size_t>(f)] = !inside[static_cast<size_t>(f)];
  constexpr int kRounds = 5;
  for (int round = 0;; ++round) {
    std::vector<int> kept;
    for (int f = 0; f < nF; ++f)
      if (keep[static_cast<size_t>(f)]) kept.push_back(f);
    if (kept.empty()) return std::nullopt;
    Eigen::MatrixX3i F(static_cast<int>(kept.size()), 3);
    for (size_t i = 0; i < kept.size(); ++i) F.row(static_cast<int>(i)) = garment.F.row(kept[i]);
    const MeshTopology rest(F, garment.numVertices());
    std::vector<double> pieceArea(static_cast<size_t>(rest.numComponents()), 0.0);
    for (size_t i = 0; i < kept.size(); ++i)
      pieceArea[static_cast<size_t>(rest.faceComponent()[static_cast<int>(i)])] += areas[kept[i]];
    const auto largest =
        static_cast<int>(std::max_element(pieceArea.begin(), pieceArea.end()) - pieceArea.begin());
    for (size_t i = 0; i < kept.size(); ++i)
      if (rest.faceComponent()[static_cast<int>(i)] != largest)
        keep[static_cast<size_t>(kept[i])] = false;
    const std::vector<int>& bowTies = rest.manifoldness().nonManifoldVertices;
    if (bowTies.empty() && rest.manifoldness().nonManifoldEdges.empty()) break;
    if (round + 1 == kRounds) return std::nullopt;
    std::vector<bool> bad(static_cast<size_t>(garment.numVertices()), false);
    for (const int v : bowTies) bad[static_cast<size_t>(v)] = true;
    for (const int f : kept)
      for (int k = 0; k < 3; ++k)
        if (bad[static_cast<size_t>(garment.F(f, k))]) keep[static_cast<size_t>(f)] = false;
  }
  InsideTrim out;
  std::vector<int> final;
  for (int f = 0; f < nF; ++f)
    if (keep[static_cast<size_t>(f)]) final.push_back(f);
  out.mesh.V = garment.V;
  out.mesh.F.resize(static_cast<int>(final.size()), 3);
  out.faceOrigin.resize(static_cast<int>(final.size()));
  for (size_t i = 0; i < final.size(); ++i) {
    out.mesh.F.row(static_cast<int>(i)) = garment.F.row(final[i]);
    out.faceOrigin[static_cast<int>(i)] = faceOrigin[final[i]];
  }
  removeUnreferencedVertices(out.mesh);
  out.removedFaces = nF - static_cast<int>(final.size());
  out.removedArea = areas.sum() - faceAreas(out.mesh).sum();
  return out;
}

}  // namespace s2p
