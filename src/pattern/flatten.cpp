#include "pattern/flatten.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/mesh_topology.h"
#include "core/reduced_system.h"
#include "core/spd_solver.h"
#include "pattern/flatten_metrics.h"
#include "pattern/flip_repair.h"
#include "pattern/grain_frame.h"

namespace s2p {
namespace {

constexpr double kPi = std::numbers::pi;

// A face is degenerate when twice its area is below this fraction of its longest edge squared
// (sin of its largest angle's supplement ~ 1e-12): numerically zero, not merely a sliver.
constexpr double kDegenerateRatio = 1e-12;

Eigen::Vector3d vertex(const TriMesh& mesh, int v) {
  return mesh.V.row(v).transpose();
}

// Corner angles of every face, #F×3 (angle at corner k of face f), from the 3D triangles.
Eigen::MatrixX3d cornerAngles(const TriMesh& mesh) {
  Eigen::MatrixX3d angles(mesh.numFaces(), 3);
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const Eigen::Vector3d p = vertex(mesh, mesh.F(f, k));
      const Eigen::Vector3d a = vertex(mesh, mesh.F(f, (k + 1) % 3)) - p;
      const Eigen::Vector3d b = vertex(mesh, mesh.F(f, (k + 2) % 3)) - p;
      angles(f, k) = std::atan2(a.cross(b).norm(), a.dot(b));
    }
  return angles;
}

// The closest matrix to J = [a b] (2×2, columns: images of unit warp and weft steps) whose
// columns are unit vectors at a signed angle in [π/2 − maxShear, π/2 + maxShear] (counter-
// clockwise from warp to weft). Each column is normalised; when the angle is out of range both
// are turned towards the range, each by a share inverse to its length (the minimiser of
// |a|δa² + |b|δb², exact to second order).
Eigen::Matrix2d warpWeftTarget(const Eigen::Matrix2d& J, double maxShear) {
  const double la = J.col(0).norm(), lb = J.col(1).norm();
  // Common case, no trigonometry: both columns non-zero, counter-clockwise and within the
  // shear range, |cos θ| ≤ sin(maxShear).
  if (la > 0.0 && lb > 0.0) {
    const Eigen::Vector2d a = J.col(0) / la, b = J.col(1) / lb;
    const double cross = a.x() * b.y() - a.y() * b.x();
    if (cross > 0.0 && std::abs(a.dot(b)) <= std::sin(maxShear)) {
      Eigen::Matrix2d T;
      T << a, b;
      return T;
    }
  }
  double alphaA = la > 0.0 ? std::atan2(J(1, 0), J(0, 0)) : 0.5 * kPi;
  double alphaB = lb > 0.0 ? std::atan2(J(1, 1), J(0, 1)) : alphaA + 0.5 * kPi;
  if (la == 0.0 && lb > 0.0) alphaA = alphaB - 0.5 * kPi;
  double theta = alphaB - alphaA;  // signed angle warp → weft in (−π, π]
  while (theta > kPi) theta -= 2.0 * kPi;
  while (theta <= -kPi) theta += 2.0 * kPi;
  const double lo = 0.5 * kPi - maxShear, hi = 0.5 * kPi + maxShear;
  const double clamped = std::clamp(theta, lo, hi);
  const double delta = clamped - theta;  // the angle must open by delta
  const double wa = la + lb > 0.0 ? lb / (la + lb) : 0.5;
  alphaA -= delta * wa;
  alphaB = alphaA + clamped;
  Eigen::Matrix2d T;
  T << std::cos(alphaA), std::cos(alphaB), std::sin(alphaA), std::sin(alphaB);
  return T;
}

Eigen::Matrix2d jacobianOf(const Eigen::MatrixX4d& J, int f) {
  Eigen::Matrix2d M;
  M << J(f, 0), J(f, 2), J(f, 1), J(f, 3);
  return M;
}

}  // namespace

