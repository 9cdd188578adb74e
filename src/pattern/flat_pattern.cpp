#include "pattern/flat_pattern.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>

#include "core/error.h"
#include "core/uv_locator.h"

namespace s2p {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double polylineLength(const Eigen::MatrixX2d& poly) {
  double l = 0.0;
  for (int i = 0; i + 1 < poly.rows(); ++i) l += (poly.row(i + 1) - poly.row(i)).norm();
  return l;
}

Eigen::MatrixX2d rowsOf(const Eigen::MatrixX2d& uv, const std::vector<int>& ids) {
  Eigen::MatrixX2d P(static_cast<int>(ids.size()), 2);
  for (size_t i = 0; i < ids.size(); ++i) P.row(static_cast<int>(i)) = uv.row(ids[i]);
  return P;
}

// Flattening of one panel (no outline yet: the seams are trued first).
void flatten(const Panel& panel, const BodyFrame& frame, const FlatPatternOptions& options,
             const PanelReshape* reshape, FlatPanel& out) {
  TriMesh shape = panel.mesh;
  out.grain = panelGrain(panel, frame);
  if (reshape && reshape->V.rows() > 0) {
    if (reshape->V.rows() != panel.mesh.numVertices() || !reshape->V.allFinite())
      throw InputError(
          fmt::format("panel '{}' of {}: its reshaped vertices ({}) do not match its "
                      "{} vertices or are not finite",
                      panel.name, panel.garment, reshape->V.rows(), panel.mesh.numVertices()));
    shape.V = reshape->V;
    if (reshape->grain.norm() > 1e-9) out.grain = reshape->grain.normalized();
    out.reshaped = reshape->why;
  }
  std::vector<int> corners;
  for (const PanelEdge& e : panel.edges) corners.push_back(e.vertices.front());
  out.surface = denoisePanel(shape, panel.loop, corners, options.denoise);
  const Eigen::VectorXd shift = (out.surface.V - shape.V).rowwise().norm();
  out.denoiseShiftMean = shift.size() ? shift.mean() : 0.0;
  out.denoiseShiftMax = shift.size() ? shift.maxCoeff() : 0.0;
  out.flattening =
      flattenPanel(out.surface, out.grain, panel.garment + " " + panel.name, options.flatten);
  out.uv = out.flattening.uv;
}

// Metrics and Bézier outline of a flattened panel (no remeshing yet: the sample counts depend
// on the partner panels' 2D lengths).
void outline(const Panel& panel, const FlatPatternOptions& options, FlatPanel& out) {
  out.metrics = flatteningMetrics(out.surface, out.uv, out.grain);
  if (!out.reshaped.empty()) out.scannedMetrics = flatteningMetrics(panel.mesh, out.uv, out.grain);
  out.edges.clear();
  for (const PanelEdge& e : panel.edges) {
    FlatEdge fe;
    const Eigen::MatrixX2d poly = rowsOf(out.uv, e.vertices);
    fe.length2d = polylineLength(poly);
    fe.chain = fitBezierChain(poly, options.bezier);
    fe.fitError = maxDeviation(fe.chain, poly);
    out.edges.push_back(std::move(fe));
  }
}

// The partner seam edges of the panels, each pair once (a < b).
std::vector<SeamPair> seamPairs(const PanelsResult& panels) {
  std::vector<SeamPair> pairs;
  for (size_t p = 0; p < panels.panels.size(); ++p) {
    const Panel& panel = panels.panels[p];
    for (size_t e = 0; e < panel.edges.size(); ++e) {
      const PanelEdge& edge = panel.edges[e];
      if (edge.opening || edge.partnerPanel < 0 || edge.partnerEdge < 0) continue;
      const std::pair<int, int> a{static_cast<int>(p), static_cast<int>(e)};
      const std::pair<int, int> b{edge.partnerPanel, edge.partnerEdge};
      if (a < b) pairs.push_back({a.first, a.second, b.first, b.second});
    }
  }
  return pairs;
}

// Whether every crossing of a flattened boundary involves a segment of an opening (a hem, a
// cuff, a frilly neckline folded over a side seam): openings are untangled after the outline fit
// (untangleOpenings, which undoes the truing when it cannot), so a truing whose overlaps are
// there is kept; two seam edges that cross are not.
bool openingsInEveryCrossing(const Panel& panel, const std::vector<int>& boundary,
                             const std::vector<std::pair<int, int>>& crossings) {
  std::map<std::pair<int, int>, bool> opening;  // boundary segment (min, max) → on an opening
  for (const PanelEdge& e : panel.edges)
    for (size_t k = 0; k + 1 < e.vertices.size(); ++k)
      opening[std::minmax(e.vertices[k], e.vertices[k + 1])] = e.opening;
  const int n = static_cast<int>(boundary.size());
  const auto isOpening = [&](int i) {
    const auto it = opening.find(std::minmax(boundary[i], boundary[(i + 1) % n]));
    return it != opening.end() && it->second;
  };
  for (const auto& [i, j] : crossings)
    if (!isOpening(i) && !isOpening(j)) return false;
  return true;
}

// Seam truing (flatten.h): both edges of every pair whose panels flattened get the mean of
// their 2D lengths; each panel is moved to its targets, then re-aligned to its grain.
void trueSeams(const PanelsResult& panels, const std::vector<SeamPair>& pairs,
               const FlatPatternOptions& options, FlatPatternResult& r) {
  std::vector<std::vector<BoundaryLengthTarget>> targets(panels.panels.size());
  auto uvLength = [&](int p, int e) {
    return polylineLength(rowsOf(r.panels[p].uv, panels.panels[p].edges[e].vertices));
  };
  for (const SeamPair& s : pairs) {
    if (!r.panels[s.panelA].error.empty() || !r.panels[s.panelB].error.empty()) continue;
    const double mean = 0.5 * (uvLength(s.panelA, s.edgeA) + uvLength(s.panelB, s.edgeB));
    targets[s.panelA].push_back({panels.panels[s.panelA].edges[s.edgeA].vertices, mean});
    targets[s.panelB].push_back({panels.panels[s.panelB].edges[s.edgeB].vertices, mean});
  }
  std::vector<std::string> failures(panels.panels.size());
  tbb::parallel_for(size_t{0}, panels.panels.size(), [&](size_t p) {
    FlatPanel& fp = r.panels[p];
    if (!fp.error.empty() || targets[p].empty()) return;
    const TriMesh& mesh = fp.surface;
    // From the refined flattening first; where that overlaps itself, from BFF's, whose seams
    // already have their 3D lengths (the strain fit of a panel that is far from developable,
    // a sleeve on a bent arm, can move its two underarm edges 10 cm apart: too far to true).
    for (const Eigen::MatrixX2d* start : {&fp.uv, &fp.flattening.uvBff}) {
      try {
        Eigen::MatrixX2d trued = trueBoundaryLengths(mesh, fp.grain, *start, targets[p],
                                                     options.flatten, options.truing);
        if (options.flatten.alignGrain) trued = alignToGrain(mesh, fp.grain, trued);
        // Truing moves the boundary: it must not come to overlap itself, but at its openings.
        std::vector<std::pair<int, int>> crossings;
        if (polygonSelfIntersects(trued, fp.flattening.boundary, &crossings) &&
            !openingsInEveryCrossing(panels.panels[p], fp.flattening.boundary, crossings)) {
          failures[p] = "its trued outline overlapped itself";
          continue;
        }
        fp.uv = trued;
        failures[p].clear();
        break;
      } catch (const Error& e) {
        failures[p] = e.what();
      }
    }
  });
  for (size_t p = 0; p < failures.size(); ++p)
    if (!failures[p].empty())
      r.warnings.push_back(
          fmt::format("panel '{}' of {}: seams not trued ({}); its stitches "
                      "keep their flattened lengths",
                      panels.panels[p].name, panels.panels[p].garment, failures[p]));
}

// The edges of the outline that cross or touch another part of it (#edges flags; all zero: the
// outline is simple), as the remesher sees the outline (each edge's chain resampled at its count,
// the last sample of each edge left to the next edge's first) and as the print draws it (a
// sample every kPrintSpacing): a crossing at either resolution is one.
std::vector<char> crossingEdges(const FlatPanel& fp, const std::vector<int>& counts) {
  constexpr double kPrintSpacing = 0.002;  // m, finer than the print's 3 mm sew-line samples
  std::vector<char> crossing(fp.edges.size(), 0);
  for (const bool fine : {false, true}) {
    std::vector<Eigen::Vector2d> pts;
    std::vector<int> owner;  // per segment, its edge
    for (size_t e = 0; e < fp.edges.size(); ++e) {
      const BezierChain& c = fp.edges[e].chain;
      const int count =
          fine ? std::max(2, static_cast<int>(std::ceil(c.length() / kPrintSpacing)) + 1)
               : counts[e];
      const Eigen::MatrixX2d s = resampleChain(c, count);
      for (int i = 0; i + 1 < s.rows(); ++i) {
        pts.push_back(s.row(i).transpose());
        owner.push_back(static_cast<int>(e));
      }
    }
    Eigen::MatrixX2d polygon(static_cast<int>(pts.size()), 2);
    std::vector<int> loop(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) {
      polygon.row(static_cast<int>(i)) = pts[i].transpose();
      loop[i] = static_cast<int>(i);
    }
    std::vector<std::pair<int, int>> pairs;
    if (polygonSelfIntersects(polygon, loop, &pairs))
      for (const auto& [a, b] : pairs) crossing[owner[a]] = crossing[owner[b]] = 1;
  }
  return crossing;
}

bool outlineSelfIntersects(const FlatPanel& fp, const std::vector<int>& counts) {
  const std::vector<char> c = crossingEdges(fp, counts);
  return std::find(c.begin(), c.end(), 1) != c.end();
}

// `iterations` steps of uniform Laplacian smoothing (λ = ½) of an open polyline, ends fixed:
// curve-shortening, under which a fold or a frill's loop shrinks and the polyline tends to the
// straight line between its corners.
Eigen::MatrixX2d smoothPolyline(Eigen::MatrixX2d p, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    Eigen::MatrixX2d q = p;
    for (int i = 1; i + 1 < p.rows(); ++i)
      q.row(i) = 0.5 * p.row(i) + 0.25 * (p.row(i - 1) + p.row(i + 1));
    p = std::move(q);
  }
  return p;
}

