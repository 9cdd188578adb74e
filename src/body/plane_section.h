// Mesh ∩ plane as polylines, and the tape-measure length around such a section: the tools a
// body measurement is taken with (body/measurements.h).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/tri_mesh.h"

namespace s2p {

// === Sections

// One connected piece of a plane section.
struct SectionLoop {
  Eigen::MatrixX3d points;  // #P×3, in order along the curve; a closed loop does not repeat
                            // its first point at the end
  bool closed = false;      // false where the curve runs into a mesh boundary
};

// Intersection of the mesh with the plane through `point` with normal `normal` (any length
// but zero): one polyline per connected piece, each point on a mesh edge. Vertices exactly on
// the plane count as lying on its positive side, so every crossing is a proper edge crossing
// and the pieces are simple. Throws InputError on an invalid mesh or a zero / non-finite
// plane.
std::vector<SectionLoop> planeSection(const TriMesh& mesh, const Eigen::Vector3d& point,
                                      const Eigen::Vector3d& normal);

// The same for many planes through one mesh: validates the mesh and builds its edge table
// once (a body measurement takes ~100 sections). Keeps a reference to the mesh.
class MeshSlicer {
 public:
  explicit MeshSlicer(const TriMesh& mesh);  // throws InputError on an invalid mesh
  std::vector<SectionLoop> section(const Eigen::Vector3d& point,
                                   const Eigen::Vector3d& normal) const;
  const TriMesh& mesh() const { return mesh_; }

 private:
  int numBins() const { return static_cast<int>(binStart_.size()) - 1; }

  const TriMesh& mesh_;
  Eigen::MatrixX2i edges_;     // #E×2 undirected edges, smaller index first
  Eigen::MatrixX3i faceEdge_;  // #F×3, edge k joins corners k and k+1
  // Faces by height bin (CSR) for horizontal planes, the common case of body measurements.
  double yMin_ = 0, yMax_ = 0, binHeight_ = 0;
  std::vector<int> binStart_;  // #bins+1, empty when the mesh is flat in y
  std::vector<int> binFaces_;
};

// === Measuring a section

// Perimeter of the convex hull of the loop's points projected on the plane ⟂ `normal`: what
// a tape measure laid around the section reads (it bridges concavities). 0 for < 2 points.
double convexHullPerimeter(const SectionLoop& loop, const Eigen::Vector3d& normal);

// Length of the polyline itself (closing segment included when closed).
double polylineLength(const SectionLoop& loop);

// Area enclosed by a closed loop, projected on the plane ⟂ `normal` (absolute value).
double enclosedArea(const SectionLoop& loop, const Eigen::Vector3d& normal);

// True when the closed loop, projected on the plane ⟂ `normal`, winds around `point`
// (projected too; even-odd rule). Always false for an open loop.
bool loopEncloses(const SectionLoop& loop, const Eigen::Vector3d& point,
                  const Eigen::Vector3d& normal);

// Distance from `point` to the nearest segment of the loop, in 3D.
double distanceToLoop(const SectionLoop& loop, const Eigen::Vector3d& point);

}  // namespace s2p
