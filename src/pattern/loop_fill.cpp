#include "pattern/loop_fill.h"

#include <fmt/format.h>

#include <Eigen/SparseCholesky>

#include "core/error.h"
#include "core/laplacian.h"
#include "core/tri_mesh.h"
#include "pattern/remesh.h"

namespace s2p {

std::optional<LoopFill> fillLoop(const std::vector<Eigen::Vector3d>& outline, double spacing,
                                 std::string* why) {
  using Vec3 = Eigen::Vector3d;
  const auto fail = [&](const std::string& reason) -> std::optional<LoopFill> {
    if (why) *why = reason;
    return std::nullopt;
  };
  const int nB = static_cast<int>(outline.size());
  if (nB < 3) return fail("the loop has fewer than 3 points");
  const FittedPlane plane = fitPlane(outline);
  const Vec3 centre = plane.centre, n = plane.axes.col(0), u = plane.axes.col(2),
             w = plane.axes.col(1);
  // remeshPanel takes the outline as edges that join up: the loop's two halves.
  const int half = nB / 2;
  Eigen::MatrixX2d e0(half + 1, 2), e1(nB - half + 1, 2);
  for (int i = 0; i <= nB; ++i) {
    const Vec3 d = outline[i % nB] - centre;
    const Eigen::RowVector2d q(d.dot(u), d.dot(w));
    if (i <= half) e0.row(i) = q;
    if (i >= half) e1.row(i - half) = q;
  }
  RemeshedPanel m;
  try {
    RemeshOptions ro;
    ro.targetEdgeLength = spacing;
    ro.repairBadFaces = false;  // a surface to cut seams on, not a simulation mesh
    m = remeshPanel({e0, e1}, "loop", ro);
  } catch (const Error& e) {
    return fail(fmt::format("it does not lie flat on a plane ({})", e.what()));
  }
  std::vector<int> ids(m.edgeVertices[0].begin(), m.edgeVertices[0].end());
  ids.insert(ids.end(), m.edgeVertices[1].begin() + 1, m.edgeVertices[1].end() - 1);
  if (static_cast<int>(ids.size()) != nB || m.boundarySteinerPoints > 0)
    return fail("the mesher changed the loop");
  // Renumber: the outline first, then the inside.
  const int nV = static_cast<int>(m.V.rows());
  std::vector<int> order(nV, -1);
  for (int i = 0; i < nB; ++i) order[ids[i]] = i;
  int next = nB;
  for (int v = 0; v < nV; ++v)
    if (order[v] < 0) order[v] = next++;
  LoopFill fill;
  fill.normal = n;
  fill.F.resize(m.F.rows(), 3);
  for (int f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k) fill.F(f, k) = order[m.F(f, k)];
  TriMesh flat;
  flat.V = Eigen::MatrixX3d::Zero(nV, 3);
  for (int v = 0; v < nV; ++v) flat.V.row(order[v]).head<2>() = m.V.row(v);
  flat.F = fill.F;
  // Off the plane: harmonic in the outline's heights. The bump: Δb = −1, 0 on the outline.
  Eigen::VectorXd height = Eigen::VectorXd::Zero(nV), bump = Eigen::VectorXd::Zero(nV);
  for (int i = 0; i < nB; ++i) height[i] = (outline[i] - centre).dot(n);
  const int nI = nV - nB;
  if (nI > 0) {
    const Eigen::SparseMatrix<double> L = cotanLaplacian(flat, 1e3);
    const Eigen::VectorXd area = vertexAreas(flat);
    const Eigen::SparseMatrix<double> Lii = L.bottomRightCorner(nI, nI);
    const Eigen::SparseMatrix<double> Lib = L.bottomLeftCorner(nI, nB);
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(Lii);
    if (solver.info() != Eigen::Success) return fail("its membrane could not be solved");
    height.tail(nI) = solver.solve(-(Lib * height.head(nB)));
    bump.tail(nI) = solver.solve(area.tail(nI));
    if (bump.maxCoeff() > 0) bump /= bump.maxCoeff();
  }
  fill.V.resize(nV, 3);
  for (int v = 0; v < nV; ++v)
    fill.V.row(v) = centre.transpose() + flat.V(v, 0) * u.transpose() +
                    flat.V(v, 1) * w.transpose() + height[v] * n.transpose();
  for (int i = 0; i < nB; ++i) fill.V.row(i) = outline[i].transpose();  // exactly
  fill.bump = bump.cwiseMax(0.0);
  return fill;
}

}  // namespace s2p
