// The zero isosurface of an OpenVDB level set as a triangle mesh (used by the mannequin, the
// synthetic scans and test shapes): OpenVDB's volumeToMesh, its quads split along the shorter
// diagonal. Points are in the grid's world space.
#pragma once

#include <openvdb/openvdb.h>

#include <functional>

#include "core/tri_mesh.h"

namespace s2p {

TriMesh levelSetToMesh(const openvdb::FloatGrid& grid, double isoValue = 0.0);

// The zero set of f (negative inside, a distance near the surface) sampled every `voxel` metres
// on the box from lo to lo + size, meshed and oriented outward (positive enclosed volume). For
// test shapes and other small implicit solids (the mannequin samples its own in parallel).
TriMesh meshImplicit(const std::function<double(const Eigen::Vector3d&)>& f,
                     const Eigen::Vector3d& lo, const Eigen::Vector3d& size, double voxel);

}  // namespace s2p