// A scan's hem or cuff with frills, lumps where its shell folded, or a scrap of skin left on it
// flattens into an outline that folds over itself, which no mesher can fill. Only openings are
// touched (a seam's length is its partner's), and only those a crossing involves: each is
// smoothed along the flattened boundary, more each round, and fitted again until the outline is
// simple. Returns the rounds' smoothing steps used (0: the outline was simple), or −1 when even
// the most smoothing left it crossing itself (the remesher then says so).
int untangleOpenings(const Panel& panel, const std::vector<int>& counts,
                     const FlatPatternOptions& options, FlatPanel& fp) {
  std::vector<char> crossing = crossingEdges(fp, counts);
  if (std::find(crossing.begin(), crossing.end(), 1) == crossing.end()) return 0;
  std::vector<char> smoothed(fp.edges.size(), 0);
  for (int iterations : {4, 16, 64, 256, 1024}) {
    for (size_t e = 0; e < panel.edges.size(); ++e) {
      smoothed[e] = smoothed[e] || (crossing[e] && panel.edges[e].opening);
      if (!smoothed[e]) continue;
      const Eigen::MatrixX2d poly = rowsOf(fp.uv, panel.edges[e].vertices);
      FlatEdge& fe = fp.edges[e];
      fe.chain = fitBezierChain(smoothPolyline(poly, iterations), options.bezier);
      fe.fitError = maxDeviation(fe.chain, poly);
    }
    crossing = crossingEdges(fp, counts);
    if (std::find(crossing.begin(), crossing.end(), 1) == crossing.end()) return iterations;
  }
  return -1;
}

