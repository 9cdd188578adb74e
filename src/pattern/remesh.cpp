#include "pattern/remesh.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

#include "core/error.h"
#include "pattern/flatten_metrics.h"

namespace s2p {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Delaunay_mesh_vertex_base_2<Kernel>;
using Fb = CGAL::Delaunay_mesh_face_base_2<Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Kernel, Tds>;
using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;
using VertexHandle = Cdt::Vertex_handle;
using Point = Cdt::Point;

constexpr double kMaxAngleDeg = 20.705;  // asin(√0.125)

double degrees(double radians) {
  return radians * 180.0 / std::numbers::pi;
}

// The constrained neighbour of v along which the boundary continues towards `towards`: the
// one (≠ previous) most aligned with the direction to `towards`.
VertexHandle nextOnConstraint(const Cdt& cdt, VertexHandle v, VertexHandle previous,
                              const Point& towards) {
  VertexHandle best;
  double bestDot = -std::numeric_limits<double>::infinity();
  const double dx = towards.x() - v->point().x(), dy = towards.y() - v->point().y();
  Cdt::Edge_circulator e = cdt.incident_edges(v), done = e;
  do {
    if (!cdt.is_infinite(e) && cdt.is_constrained(*e)) {
      const Cdt::Face_handle f = e->first;
      const int i = e->second;
      VertexHandle a = f->vertex(Cdt::cw(i)), b = f->vertex(Cdt::ccw(i));
      const VertexHandle w = a == v ? b : a;
      if (w != previous) {
        const double wx = w->point().x() - v->point().x(), wy = w->point().y() - v->point().y();
        const double dot = (wx * dx + wy * dy) / std::max(std::hypot(wx, wy), 1e-300);
        if (dot > bestDot) bestDot = dot, best = w;
      }
    }
  } while (++e != done);
  return best;
}

// Smallest angle (degrees) of face f.
double faceMinAngleDeg(const Eigen::MatrixX2d& V, const Eigen::MatrixX3i& F, int f) {
  double worst = 180.0;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector2d p = V.row(F(f, k)).transpose();
    const Eigen::Vector2d a = V.row(F(f, (k + 1) % 3)).transpose() - p;
    const Eigen::Vector2d b = V.row(F(f, (k + 2) % 3)).transpose() - p;
    worst = std::min(worst, degrees(std::atan2(std::abs(a.x() * b.y() - a.y() * b.x()), a.dot(b))));
  }
  return worst;
}

}  // namespace

double minimumAngleDeg(const Eigen::MatrixX2d& V, const Eigen::MatrixX3i& F) {
  double worst = 180.0;
  for (int f = 0; f < F.rows(); ++f) worst = std::min(worst, faceMinAngleDeg(V, F, f));
  return F.rows() > 0 ? worst : 0.0;
}

int boundarySampleCount(double edgeLength, double targetEdgeLength) {
  if (!(edgeLength >= 0.0) || !(targetEdgeLength > 0.0) ||
      !std::isfinite(edgeLength / targetEdgeLength))
    throw InputError(
        fmt::format("boundarySampleCount: edge length {} and target {} must be "
                    "finite, the target positive",
                    edgeLength, targetEdgeLength));
  constexpr double kSpacing = 0.7;  // of the target: no boundary triangle's refinement point
                                    // then encroaches upon a boundary segment (tests/remesh)
  return std::max(2, static_cast<int>(std::ceil(edgeLength / (kSpacing * targetEdgeLength))) + 1);
}

TriMesh RemeshedPanel::toTriMesh() const {
  TriMesh mesh;
  mesh.V.setZero(V.rows(), 3);
  mesh.V.leftCols(2) = V;
  mesh.F = F;
  return mesh;
}

