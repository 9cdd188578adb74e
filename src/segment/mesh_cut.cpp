#include "segment/mesh_cut.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace s2p {

namespace {

// Builds one part incrementally: original vertices and edge vertices are created on first use.
class PartBuilder {
 public:
  PartBuilder(const TriMesh& mesh, int numEdges)
      : mesh_(mesh), vertexId_(mesh.numVertices(), -1), edgeId_(numEdges, -1) {}

  int original(int v) {
    if (vertexId_[v] < 0) {
      vertexId_[v] = static_cast<int>(origin_.size());
      origin_.push_back({v, v, 0.0});
    }
    return vertexId_[v];
  }
  int onEdge(const IsolinePoint& p, int a, int b) {
    if (edgeId_[p.edge] < 0) {
      edgeId_[p.edge] = static_cast<int>(origin_.size());
      origin_.push_back({a, b, p.t});
    }
    return edgeId_[p.edge];
  }
  void face(int a, int b, int c, int originalFace) {
    faces_.push_back({a, b, c});
    faceOrigin_.push_back(originalFace);
  }
  CutPart finish() const {
    CutPart part;
    part.vertexOrigin = origin_;
    part.mesh.V.resize(static_cast<int>(origin_.size()), 3);
    for (size_t i = 0; i < origin_.size(); ++i) {
      const VertexOrigin& o = origin_[i];
      part.mesh.V.row(static_cast<int>(i)) = (1 - o.t) * mesh_.V.row(o.a) + o.t * mesh_.V.row(o.b);
    }
    part.mesh.F.resize(static_cast<int>(faces_.size()), 3);
    part.faceOrigin.resize(static_cast<int>(faces_.size()));
    for (size_t i = 0; i < faces_.size(); ++i) {
      part.mesh.F.row(static_cast<int>(i)) << faces_[i][0], faces_[i][1], faces_[i][2];
      part.faceOrigin[static_cast<int>(i)] = faceOrigin_[i];
    }
    return part;
  }

 private:
  const TriMesh& mesh_;
  std::vector<int> vertexId_, edgeId_;
  std::vector<VertexOrigin> origin_;
  std::vector<std::array<int, 3>> faces_;
  std::vector<int> faceOrigin_;
};

}  // namespace

CutResult cutAlongIsoline(const TriMesh& mesh, const Eigen::VectorXd& phi) {
  const MeshTopology topology(mesh.F, mesh.numVertices());
  return cutAlongIsoline(mesh, topology, phi);
}

CutResult cutAlongIsoline(const TriMesh& mesh, const MeshTopology& topology,
                          const Eigen::VectorXd& phi) {
  CutResult result;
  result.isoline = extractIsoline(mesh, topology, phi, 0.0);  // validates phi and orientation
  const int nE = topology.numEdges();
  std::vector<const IsolinePoint*> edgePoint(nE, nullptr);
  for (const auto& c : result.isoline.curves)
    for (const auto& p : c.points) edgePoint[p.edge] = &p;

  PartBuilder neg(mesh, nE), pos(mesh, nE);
  const Eigen::MatrixX3i& FE = topology.faceEdges();
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const std::array<int, 3> v = {mesh.F(f, 0), mesh.F(f, 1), mesh.F(f, 2)};
    const std::array<bool, 3> s = {phi[v[0]] >= 0, phi[v[1]] >= 0, phi[v[2]] >= 0};
    if (s[0] == s[1] && s[1] == s[2]) {
      PartBuilder& part = s[0] ? pos : neg;
      part.face(part.original(v[0]), part.original(v[1]), part.original(v[2]), f);
      continue;
    }
    const int k = (s[0] != s[1] && s[0] != s[2]) ? 0 : (s[1] != s[0] && s[1] != s[2]) ? 1 : 2;
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    const IsolinePoint& pNext = *edgePoint[FE(f, k2)];  // on edge (k, k+1)
    const IsolinePoint& pPrev = *edgePoint[FE(f, k1)];  // on edge (k+2, k)
    const auto edgeEnds = [&](const IsolinePoint& p) {
      return std::array<int, 2>{topology.edges()(p.edge, 0), topology.edges()(p.edge, 1)};
    };
    PartBuilder& lone = s[k] ? pos : neg;
    PartBuilder& other = s[k] ? neg : pos;
    const auto [na, nb] = edgeEnds(pNext);
    const auto [pa, pb] = edgeEnds(pPrev);
    // Lone side: (k, p, q).
    lone.face(lone.original(v[k]), lone.onEdge(pNext, na, nb), lone.onEdge(pPrev, pa, pb), f);
    // Other side: quad (p, k+1, k+2, q), split along its shorter diagonal.
    const int p = other.onEdge(pNext, na, nb), q = other.onEdge(pPrev, pa, pb);
    const int b = other.original(v[k1]), c = other.original(v[k2]);
    const double dPc = (pNext.position - mesh.V.row(v[k2]).transpose()).norm();
    const double dQb = (pPrev.position - mesh.V.row(v[k1]).transpose()).norm();
    if (dPc <= dQb) {
      other.face(p, b, c, f);
      other.face(p, c, q, f);
    } else {
      other.face(p, b, q, f);
      other.face(b, c, q, f);
    }
  }
  result.negative = neg.finish();
  result.positive = pos.finish();
  return result;
}