// Seam walking (FlatPatternOptions::walkSeams): both chains of a pair to their mean length; a
// panel whose outline the walked chains make cross itself gets its own chains back.
void walkSeams(const PanelsResult& panels, const std::vector<SeamPair>& pairs,
               const FlatPatternOptions& options, FlatPatternResult& r) {
  std::vector<std::vector<FlatEdge>> before(r.panels.size());
  for (size_t p = 0; p < r.panels.size(); ++p) before[p] = r.panels[p].edges;
  int walked = 0;
  for (const SeamPair& s : pairs) {
    FlatPanel& fa = r.panels[s.panelA];
    FlatPanel& fb = r.panels[s.panelB];
    if (!fa.error.empty() || !fb.error.empty()) continue;
    BezierChain& ca = fa.edges[s.edgeA].chain;
    BezierChain& cb = fb.edges[s.edgeB].chain;
    const double la = ca.length(), lb = cb.length(), mean = 0.5 * (la + lb);
    if (std::abs(la - lb) < 1e-5) continue;
    const auto wa = walkChainToLength(ca, mean, options.walkLimit);
    const auto wb = walkChainToLength(cb, mean, options.walkLimit);
    if (!wa || !wb) continue;
    ca = *wa;
    cb = *wb;
    ++walked;
  }
  if (walked == 0) return;
  const double target = options.remesh.targetEdgeLength;
  for (size_t p = 0; p < r.panels.size(); ++p) {
    FlatPanel& fp = r.panels[p];
    if (!fp.error.empty()) continue;
    std::vector<int> counts, countsBefore;
    for (size_t e = 0; e < fp.edges.size(); ++e) {
      counts.push_back(boundarySampleCount(fp.edges[e].chain.length(), target));
      countsBefore.push_back(boundarySampleCount(before[p][e].chain.length(), target));
    }
    FlatPanel unwalked;
    unwalked.edges = before[p];
    if (outlineSelfIntersects(fp, counts) && !outlineSelfIntersects(unwalked, countsBefore)) {
      fp.edges = before[p];
      r.warnings.push_back(
          fmt::format("panel '{}' of {}: its seams not walked to their partners' "
                      "lengths (the outline would cross itself)",
                      panels.panels[p].name, panels.panels[p].garment));
    }
  }
}

