// Facing direction of a standing person about the vertical (paper §3 assumes a scan facing +Z;
// ours may be turned by any angle). Geometry only: the lateral axis from the shape of the
// torso (a body is wider than deep), its sign from robust cues voting together (the feet point
// forward of their own shins, the nose and chest stick out in front, the buttocks behind).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "core/tri_mesh.h"

namespace s2p {

struct OrientationCue {
  std::string name;  // "feet", "nose", "chest", "buttocks"
  double vote = 0;   // signed support for the chosen facing, in metres of asymmetry
};

struct Orientation {
  Eigen::Vector3d facing = Eigen::Vector3d::UnitZ();  // unit, horizontal: where the person looks
  double yaw = 0;                                     // radians: yawRotation(yaw) · facing = +Z
  double confidence = 0;  // in [0, 1]: agreement of the cues times the torso's anisotropy
  std::vector<OrientationCue> cues;
};

struct OrientationOptions {
  double minHeight = 0.5, maxHeight = 2.6;  // metres: plausible person heights
  int minVertices = 100;                    // fewer: not a scan of a person
};

// Finds where a scan (metres, +Y up) faces. Throws InputError for a mesh too small or not
// person-sized, a person lying down (the vertical is not the main axis), a shape that is not
// elongated vertically (a sphere, a blob) or a person upside down (the wide, two-footed end
// at the top, most of the surface below mid-height).
Orientation estimateOrientation(const TriMesh& scan, const OrientationOptions& options = {});

// Rotation about +Y by `yaw` radians (right-handed).
Eigen::Matrix3d yawRotation(double yaw);
// Rotation by `yaw` about the vertical axis through the bounding-box centre (x, z) of `mesh`.
Eigen::Affine3d turnAboutVertical(const TriMesh& mesh, double yaw);
// The mesh turned by turnAboutVertical(mesh, yaw).
TriMesh rotateAboutVertical(const TriMesh& mesh, double yaw);

}  // namespace s2p