// === Input checks

std::vector<int> checkFlattenablePanel(const TriMesh& panel, const std::string& name) {
  const std::string what = fmt::format("panel '{}'", name);
  validateMesh(panel, what);
  const int nV = panel.numVertices(), nF = panel.numFaces();
  std::vector<bool> used(nV, false);
  for (int f = 0; f < nF; ++f) {
    for (int k = 0; k < 3; ++k) used[panel.F(f, k)] = true;
    const Eigen::Vector3d a = vertex(panel, panel.F(f, 0)), b = vertex(panel, panel.F(f, 1)),
                          c = vertex(panel, panel.F(f, 2));
    const double longest2 =
        std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
    const double doubleArea = (b - a).cross(c - a).norm();
    if (!(doubleArea > kDegenerateRatio * longest2))
      throw InputError(fmt::format(
          "{}: face {} (vertices {}, {}, {}) has zero area; remove degenerate faces (collapse "
          "its shortest edge) before flattening",
          what, f, panel.F(f, 0), panel.F(f, 1), panel.F(f, 2)));
  }
  for (int v = 0; v < nV; ++v)
    if (!used[v])
      throw InputError(fmt::format(
          "{}: vertex {} is used by no face; drop unreferenced vertices before flattening", what,
          v));
  const MeshTopology topology(panel.F, nV);
  const ManifoldReport& manifold = topology.manifoldness();
  if (!manifold.isManifold())
    throw TopologyError(fmt::format(
        "{}: not a manifold ({} non-manifold edges, {} non-manifold vertices{}); a panel must "
        "be a topological disk",
        what, manifold.nonManifoldEdges.size(), manifold.nonManifoldVertices.size(),
        manifold.nonManifoldVertices.empty()
            ? std::string()
            : fmt::format(", e.g. vertex {}", manifold.nonManifoldVertices.front())));
  // Consistent orientation: each edge traversed at most once in each direction.
  std::vector<unsigned char> seen(topology.numEdges(), 0);  // bit 0: low→high, bit 1: high→low
  for (int f = 0; f < nF; ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = panel.F(f, (k + 1) % 3), b = panel.F(f, (k + 2) % 3);
      if (a == b) throw InputError(fmt::format("{}: face {} uses vertex {} twice", what, f, a));
      const int e = topology.faceEdges()(f, k);
      const unsigned char bit = a < b ? 1 : 2;
      if (seen[e] & bit)
        throw TopologyError(fmt::format(
            "{}: edge ({}, {}) is traversed in the same direction by two faces (face {} and an "
            "earlier one): the faces are not consistently oriented; reorient them",
            what, a, b, f));
      seen[e] |= bit;
    }
  if (topology.numComponents() != 1)
    throw TopologyError(
        fmt::format("{}: has {} separate pieces; flatten each piece as its own "
                    "panel",
                    what, topology.numComponents()));
  const auto& loops = topology.boundaryLoops();
  if (loops.empty())
    throw TopologyError(fmt::format(
        "{}: is closed (no boundary); cut it open along a seam into a disk before flattening",
        what));
  if (loops.size() != 1 || topology.eulerCharacteristic() != 1)
    throw TopologyError(fmt::format(
        "{}: is not a disk ({} boundary loops, Euler characteristic {}; a disk has 1 and 1): "
        "cut it along a seam so that it has one boundary and no handles",
        what, loops.size(), topology.eulerCharacteristic()));
  return loops.front();
}

// === Boundary First Flattening, u = 0 on the boundary

