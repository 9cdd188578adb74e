// The zero isosurface of an OpenVDB level set as a triangle mesh (used by the mannequin, the
// synthetic scans and test shapes): OpenVDB's volumeToMesh, its quads split along the shorter
// diagonal. Points are in the grid's world space.
#pragma once

#include <openvdb/openvdb.h>

#include "core/tri_mesh.h"

namespace s2p {

TriMesh levelSetToMesh(const openvdb::FloatGrid& grid, double isoValue = 0.0);

}  // namespace s2p
