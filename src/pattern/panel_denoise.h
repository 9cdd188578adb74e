// Scan noise taken out of a 3D panel before it is flattened. A scanner's positional noise
// (σ ≈ 1–2 mm per vertex) wrinkles the surface at the scale of its edges: every 3D edge comes
// out longer than the cloth it samples (by ½⟨slope²⟩, 2–4 % at 1.5 mm noise on 7 mm edges),
// and a flattening that keeps those lengths makes the pattern that much too big and its strain
// figures measure the noise. The filter is the bi-Laplacian smoothing
//   (M + h⁴ L M⁻¹ L) x = M x₀        (M lumped mass, L cotan Laplacian, h the filter length)
// whose response 1/(1 + (hk)⁴) removes wavelengths below ~2πh and leaves the garment's shape:
// unlike Laplacian smoothing it does not shrink a cylinder (L M⁻¹ L of a cylinder's positions is
// O(h⁴/r⁴), 10⁻⁴ of a 5 cm radius at h = 5 mm). The boundary is filtered first, each chain
// between two corners as a curve with its ends fixed (1D operator, same response), so the two
// sides of a seam, which share their vertices, stay one curve; the interior is then solved with
// the boundary fixed. The smoothness energy Σ|Lx|²/m is summed over each curve's and the
// surface's inner vertices only: a rim vertex's one-sided Laplacian points into the panel and
// is no curvature (counted, it pulled a clean cylinder's rim in by 0.4 mm).
// At 1.5 mm of noise on 7 mm edges the flattened area is 7.7 % too big unfiltered, 0.8 % at
// h = 5 mm (3.9 % at 3 mm); on the suite the filter moved vertices by 0.5–1.3 mm on average.
#pragma once

#include <vector>

#include "core/tri_mesh.h"

namespace s2p {

struct PanelDenoiseOptions {
  double scale = 0.005;  // metres: the filter length h (0: off)
};

// The panel with the same faces and its vertices filtered as above. loop: the boundary loop
// (vertex ids, in order); corners: the loop's vertices that stay fixed (seam ends; none: the
// loop is filtered as a closed curve). Returns the panel unchanged when scale is 0.
// Throws InputError for non-finite coordinates or a negative scale, SolverError if the solve
// fails.
TriMesh denoisePanel(const TriMesh& panel, const std::vector<int>& loop,
                     const std::vector<int>& corners, const PanelDenoiseOptions& options = {});

}  // namespace s2p