namespace {

Eigen::MatrixX2d bffImpl(const TriMesh& panel, const std::vector<int>& loop,
                         const std::string& name, Eigen::VectorXd* logScale) {
  const int nV = panel.numVertices(), nF = panel.numFaces();
  const int nB = static_cast<int>(loop.size()), nI = nV - nB;

  // Step 1: curvatures. K_i = 2π − Σθ inside, k_i = π − Σθ on the boundary.
  const Eigen::MatrixX3d angles = cornerAngles(panel);
  Eigen::VectorXd angleSum = Eigen::VectorXd::Zero(nV);
  for (int f = 0; f < nF; ++f)
    for (int k = 0; k < 3; ++k) angleSum(panel.F(f, k)) += angles(f, k);

  Eigen::VectorXd kTilde(nB);  // target exterior angles
  for (int i = 0; i < nB; ++i) kTilde(i) = kPi - angleSum(loop[i]);

  // Step 2: Laplacian blocks, the boundary known.
  const Eigen::SparseMatrix<double> L = cotanLaplacian(panel);
  std::vector<char> onBoundary(nV, 0);
  for (int v : loop) onBoundary[v] = 1;
  const ReducedSystem system(L, onBoundary);
  SpdSolver solver;
  Eigen::VectorXd u = Eigen::VectorXd::Zero(nV);  // the log scale, 0 on the boundary
  if (nI > 0) {
    try {
      solver.compute(system.freeBlock());
    } catch (const SolverError& e) {
      throw SolverError(fmt::format("panel '{}': the interior Laplacian cannot be factored ({})",
                                    name, e.what()));
    }
    // Step 3: Dirichlet-to-Neumann with u_B = 0: A_II u_I = −K_I, k̃ = k + A_IBᵀ u_I (the
    // boundary rows of A u, A symmetric).
    Eigen::VectorXd minusK(nI);
    for (int i = 0; i < nI; ++i) minusK(i) = -(2.0 * kPi - angleSum(system.fullIndex(i)));
    system.scatter(solver.solve(minusK), u);
    const Eigen::VectorXd Au = L * u;
    for (int i = 0; i < nB; ++i) kTilde(i) += Au(loop[i]);
  }
  if (logScale) *logScale = u;

  // Steps 4–5: boundary lengths kept (u = 0), tangents from k̃, closed by the projection.
  Eigen::VectorXd length(nB);
  for (int i = 0; i < nB; ++i)
    length(i) = (vertex(panel, loop[(i + 1) % nB]) - vertex(panel, loop[i])).norm();
  Eigen::Matrix2Xd T(2, nB);
  double phi = 0.0;
  for (int i = 0; i < nB; ++i) {
    phi += kTilde(i);
    T.col(i) = Eigen::Vector2d(std::cos(phi), std::sin(phi));
  }
  const Eigen::Matrix2d TNT = T * length.asDiagonal() * T.transpose();  // T N⁻¹ Tᵀ
  const Eigen::Vector2d gap = T * length;                               // T l*
  const Eigen::VectorXd closedLength =
      length - length.asDiagonal() * (T.transpose() * TNT.ldlt().solve(gap));
  for (int i = 0; i < nB; ++i)
    if (!(closedLength(i) > 0.0))
      throw SolverError(fmt::format(
          "panel '{}': BFF could not close the boundary curve (boundary edge {} would get "
          "length {:.3g} m); the panel is too curved or badly triangulated",
          name, i, closedLength(i)));

  Eigen::MatrixX2d uv = Eigen::MatrixX2d::Zero(nV, 2);
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  for (int i = 0; i < nB; ++i) {
    uv.row(loop[i]) = p.transpose();
    p += closedLength(i) * T.col(i);
  }
  // Step 6: harmonic extension of both coordinates, A_II x_I = −A_IB γ.
  if (nI > 0) system.scatter(solver.solve(Eigen::MatrixXd(-system.knownPart(uv))), uv);
  // The curve turns counter-clockwise with the surface on its left, so faces keep their
  // orientation; mirror if a badly curved panel came out reversed.
  double signedArea = 0.0;
  for (int f = 0; f < nF; ++f) signedArea += signedFaceArea(uv, panel.F, f);
  if (signedArea < 0.0) uv.col(0) = -uv.col(0);
  return uv;
}

}  // namespace