void remesh(const Panel& panel, const TriMesh& scan, const std::vector<int>& counts,
            const FlatPatternOptions& options, FlatPanel& out) {
  std::vector<Eigen::MatrixX2d> samples;
  for (size_t e = 0; e < out.edges.size(); ++e)
    samples.push_back(resampleChain(out.edges[e].chain, counts[e]));
  out.remeshed = remeshPanel(samples, panel.garment + " " + panel.name, options.remesh);
  for (size_t e = 0; e < out.edges.size(); ++e)
    out.edges[e].vertices = out.remeshed.edgeVertices[e];
  const UvLocator locator(out.uv, panel.mesh.F);
  out.location = locator.locate(out.remeshed.V);
  out.position = interpolateAt(out.location, panel.mesh.F, panel.mesh.V);
  const int n = static_cast<int>(out.location.size());
  out.scanFace.resize(n);
  out.scanBary.resize(n, 3);
  for (int v = 0; v < n; ++v) {
    const int f = panel.faceOrigin[out.location[v].face];
    out.scanFace[v] = f;
    const Eigen::Vector3d p = out.position.row(v).transpose();
    out.scanBary.row(v) = closestPointBarycentric(p, scan.V.row(scan.F(f, 0)).transpose(),
                                                  scan.V.row(scan.F(f, 1)).transpose(),
                                                  scan.V.row(scan.F(f, 2)).transpose())
                              .transpose();
  }
}

