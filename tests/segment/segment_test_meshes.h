// Meshes for the segment tests that src/core/shapes.h does not make.
#pragma once

#include "core/tri_mesh.h"

namespace s2p::testing {

// A closed "pair of trousers": a vertical trunk capsule (axis x = z = 0, y from 0.55 to 1.0,
// radius 0.13) smoothly joined to two leg capsules (axes x = ±0.075, y from 0.05 to 0.62,
// radius 0.055), meshed from its signed distance with OpenVDB at `voxel` metres. The fork
// (crotch) is at y ≈ 0.43; above y ≈ 0.6 every horizontal section is one loop, below the
// crotch two.
TriMesh makeTrousers(double voxel = 0.01);

}  // namespace s2p::testing