Eigen::MatrixX2d flattenBff(const TriMesh& panel, const std::string& name,
                            Eigen::VectorXd* logScale) {
  const std::vector<int> loop = checkFlattenablePanel(panel, name);
  return bffImpl(panel, loop, name, logScale);
}

// === Warp/weft refinement

double warpWeftEnergy(const TriMesh& panel, const Eigen::Vector3d& grain,
                      const Eigen::MatrixX2d& uv, double maxShear) {
  const GrainFrames frames = grainFrames(panel, grain);
  const Eigen::MatrixX4d J = grainJacobians(frames, panel.F, uv);
  double energy = 0.0;
  for (int f = 0; f < panel.numFaces(); ++f) {
    const Eigen::Matrix2d Jf = jacobianOf(J, f);
    energy += frames.area(f) * (Jf - warpWeftTarget(Jf, maxShear)).squaredNorm();
  }
  return energy;
}

namespace {

// Boundary edges (i → j) held at target lengths in the refinement, each with its weight.
struct BoundaryTerm {
  std::vector<std::array<int, 2>> edges;
  std::vector<double> length, weight;
  // Weight w_e = w·√A / l_e, so that Σ_e w_e l_e² ε² ≈ w · A · ε²: the edges at strain ε weigh
  // as much as w times the whole area at that strain, at any resolution.
  void add(int i, int j, double targetLength, double w, double sqrtArea) {
    edges.push_back({i, j});
    length.push_back(targetLength);
    weight.push_back(w * sqrtArea / std::max(targetLength, 1e-9));
  }
};

WarpWeftRefinement refineWithBoundary(const TriMesh& panel, const GrainFrames& frames,
                                      const Eigen::MatrixX2d& uv0, const FlattenOptions& options,
                                      const BoundaryTerm& boundary);

}  // namespace

WarpWeftRefinement refineWarpWeft(const TriMesh& panel, const Eigen::Vector3d& grain,
                                  const Eigen::MatrixX2d& uv0, const FlattenOptions& options) {
  const int nV = panel.numVertices();
  if (uv0.rows() != nV)
    throw InputError(
        fmt::format("refineWarpWeft: uv has {} rows, the panel {} vertices", uv0.rows(), nV));
  const GrainFrames frames = grainFrames(panel, grain);
  // Every boundary edge at its 3D length, weighted by boundaryWeight.
  BoundaryTerm boundary;
  const double sqrtArea = std::sqrt(frames.area.sum());
  const MeshTopology topology(panel.F, nV);
  if (options.boundaryWeight > 0.0)
    for (const std::vector<int>& loop : topology.boundaryLoops())
      for (size_t k = 0; k < loop.size(); ++k) {
        const int i = loop[k], j = loop[(k + 1) % loop.size()];
        boundary.add(i, j, (vertex(panel, j) - vertex(panel, i)).norm(), options.boundaryWeight,
                     sqrtArea);
      }
  return refineWithBoundary(panel, frames, uv0, options, boundary);
}