Eigen::VectorXd awayFromZero(Eigen::VectorXd phi, const TriMesh& mesh) {
  const double eps = 1e-4 * meanEdgeLength(mesh);
  for (int v = 0; v < phi.size(); ++v)
    if (std::abs(phi[v]) < eps) phi[v] = phi[v] < 0 ? -eps : eps;
  return phi;
}

RefinedMesh refineAlongIsoline(const TriMesh& mesh, const MeshTopology& topology,
                               const Eigen::VectorXd& phi) {
  const CutResult cut = cutAlongIsoline(mesh, topology, phi);
  RefinedMesh out;
  // A vertex is known by its origin: an original vertex, or the one crossing of a crossed edge,
  // which both sides created from the same (a, b, t): the two sides join exactly.
  std::unordered_map<std::int64_t, int> id;
  const std::int64_t n = mesh.numVertices();
  const auto vertexOf = [&](const VertexOrigin& o) {
    const auto [it, added] = id.try_emplace(o.a * n + o.b, static_cast<int>(out.vertexOrigin.size()));
    if (added) out.vertexOrigin.push_back(o);
    return it->second;
  };
  const int nF = cut.negative.mesh.numFaces() + cut.positive.mesh.numFaces();
  out.mesh.F.resize(nF, 3);
  out.faceOrigin.resize(nF);
  out.faceSide.resize(nF);
  int f = 0;
  for (const CutPart* part : {&cut.negative, &cut.positive}) {
    for (int g = 0; g < part->mesh.numFaces(); ++g, ++f) {
      for (int k = 0; k < 3; ++k) out.mesh.F(f, k) = vertexOf(part->vertexOrigin[part->mesh.F(g, k)]);
      out.faceOrigin[f] = part->faceOrigin[g];
      out.faceSide[f] = part == &cut.positive ? 1 : 0;
    }
  }
  out.mesh.V.resize(static_cast<int>(out.vertexOrigin.size()), 3);
  for (size_t i = 0; i < out.vertexOrigin.size(); ++i) {
    const VertexOrigin& o = out.vertexOrigin[i];
    out.mesh.V.row(static_cast<int>(i)) = (1 - o.t) * mesh.V.row(o.a) + o.t * mesh.V.row(o.b);
  }
  return out;
}

Eigen::VectorXd carryToVertices(const std::vector<VertexOrigin>& origin,
                                const Eigen::VectorXd& values) {
  Eigen::VectorXd out(static_cast<int>(origin.size()));
  for (size_t i = 0; i < origin.size(); ++i) {
    const VertexOrigin& o = origin[i];
    out[static_cast<int>(i)] = (1 - o.t) * values[o.a] + o.t * values[o.b];
  }
  return out;
}

}  // namespace s2p
