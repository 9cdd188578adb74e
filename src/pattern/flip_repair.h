// Repair of inverted triangles in a flattening.
//
// BFF's harmonic extension is not guaranteed to be flip-free: a sliver left by an exact cut has
// an angle near 180°, a negative cotan weight, and its vertex can be carried across its
// neighbours. The warp/weft refinement then keeps the inversion (it refuses steps that add
// inversions, and a fold is a local minimum of its energy). A pattern with a folded triangle
// cannot be remeshed or mapped back onto the scan, so each vertex of an inverted face is moved,
// one at a time, to the point closest to where it is at which every face around it has positive
// area: the closest point of its one-ring's kernel (shrunk by a margin), a 2D quadratic
// programme with a handful of half-plane constraints, solved exactly by enumerating the
// candidates (the point itself, its projection on each constraint line, each pair's
// intersection). Moving a vertex changes its own faces only, and leaves all of them positive,
// so the count of inverted faces never grows; a vertex whose kernel is empty (its one-ring is
// itself tangled) is tried again after its neighbours have moved, and the set of vertices
// allowed to move grows ring by ring until no face is inverted or the rings run out.
#pragma once

#include <Eigen/Core>

namespace s2p {

struct FlipRepairOptions {
  // A repaired face gets at least this fraction of the 2D area its 3D area stands for (the
  // panel's 2D/3D area ratio × its 3D area, floored at 1 % of the mean face): slivers come out
  // thin but not numerically zero, so the next step of an iteration does not flip them back.
  double areaMargin = 0.05;
  int maxRings = 4;    // the movable set grows by one ring of neighbours this many times
  int maxPasses = 20;  // Gauss–Seidel passes per ring
};

struct FlipRepairResult {
  int invertedBefore = 0;
  int invertedAfter = 0;
  int verticesMoved = 0;
};

// Signed area of face f in uv (positive: counter-clockwise).
double signedFaceArea(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& F, int f);

// Faces of F whose signed area in uv is not positive.
int countInvertedFaces(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& F);

// Moves vertices of uv (#V×2) so that the faces F (#F×3, counter-clockwise when not inverted)
// stop being inverted, as described above. area3d: #F, each face's 3D area (the margin's
// scale). Vertices of faces that are not inverted and not near one do not move.
FlipRepairResult repairFlips(Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& F,
                             const Eigen::VectorXd& area3d, const FlipRepairOptions& options = {});

}  // namespace s2p