Eigen::MatrixX2d trueBoundaryLengths(const TriMesh& panel, const Eigen::Vector3d& grain,
                                     const Eigen::MatrixX2d& uv0,
                                     const std::vector<BoundaryLengthTarget>& targets,
                                     const FlattenOptions& options, const SeamTruing& truing) {
  const int nV = panel.numVertices();
  if (uv0.rows() != nV)
    throw InputError(
        fmt::format("trueBoundaryLengths: uv has {} rows, the panel {} vertices", uv0.rows(), nV));
  for (const BoundaryLengthTarget& t : targets)
    for (int v : t.vertices)
      if (v < 0 || v >= nV)
        throw InputError(fmt::format("trueBoundaryLengths: vertex {} of a target is not in the "
                                     "panel's {} vertices", v, nV));
  const GrainFrames frames = grainFrames(panel, grain);
  const double sqrtArea = std::sqrt(frames.area.sum());
  auto chainLength = [](const Eigen::MatrixX2d& uv, const std::vector<int>& chain) {
    double l = 0.0;
    for (size_t k = 0; k + 1 < chain.size(); ++k) l += (uv.row(chain[k + 1]) - uv.row(chain[k])).norm();
    return l;
  };
  Eigen::MatrixX2d uv = uv0;
  FlattenOptions local = options;
  local.refineIterations = truing.iterations;
  for (int round = 0; round < truing.rounds; ++round) {
    double worst = 0.0;
    BoundaryTerm boundary;
    for (const BoundaryLengthTarget& t : targets) {
      const double current = chainLength(uv, t.vertices);
      worst = std::max(worst, std::abs(current - t.length));
      // Every edge of the chain scaled by the same factor: the chain keeps its shape and
      // takes the target length; the rest of the panel follows by the strain energy.
      const double scale = current > 0.0 ? t.length / current : 1.0;
      for (size_t k = 0; k + 1 < t.vertices.size(); ++k) {
        const int i = t.vertices[k], j = t.vertices[k + 1];
        boundary.add(i, j, scale * (uv.row(j) - uv.row(i)).norm(), truing.weight, sqrtArea);
      }
    }
    if (worst <= truing.tolerance || boundary.edges.empty()) break;
    uv = refineWithBoundary(panel, frames, uv, local, boundary).uv;
  }
  return uv;
}