RemeshedPanel remeshPanel(const std::vector<Eigen::MatrixX2d>& edges, const std::string& name,
                          const RemeshOptions& options) {
  const std::string what = fmt::format("remeshPanel: panel '{}'", name);
  if (!(options.targetEdgeLength > 0.0) || !std::isfinite(options.targetEdgeLength))
    throw InputError(fmt::format("{}: targetEdgeLength must be positive (got {})", what,
                                 options.targetEdgeLength));
  if (!(options.minAngleDeg > 0.0 && options.minAngleDeg <= kMaxAngleDeg))
    throw InputError(
        fmt::format("{}: minAngleDeg must be in (0, {}] for the mesher to terminate "
                    "(got {})",
                    what, kMaxAngleDeg, options.minAngleDeg));
  if (edges.empty()) throw InputError(fmt::format("{}: the outline has no edges", what));

  // === The outline polygon: each edge's samples but its last (the next edge's first).
  double scale = 0.0;
  for (size_t k = 0; k < edges.size(); ++k) {
    if (edges[k].rows() < 2 || !edges[k].allFinite())
      throw InputError(
          fmt::format("{}: edge {} has {} samples{}; an edge needs two or more "
                      "finite samples",
                      what, k, edges[k].rows(), edges[k].allFinite() ? "" : " (some non-finite)"));
    scale = std::max(scale, edges[k].cwiseAbs().maxCoeff());
  }
  const double joinTolerance = 1e-9 * std::max(scale, 1e-300);
  std::vector<Eigen::Vector2d> samples;
  std::vector<int> edgeStart;
  for (size_t k = 0; k < edges.size(); ++k) {
    const Eigen::MatrixX2d& e = edges[k];
    const Eigen::MatrixX2d& next = edges[(k + 1) % edges.size()];
    if ((e.row(e.rows() - 1) - next.row(0)).norm() > joinTolerance)
      throw InputError(fmt::format(
          "{}: edge {} ends at ({:.6g}, {:.6g}) but edge {} starts at ({:.6g}, {:.6g}); the edges "
          "must join up into one closed outline, in order",
          what, k, e(e.rows() - 1, 0), e(e.rows() - 1, 1), (k + 1) % edges.size(), next(0, 0),
          next(0, 1)));
    edgeStart.push_back(static_cast<int>(samples.size()));
    for (int i = 0; i + 1 < e.rows(); ++i) samples.push_back(e.row(i).transpose());
  }
  const int n = static_cast<int>(samples.size());
  if (n < 3)
    throw InputError(
        fmt::format("{}: the outline has {} distinct samples; it needs three or more", what, n));
  Eigen::MatrixX2d polygon(n, 2);
  std::vector<int> loop(n);
  double signedArea = 0.0;
  for (int i = 0; i < n; ++i) {
    polygon.row(i) = samples[i].transpose();
    loop[i] = i;
    const Eigen::Vector2d& a = samples[i];
    const Eigen::Vector2d& b = samples[(i + 1) % n];
    signedArea += 0.5 * (a.x() * b.y() - a.y() * b.x());
  }
  if (!(std::abs(signedArea) > 0.0))
    throw InputError(fmt::format("{}: the outline encloses no area", what));
  if (polygonSelfIntersects(polygon, loop))
    throw InputError(
        fmt::format("{}: the outline touches or crosses itself (repeated samples "
                    "or overlapping edges); fix the flattening or the outline fit",
                    what));

  // === Constrained Delaunay triangulation of the outline, refined.
  Cdt cdt;
  std::vector<VertexHandle> handles(n);
  for (int i = 0; i < n; ++i) handles[i] = cdt.insert(Point(samples[i].x(), samples[i].y()));
  for (int i = 0; i < n; ++i) cdt.insert_constraint(handles[i], handles[(i + 1) % n]);
  const double sine = std::sin(options.minAngleDeg * std::numbers::pi / 180.0);
  const Criteria criteria(sine * sine, options.targetEdgeLength);
  if (options.allowBoundarySteiner) {
    CGAL::Delaunay_mesher_2<Cdt, Criteria> mesher(cdt, criteria);
    mesher.clear_seeds();  // as below: seeds_mark is otherwise read uninitialised
    mesher.refine_mesh();
  } else {
    CGAL::Delaunay_mesher_no_edge_refinement_2<Cdt, Criteria> mesher(cdt, criteria);
    // CGAL 5.5 leaves this mesher's seeds_mark uninitialised until seeds are set or cleared
    // (its refine_mesh reads it: undefined behaviour, caught by UBSan): clear them first.
    mesher.clear_seeds();
    mesher.refine_mesh();
  }

  // === Output: boundary vertices in outline order (walking the constraints), then the rest.
  RemeshedPanel out;
  std::map<VertexHandle, int> index;
  std::vector<Eigen::Vector2d> points;
  auto add = [&](VertexHandle v) {
    auto [it, inserted] = index.emplace(v, static_cast<int>(points.size()));
    if (inserted) points.emplace_back(v->point().x(), v->point().y());
    return it->second;
  };
  std::vector<std::vector<int>> segmentVertices(n);  // per polygon segment i → i+1, inner ones
  for (int i = 0; i < n; ++i) {
    add(handles[i]);
    VertexHandle previous = handles[(i + n - 1) % n], v = handles[i];
    const VertexHandle target = handles[(i + 1) % n];
    // Steiner points on segment i (only with allowBoundarySteiner).
    for (int guard = 0; guard < 1 << 20; ++guard) {
      const VertexHandle w = nextOnConstraint(cdt, v, previous, target->point());
      if (w == VertexHandle() || w == target) break;
      segmentVertices[i].push_back(add(w));
      ++out.boundarySteinerPoints;
      previous = v;
      v = w;
    }
  }
  out.numBoundaryVertices = static_cast<int>(points.size());
  std::vector<Eigen::Vector3i> faces;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    faces.emplace_back(add(f->vertex(0)), add(f->vertex(1)), add(f->vertex(2)));
  }
  out.V.resize(static_cast<int>(points.size()), 2);
  for (int v = 0; v < out.V.rows(); ++v) out.V.row(v) = points[v].transpose();
  out.F.resize(static_cast<int>(faces.size()), 3);
  for (int f = 0; f < out.F.rows(); ++f) out.F.row(f) = faces[f].transpose();

  // Per input edge: its samples' vertices (and Steiner points between them).
  for (size_t k = 0; k < edges.size(); ++k) {
    std::vector<int> ids;
    const int count = static_cast<int>(edges[k].rows());
    for (int j = 0; j < count; ++j) {
      const int s = (edgeStart[k] + j) % n;
      ids.push_back(index.at(handles[s]));
      if (j + 1 < count)
        ids.insert(ids.end(), segmentVertices[s].begin(), segmentVertices[s].end());
    }
    out.edgeVertices.push_back(std::move(ids));
  }

  // Quality figures.
  out.minAngleDeg = minimumAngleDeg(out.V, out.F);
  for (int f = 0; f < out.F.rows(); ++f) {
    const Eigen::Vector2d a = out.V.row(out.F(f, 0)).transpose();
    const Eigen::Vector2d b = out.V.row(out.F(f, 1)).transpose() - a;
    const Eigen::Vector2d c = out.V.row(out.F(f, 2)).transpose() - a;
    out.area += 0.5 * (b.x() * c.y() - b.y() * c.x());
    out.longestEdge = std::max({out.longestEdge, b.norm(), c.norm(), (c - b).norm()});
    if (faceMinAngleDeg(out.V, out.F, f) < options.minAngleDeg) ++out.badFaces;
  }
  return out;
}

}  // namespace s2p
