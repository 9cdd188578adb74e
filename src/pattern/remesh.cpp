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
#include <limits>
#include <map>
#include <numbers>
#include <optional>

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

// Smallest angle (degrees) of a CDT face.
double cdtFaceMinAngleDeg(const Cdt::Face_handle& f) {
  double worst = 180.0;
  for (int k = 0; k < 3; ++k) {
    const Point& p = f->vertex(k)->point();
    const Point& q = f->vertex((k + 1) % 3)->point();
    const Point& r = f->vertex((k + 2) % 3)->point();
    const double ax = q.x() - p.x(), ay = q.y() - p.y(), bx = r.x() - p.x(), by = r.y() - p.y();
    worst = std::min(worst, degrees(std::atan2(std::abs(ax * by - ay * bx), ax * bx + ay * by)));
  }
  return worst;
}

// The mesh's standing against the angle bound: faces below it (fewer is better), then its
// smallest angle (larger is better).
struct AngleScore {
  int badFaces = 0;
  double minAngleDeg = 180.0;
  bool betterThan(const AngleScore& other) const {
    return badFaces != other.badFaces ? badFaces < other.badFaces
                                      : minAngleDeg > other.minAngleDeg + 1e-9;
  }
};

AngleScore angleScore(const Cdt& cdt, double boundDeg, std::vector<Cdt::Face_handle>* bad) {
  AngleScore score;
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->is_in_domain()) continue;
    const double angle = cdtFaceMinAngleDeg(f);
    score.minAngleDeg = std::min(score.minAngleDeg, angle);
    if (angle < boundDeg) {
      ++score.badFaces;
      if (bad) bad->push_back(f);
    }
  }
  return score;
}

template <class Mesher>
void refine(Cdt& cdt, const Criteria& criteria) {
  Mesher mesher(cdt, criteria);
  // CGAL 5.5 leaves the mesher's seeds_mark uninitialised until seeds are set or cleared (its
  // refine_mesh reads it: undefined behaviour, caught by UBSan): clear them first.
  mesher.clear_seeds();
  mesher.refine_mesh();
}

// Inserts p into the CDT when it lies strictly inside the domain, away from every vertex, and
// refines again; false (cdt untouched) otherwise.
bool insertInside(Cdt& cdt, const Point& p, double minDistance, const Criteria& criteria) {
  Cdt::Locate_type type;
  int li = 0;
  const Cdt::Face_handle f = cdt.locate(p, type, li);
  if (type != Cdt::FACE || cdt.is_infinite(f) || !f->is_in_domain()) return false;
  for (int k = 0; k < 3; ++k)
    if (CGAL::squared_distance(p, f->vertex(k)->point()) < minDistance * minDistance)
      return false;
  cdt.insert(p, f);
  refine<CGAL::Delaunay_mesher_no_edge_refinement_2<Cdt, Criteria>>(cdt, criteria);
  return true;
}

// Faces the refinement leaves below the angle bound when it may not split the boundary. The
// mesher drops a refinement point (the bad face's circumcentre) that encroaches upon a boundary
// segment. Between a boundary segment much shorter than its neighbour and that neighbour (two
// outline corners a few millimetres apart, a 2.4 mm jog beside 7 mm samples), the thin face's
// circumcentre always does, yet a point nearer the short segment makes good faces of it. So
// each face still below the bound is offered other interior points: on each of its edges, the
// apex of isosceles triangles with base angles 30°, 45° and 60° on the face's side, and its
// centroid. The point after whose insertion (and refinement) the mesh scores best is kept, while
// one improves the score; the boundary is never touched.
void repairBadFaces(Cdt& cdt, const Criteria& criteria, double boundDeg) {
  constexpr int kMaxRounds = 16;
  constexpr int kMaxFacesPerRound = 8;
  for (int round = 0; round < kMaxRounds; ++round) {
    std::vector<Cdt::Face_handle> bad;
    const AngleScore current = angleScore(cdt, boundDeg, &bad);
    if (bad.empty()) return;
    std::vector<Point> candidates;
    for (int b = 0; b < std::min<int>(kMaxFacesPerRound, static_cast<int>(bad.size())); ++b) {
      const Cdt::Face_handle f = bad[b];
      const Point &p0 = f->vertex(0)->point(), &p1 = f->vertex(1)->point(),
                  &p2 = f->vertex(2)->point();
      candidates.emplace_back((p0.x() + p1.x() + p2.x()) / 3.0, (p0.y() + p1.y() + p2.y()) / 3.0);
      for (int k = 0; k < 3; ++k) {
        const Point& a = f->vertex((k + 1) % 3)->point();
        const Point& c = f->vertex((k + 2) % 3)->point();
        const Point& opposite = f->vertex(k)->point();
        const double mx = 0.5 * (a.x() + c.x()), my = 0.5 * (a.y() + c.y());
        double nx = -(c.y() - a.y()), ny = c.x() - a.x();  // a normal of edge a→c
        if (nx * (opposite.x() - mx) + ny * (opposite.y() - my) < 0.0) nx = -nx, ny = -ny;
        const double half = 0.5 * std::hypot(nx, ny);
        if (!(half > 0.0)) continue;
        for (const double baseDeg : {30.0, 45.0, 60.0}) {
          const double height = half * std::tan(baseDeg * std::numbers::pi / 180.0);
          candidates.emplace_back(mx + nx / (2.0 * half) * height, my + ny / (2.0 * half) * height);
        }
      }
    }
    double shortestEdge = std::numeric_limits<double>::infinity();
    for (const Cdt::Face_handle& f : bad)
      for (int k = 0; k < 3; ++k)
        shortestEdge = std::min(shortestEdge, std::sqrt(CGAL::squared_distance(
                                                  f->vertex(k)->point(),
                                                  f->vertex((k + 1) % 3)->point())));
    const double minDistance = 0.2 * shortestEdge;
    std::optional<Point> best;
    AngleScore bestScore = current;
    for (const Point& p : candidates) {
      Cdt trial = cdt;
      if (!insertInside(trial, p, minDistance, criteria)) continue;
      const AngleScore score = angleScore(trial, boundDeg, nullptr);
      if (score.betterThan(bestScore)) bestScore = score, best = p;
    }
    if (!best) return;
    insertInside(cdt, *best, minDistance, criteria);
  }
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
    refine<CGAL::Delaunay_mesher_2<Cdt, Criteria>>(cdt, criteria);
  } else {
    refine<CGAL::Delaunay_mesher_no_edge_refinement_2<Cdt, Criteria>>(cdt, criteria);
    if (options.repairBadFaces) repairBadFaces(cdt, criteria, options.minAngleDeg);
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