namespace {

WarpWeftRefinement refineWithBoundary(const TriMesh& panel, const GrainFrames& frames,
                                      const Eigen::MatrixX2d& uv0, const FlattenOptions& options,
                                      const BoundaryTerm& boundary) {
  const int nV = panel.numVertices(), nF = panel.numFaces();
  WarpWeftRefinement result;
  result.uv = uv0;
  if (nV < 2) return result;
  const std::vector<std::array<int, 2>>& bEdges = boundary.edges;
  const std::vector<double>& bLength = boundary.length;
  const std::vector<double>& bWeight = boundary.weight;

  // Global step matrix: the 3D cotan Laplacian (Σ A_f ∇φ_i·∇φ_j) plus the boundary edges'
  // graph Laplacian Σ w_e (e_i − e_j)(e_i − e_j)ᵀ, vertex `pinned` removed; factored once.
  const int pinned = 0;
  std::vector<Eigen::Triplet<double>> triplets;
  {
    const Eigen::SparseMatrix<double> L = cotanLaplacian(panel);
    triplets.reserve(L.nonZeros() + 4 * bEdges.size());
    for (int c = 0; c < L.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(L, c); it; ++it)
        triplets.emplace_back(static_cast<int>(it.row()), c, it.value());
    for (size_t e = 0; e < bEdges.size(); ++e) {
      const auto [i, j] = bEdges[e];
      triplets.emplace_back(i, i, bWeight[e]);
      triplets.emplace_back(j, j, bWeight[e]);
      triplets.emplace_back(i, j, -bWeight[e]);
      triplets.emplace_back(j, i, -bWeight[e]);
    }
  }
  Eigen::SparseMatrix<double> A(nV, nV);
  A.setFromTriplets(triplets.begin(), triplets.end());
  std::vector<char> isPinned(nV, 0);
  isPinned[pinned] = 1;
  const ReducedSystem system(A, isPinned);
  SpdSolver solver;
  solver.compute(system.freeBlock());

  Eigen::MatrixX4d J = grainJacobians(frames, panel.F, result.uv);
  std::vector<Eigen::Matrix2d> target(nF);
  std::vector<Eigen::Vector2d> edgeTarget(bEdges.size());
  // Local step: the targets of every face and boundary edge (the edge's current direction at
  // its 3D length); returns the area energy and, in total, area + boundary energy.
  auto localStep = [&](double& total) {
    std::vector<double> faceEnergy(nF);
    tbb::parallel_for(0, nF, [&](int f) {
      const Eigen::Matrix2d Jf = jacobianOf(J, f);
      target[f] = warpWeftTarget(Jf, options.maxShear);
      faceEnergy[f] = frames.area(f) * (Jf - target[f]).squaredNorm();
    });
    double e = 0.0;
    for (double x : faceEnergy) e += x;
    total = e;
    for (size_t k = 0; k < bEdges.size(); ++k) {
      const Eigen::Vector2d d =
          (result.uv.row(bEdges[k][1]) - result.uv.row(bEdges[k][0])).transpose();
      edgeTarget[k] = d.norm() > 0.0 ? Eigen::Vector2d(bLength[k] * d.normalized())
                                     : Eigen::Vector2d(bLength[k], 0.0);
      total += bWeight[k] * (d - edgeTarget[k]).squaredNorm();
    }
    return e;
  };
  double energy = 0.0;
  result.energyStart = localStep(energy);
  int inverted = countInvertedFaces(result.uv, panel.F);
  result.energyEnd = result.energyStart;
  Eigen::MatrixX2d rhs(nV, 2);
  for (int iter = 0; iter < options.refineIterations; ++iter) {
    // Global step: A uv = Σ_f A_f T_f ∇φ_i + Σ_e w_e (±t_e), vertex `pinned` held in place.
    rhs.setZero();
    for (int f = 0; f < nF; ++f)
      for (int i = 0; i < 3; ++i) {
        const Eigen::Vector2d g(frames.gradients(f, 2 * i), frames.gradients(f, 2 * i + 1));
        rhs.row(panel.F(f, i)) += frames.area(f) * (target[f] * g).transpose();
      }
    for (size_t k = 0; k < bEdges.size(); ++k) {
      rhs.row(bEdges[k][1]) += bWeight[k] * edgeTarget[k].transpose();
      rhs.row(bEdges[k][0]) -= bWeight[k] * edgeTarget[k].transpose();
    }
    Eigen::MatrixX2d next = result.uv;  // the pinned vertex stays
    system.scatter(solver.solve(system.rhs(rhs, result.uv)), next);
    ++result.iterations;
    // A step that inverts more faces than the current iterate has (none, from a flip-free
    // start) is shortened (uv + t(next − uv), t = ½, ¼, ...); when no shortened step will do,
    // the current iterate is kept.
    int nextInverted = countInvertedFaces(next, panel.F);
    if (nextInverted > inverted) {
      // A sliver the step folded is opened again in place (flip_repair.h) before the step is
      // shortened: a panel whose truing folds one face would otherwise stop where it is.
      repairFlips(next, panel.F, frames.area);
      nextInverted = countInvertedFaces(next, panel.F);
    }
    for (int halving = 0; nextInverted > inverted && halving < 6; ++halving) {
      next = 0.5 * (result.uv + next);
      nextInverted = countInvertedFaces(next, panel.F);
    }
    if (nextInverted > inverted) {
      ++result.rejectedIterations;
      break;
    }
    result.uv = next;
    inverted = nextInverted;
    J = grainJacobians(frames, panel.F, result.uv);
    double nextEnergy = 0.0;
    result.energyEnd = localStep(nextEnergy);
    const double decrease = energy - nextEnergy;
    energy = nextEnergy;
    if (!(decrease > options.tolerance * std::max(energy, 1e-300))) break;
  }
  return result;
}

}  // namespace