// Boundary samples of a stitched pair: the count of its mean 2D length (of the one flattened
// panel when the other was not).
int pairSampleCount(const std::vector<FlatPanel>& panels, const SeamPair& s, double target) {
  const bool a = panels[s.panelA].error.empty(), b = panels[s.panelB].error.empty();
  const double mean = a && b ? 0.5 * (s.lengthA + s.lengthB) : std::max(s.lengthA, s.lengthB);
  return boundarySampleCount(mean, target);
}

// Per panel and edge, its boundary samples at the target edge length: a stitched pair shares
// one count, so that a simulator can pair the two edges vertex to vertex. Panels that were not
// flattened get none.
std::vector<std::vector<int>> sampleCounts(const std::vector<FlatPanel>& panels,
                                           const std::vector<SeamPair>& pairs, double target) {
  std::vector<std::vector<int>> counts(panels.size());
  for (size_t p = 0; p < panels.size(); ++p) {
    if (!panels[p].error.empty()) continue;
    for (const FlatEdge& e : panels[p].edges)
      counts[p].push_back(boundarySampleCount(e.length2d, target));
  }
  for (const SeamPair& s : pairs) {
    const int n = pairSampleCount(panels, s, target);
    if (!counts[s.panelA].empty()) counts[s.panelA][s.edgeA] = n;
    if (!counts[s.panelB].empty()) counts[s.panelB][s.edgeB] = n;
  }
  return counts;
}

}  // namespace

Eigen::Vector3d panelGrain(const Panel& panel, const BodyFrame& frame) {
  if (panel.name.find("sleeve") != std::string::npos) {
    const bool left = panel.name.rfind("left", 0) == 0;
    const Eigen::Vector3d axis =
        frame.at(left ? Canonical::LeftShoulder : Canonical::RightShoulder) -
        frame.at(left ? Canonical::LeftWrist : Canonical::RightWrist);
    if (axis.norm() > 1e-6) return axis.normalized();
  }
  return frame.up();
}

