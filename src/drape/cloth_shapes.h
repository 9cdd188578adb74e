// Garments and bodies built in code, with known answers: for the drape tests, the bench and the
// demo (as core/shapes.h is for meshes).
#pragma once

#include <Eigen/Core>
#include <functional>
#include <string>

#include "drape/cloth.h"

namespace s2p {

// A panel cut from a regular grid of nx×ny square-ish cells on [0, sx]×[0, sy] (each cell two
// triangles), keeping the cells where keep(i, j) is true (all when empty), placed in 3D at
// origin + u·xAxis + v·yAxis for its flat (u, v). flip reverses the faces' orientation (a back
// panel facing −Z).
struct GridPanel {
  ClothPanel panel;
  Eigen::MatrixXi index;  // (nx+1)×(ny+1): panel vertex of grid point (i, j), −1 when cut away
};
GridPanel makeGridPanel(const std::string& name, int nx, int ny, double sx, double sy,
                        const Eigen::Vector3d& origin, const Eigen::Vector3d& xAxis,
                        const Eigen::Vector3d& yAxis, bool flip,
                        const std::function<bool(int, int)>& keep = {});

// Closed cylinder around the y axis from y0 to y1 (side in rings×segments quads, both caps as
// fans): outward normals, watertight.
TriMesh makeClosedCylinder(double radius, double y0, double y1, int rings, int segments);

// Two rectangles, width × height each (metres) at about `edge` spacing, facing each other at
// z = ±distance, stitched along both vertical sides: sewn, a tube of circumference 2·width.
// The body is a closed cylinder of radius bodyRadius inside. Panel 0 is the front.
DrapeInput makeTubeGarment(double width, double height, double edge, double distance,
                           double bodyRadius);

// A shirt-like garment of two T-shaped panels (torso 0.6 × 0.7 m, sleeves 0.25 × 0.2 m) around
// a body-sized closed cylinder (radius 0.15 m, height 0.75 m): side, underarm and shoulder
// seams, open hem, neck and cuffs. About `edge` spacing.
DrapeInput makeShirtGarment(double edge);

}  // namespace s2p