// close_to_skin's shorts: one vertex thrown 21 mm out for 0.4 mm of cloth, a needle the outline
// fit turned into a self-crossing, and the panel was lost.
int pullInBoundarySpikes(const TriMesh& panel, const std::vector<int>& boundary,
                         Eigen::MatrixX2d& uv) {
  constexpr double kSpikeRatio = 4.0;
  constexpr double kSpikeExcess = 0.002;  // m
  double orientation = 0;  // the side the panel's faces turn to in 2D
  for (int f = 0; f < panel.numFaces(); ++f) orientation += signedFaceArea(uv, panel.F, f);
  const double sigma = orientation < 0 ? -1.0 : 1.0;
  std::vector<std::vector<int>> facesOf(static_cast<size_t>(panel.numVertices()));
  for (int f = 0; f < panel.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) facesOf[panel.F(f, k)].push_back(f);
  // A spike's neighbours have one long edge (to it), the spike has most of its edges long: the
  // vertex whose edges are stretched most on average goes first, then the rest are looked at
  // again with it in place.
  const auto score = [&](int v) {
    bool spike = false;
    double sum = 0;
    int n = 0;
    for (int f : facesOf[v])
      for (int k = 0; k < 3; ++k) {
        const int w = panel.F(f, k);
        if (w == v) continue;
        const double l3 = (panel.V.row(v) - panel.V.row(w)).norm();
        const double l2 = (uv.row(v) - uv.row(w)).norm();
        if (l2 > kSpikeRatio * l3 && l2 - l3 > kSpikeExcess) spike = true;
        sum += l3 > 0 && l2 > l3 ? std::log(l2 / l3) : 0.0;
        ++n;
      }
    return spike && n > 0 ? sum / n : -1.0;
  };
  std::vector<char> done(static_cast<size_t>(panel.numVertices()), 0);
  int moved = 0;
  for (size_t round = 0; round < boundary.size(); ++round) {
    int v = -1;
    double worst = 0;
    for (int b : boundary)
      if (!done[b])
        if (const double s = score(b); s > worst) worst = s, v = b;
    if (v < 0) break;
    done[v] = 1;  // each vertex is put back at most once
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    int n = 0;
    for (int f : facesOf[v]) {
      int k = 0;
      while (panel.F(f, k) != v) ++k;
      const int a = panel.F(f, (k + 1) % 3), b = panel.F(f, (k + 2) % 3);  // v, a, b in order
      const Eigen::Vector2d A = uv.row(a), B = uv.row(b);
      const double d = (B - A).norm();
      const double d3 = (panel.V.row(a) - panel.V.row(b)).norm();
      if (!(d > 0) || !(d3 > 0)) continue;
      const double scale = d / d3;
      const double ra = scale * (panel.V.row(v) - panel.V.row(a)).norm();
      const double rb = scale * (panel.V.row(v) - panel.V.row(b)).norm();
      const Eigen::Vector2d u = (B - A) / d;
      const Eigen::Vector2d left(-u.y(), u.x());
      const double x = (ra * ra - rb * rb + d * d) / (2 * d);
      const double h = std::sqrt(std::max(0.0, ra * ra - x * x));
      // v, a, b turn the panel's way: v lies on that side of a → b.
      sum += A + x * u + sigma * h * left;
      ++n;
    }
    if (n == 0) continue;
    uv.row(v) = (sum / n).transpose();
    ++moved;
  }
  return moved;
}

// === Grain alignment

Eigen::MatrixX2d alignToGrain(const TriMesh& panel, const Eigen::Vector3d& grain,
                              const Eigen::MatrixX2d& uv) {
  const GrainFrames frames = grainFrames(panel, grain);
  const Eigen::MatrixX4d J = grainJacobians(frames, panel.F, uv);
  Eigen::Vector2d warp = Eigen::Vector2d::Zero(), centroid = Eigen::Vector2d::Zero();
  double area = 0.0;
  for (int f = 0; f < panel.numFaces(); ++f) {
    warp += frames.area(f) * Eigen::Vector2d(J(f, 0), J(f, 1));
    const double a = std::abs(signedFaceArea(uv, panel.F, f));
    for (int k = 0; k < 3; ++k) centroid += (a / 3.0) * uv.row(panel.F(f, k)).transpose();
    area += a;
  }
  if (area > 0.0) centroid /= area;
  // Rotation taking `warp` to +y.
  const double angle = warp.norm() > 0.0 ? 0.5 * kPi - std::atan2(warp.y(), warp.x()) : 0.0;
  const Eigen::Matrix2d R = Eigen::Rotation2Dd(angle).toRotationMatrix();
  Eigen::MatrixX2d out(uv.rows(), 2);
  for (int v = 0; v < uv.rows(); ++v)
    out.row(v) = (R * (uv.row(v).transpose() - centroid)).transpose();
  return out;
}