FlatPatternResult runFlatPattern(const PanelsResult& panels, const TriMesh& scan,
                                 const BodyFrame& frame, const FlatPatternOptions& options,
                                 const std::vector<PanelReshape>& reshape) {
  if (!reshape.empty() && reshape.size() != panels.panels.size())
    throw InputError(fmt::format("runFlatPattern: {} reshaped shapes for {} panels", reshape.size(),
                                 panels.panels.size()));
  const auto t0 = std::chrono::steady_clock::now();
  FlatPatternResult r;
  r.panels.resize(panels.panels.size());
  tbb::parallel_for(size_t{0}, panels.panels.size(), [&](size_t p) {  // panels are independent
    const auto tp = std::chrono::steady_clock::now();
    FlatPanel& fp = r.panels[p];
    fp.panel = static_cast<int>(p);
    try {
      flatten(panels.panels[p], frame, options, reshape.empty() ? nullptr : &reshape[p], fp);
    } catch (const Error& e) {
      fp.error = e.what();
    }
    fp.seconds = secondsSince(tp);
  });
  for (size_t p = 0; p < panels.panels.size(); ++p)
    if (!r.panels[p].error.empty())
      r.warnings.push_back(fmt::format("panel '{}' of {} not flattened: {}", panels.panels[p].name,
                                       panels.panels[p].garment, r.panels[p].error));
  std::vector<SeamPair> pairs = seamPairs(panels);
  std::vector<Eigen::MatrixX2d> untrued(panels.panels.size());
  for (size_t p = 0; p < panels.panels.size(); ++p) untrued[p] = r.panels[p].uv;
  if (options.trueSeams) trueSeams(panels, pairs, options, r);
  for (size_t p = 0; p < panels.panels.size(); ++p)
    if (r.panels[p].error.empty()) outline(panels.panels[p], options, r.panels[p]);
  if (options.walkSeams) walkSeams(panels, pairs, options, r);
  for (SeamPair& s : pairs) {
    // The lengths a simulator and a pattern maker see: the Bézier chains'.
    if (r.panels[s.panelA].error.empty())
      s.lengthA = r.panels[s.panelA].edges[s.edgeA].chain.length();
    if (r.panels[s.panelB].error.empty())
      s.lengthB = r.panels[s.panelB].edges[s.edgeB].chain.length();
  }
  const std::vector<std::vector<int>> counts =
      sampleCounts(r.panels, pairs, options.remesh.targetEdgeLength);
  for (SeamPair& s : pairs)
    s.samples = pairSampleCount(r.panels, s, options.remesh.targetEdgeLength);
  r.seams = std::move(pairs);
  for (size_t p = 0; p < panels.panels.size(); ++p) {
    FlatPanel& fp = r.panels[p];
    if (!fp.error.empty()) continue;
    const auto tp = std::chrono::steady_clock::now();
    try {
      int rounds = untangleOpenings(panels.panels[p], counts[p], options, fp);
      if (rounds < 0 && !fp.uv.isApprox(untrued[p])) {
        // The trued openings could not be untangled: the flattened shape, untrued.
        fp.uv = untrued[p];
        outline(panels.panels[p], options, fp);
        rounds = untangleOpenings(panels.panels[p], counts[p], options, fp);
        r.warnings.push_back(
            fmt::format("panel '{}' of {}: truing undone (its openings "
                        "folded over themselves); its stitches keep their "
                        "flattened lengths",
                        panels.panels[p].name, panels.panels[p].garment));
      }
      if (rounds > 0) {
        double worst = 0;
        for (size_t e = 0; e < fp.edges.size(); ++e)
          if (panels.panels[p].edges[e].opening) worst = std::max(worst, fp.edges[e].fitError);
        r.warnings.push_back(fmt::format(
            "panel '{}' of {}: its flattened openings folded over themselves (frills or lumps "
            "of the scan); they were smoothed ({} steps) and now lie within {:.1f} mm of the "
            "scan's edge",
            panels.panels[p].name, panels.panels[p].garment, rounds, 1000 * worst));
      }
      remesh(panels.panels[p], scan, counts[p], options, fp);
    } catch (const Error& e) {
      fp.error = e.what();
      r.warnings.push_back(fmt::format("panel '{}' of {} not remeshed: {}", panels.panels[p].name,
                                       panels.panels[p].garment, e.what()));
    }
    fp.seconds += secondsSince(tp);
  }
  r.seconds = secondsSince(t0);
  return r;
}

std::vector<RemeshedPanel> remeshOutlines(const FlatPatternResult& flat,
                                          const RemeshOptions& options,
                                          std::vector<std::string>* errors) {
  const std::vector<std::vector<int>> counts =
      sampleCounts(flat.panels, flat.seams, options.targetEdgeLength);
  std::vector<RemeshedPanel> out(flat.panels.size());
  std::vector<std::string> why(flat.panels.size());
  tbb::parallel_for(size_t{0}, flat.panels.size(), [&](size_t p) {
    const FlatPanel& fp = flat.panels[p];
    if (!fp.error.empty() || fp.remeshed.V.rows() == 0) return;
    std::vector<Eigen::MatrixX2d> samples;
    for (size_t e = 0; e < fp.edges.size(); ++e)
      samples.push_back(resampleChain(fp.edges[e].chain, counts[p][e]));
    try {
      out[p] = remeshPanel(samples, fmt::format("panel {}", p), options);
    } catch (const Error& e) {
      why[p] = e.what();
    }
  });
  if (errors) *errors = std::move(why);
  return out;
}

}  // namespace s2p
