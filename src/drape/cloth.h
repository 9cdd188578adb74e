// What the drape simulator consumes: the pattern's panels (flat rest shape + initial 3D
// placement), the stitches that sew them and the body they are draped on. Plain data.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/tri_mesh.h"

namespace s2p {

// One pattern piece as cloth: its flat shape is the rest state of stretch and shear (and of
// bending: flat), `start` its placement around the body, in the same vertex order.
struct ClothPanel {
  std::string name;
  Eigen::MatrixX2d rest2d;  // #V×2, metres: the flat pattern (panels_flat.obj)
  Eigen::MatrixX3d start;   // #V×3, metres: initial placement around the body (panels.obj)
  Eigen::MatrixX3i F;       // #F×3 vertex indices (either orientation)
  // Garments worn over others: a panel of a higher layer lies outside every panel of a lower
  // one (a shirt worn over the trousers' waistband). Equal layers: no order is known.
  int layer = 0;

  int numVertices() const { return static_cast<int>(rest2d.rows()); }
  int numFaces() const { return static_cast<int>(F.rows()); }
};

// Sew vertex `vertexA` of panel `panelA` to vertex `vertexB` of panel `panelB` (indices into
// DrapeInput::panels and each panel's vertices). A panel may be sewn to itself (a dart, a
// sleeve's underarm seam). One vertex pair of a seam (pattern/placement.h's Stitch is the seam).
struct ClothStitch {
  int panelA = -1;
  int vertexA = -1;
  int panelB = -1;
  int vertexB = -1;
};

struct DrapeInput {
  std::vector<ClothPanel> panels;
  std::vector<ClothStitch> stitches;
  TriMesh body;  // closed, metres, +Y up, facing +Z (body_rest.obj)
};

}  // namespace s2p