// === The whole flattening

PanelFlattening flattenPanel(const TriMesh& panel, const Eigen::Vector3d& grain,
                             const std::string& name, const FlattenOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (!grain.allFinite() || grain.norm() == 0.0)
    throw InputError(
        fmt::format("panel '{}': the grain ({}, {}, {}) must be a finite non-zero "
                    "vector (the panel's vertical)",
                    name, grain.x(), grain.y(), grain.z()));
  if (options.refineIterations < 0 || !(options.maxShear >= 0.0 && options.maxShear < 0.5 * kPi))
    throw InputError(
        fmt::format("panel '{}': FlattenOptions need refineIterations ≥ 0 and "
                    "maxShear in [0, π/2) (got {} and {})",
                    name, options.refineIterations, options.maxShear));
  PanelFlattening out;
  out.boundary = checkFlattenablePanel(panel, name);
  Eigen::MatrixX2d uv = bffImpl(panel, out.boundary, name, &out.logScale);
  // BFF's harmonic extension can fold slivers (negative cotan weights); the refinement only
  // keeps what it starts from, so it starts flip-free.
  out.bffInvertedFaces = repairFlips(uv, panel.F, faceAreas(panel)).invertedBefore;
  out.boundarySpikes = pullInBoundarySpikes(panel, out.boundary, uv);
  out.energyBff = warpWeftEnergy(panel, grain, uv, options.maxShear);
  out.energy = out.energyBff;
  out.uvBff = options.alignGrain ? alignToGrain(panel, grain, uv) : uv;
  if (options.refine && options.refineIterations > 0) {
    WarpWeftRefinement refined = refineWarpWeft(panel, grain, out.uvBff, options);
    out.boundarySpikes += pullInBoundarySpikes(panel, out.boundary, refined.uv);
    out.energy = refined.energyEnd;
    out.iterations = refined.iterations;
    out.rejectedIterations = refined.rejectedIterations;
    out.uv = options.alignGrain ? alignToGrain(panel, grain, refined.uv) : refined.uv;
    // The refinement moves the boundary freely; a boundary that comes to overlap itself is
    // not a pattern, so BFF's is kept then (BFF's own curve is checked by the caller).
    if (polygonSelfIntersects(out.uv, out.boundary) &&
        !polygonSelfIntersects(out.uvBff, out.boundary)) {
      out.uv = out.uvBff;
      out.energy = out.energyBff;
      out.refinementReverted = true;
    }
  } else {
    out.uv = out.uvBff;
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

std::vector<PanelFlatteningOutcome> flattenPanels(const std::vector<PanelToFlatten>& panels,
                                                  const FlattenOptions& options) {
  std::vector<PanelFlatteningOutcome> outcomes(panels.size());
  tbb::parallel_for(size_t{0}, panels.size(), [&](size_t i) {
    const PanelToFlatten& p = panels[i];
    try {
      if (!p.mesh) throw InputError(fmt::format("panel '{}': no mesh given", p.name));
      outcomes[i].flattening = flattenPanel(*p.mesh, p.grain, p.name, options);
    } catch (const Error& e) {
      outcomes[i].error = e.what();
      outcomes[i].errorCode = e.exitCode();
    }
  });
  return outcomes;
}

}  // namespace s2p
