// Completion of an occluded garment (§5.3, Fig. 10): the part of a garment hidden under the
// other one is cut along the initial waist boundary, so it is a copy of the outer garment's
// surface. A biharmonic deformation (Jacobson et al. 2010, the paper's [JTSZ10]) pulls its cut
// rim onto the body while the visible part keeps its place, so the hidden band shrinks smoothly
// towards the body under the outer garment.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/tri_mesh.h"

namespace s2p {

// Displacements d minimise ∫|Δd|² dA (cotan L, lumped M: dᵀ L M⁻¹ L d per coordinate) with
// d = rimTargets − V on the `rim` vertices and d = 0 on the `fixed` ones (#V flags); every other
// vertex is free. Returns the deformed vertices (#V×3). Throws InputError for an invalid mesh,
// sizes that do not match, a rim vertex that is also fixed, or non-finite targets.
Eigen::MatrixX3d biharmonicDeformation(const TriMesh& mesh, const std::vector<int>& rim,
                                       const Eigen::MatrixX3d& rimTargets,
                                       const std::vector<bool>& fixed);

}  // namespace s2p
