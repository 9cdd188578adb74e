// The paper's seven views (§4; research note E §4, from the authors' Photographer code): pinhole
// cameras on a horizontal circle around the scan, flat grey Lambert renders without texture,
// for OpenPose to detect BODY_25 keypoints and triangulate them in 3D (its --3d mode), the
// result being read back by readKeypoints (keypoints.h).
//
// Camera convention (OpenCV, as OpenPose reads it): p_cam = R·p + t with camera x to the image's
// right, y down, z forward; pixel = (K·p_cam) / z_cam with integer pixel coordinates at pixel
// centres, (0, 0) the centre of the top-left pixel.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/tri_mesh.h"
#include "io/scan.h"

namespace s2p {

struct PinholeCamera {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();  // intrinsics, pixels, upper triangular
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // world → camera rotation
  Eigen::Vector3d t = Eigen::Vector3d::Zero();      // world → camera translation
  int width = 0, height = 0;                        // pixels

  Eigen::Vector3d toCamera(const Eigen::Vector3d& p) const { return R * p + t; }
  // Pixel coordinates of a world point in front of the camera (z_cam > 0).
  Eigen::Vector2d project(const Eigen::Vector3d& p) const;
  Eigen::Vector3d centre() const { return -R.transpose() * t; }  // camera position, world
};

struct CameraRigOptions {
  int numViews = 7;                // cameras evenly spaced on the circle
  double firstAngle = 0.2;         // radians about +Y; angle 0 puts the camera on +Z (front)
  double distance = 4.5;           // metres from the scan's bounding-box centre
  int width = 800, height = 600;   // pixels, each in [16, 8192]
  double verticalFovDegrees = 35;  // in (1, 170)
  int supersample = 2;             // samples per pixel along each axis, in [1, 4]
  std::uint8_t background = 255;   // grey level of empty pixels
  std::uint8_t surface = 200;      // grey level of a surface lit head-on (Lambert, headlight)
  double ambient = 0.25;           // fraction of `surface` on a surface seen edge-on, in [0, 1]
};

// The rig's cameras in the scan's normalised frame (metres, +Y up) around `target`: camera k at
// angle a_k = firstAngle + 2πk/numViews sits at target + distance·(sin a_k, 0, cos a_k), looks
// at `target` with the image's up along +Y. Throws InputError on out-of-range options.
std::vector<PinholeCamera> cameraRig(const Eigen::Vector3d& target,
                                     const CameraRigOptions& options);

// Renders `mesh` through `camera` (z-buffer, perspective-correct, smooth normals, two-sided
// Lambert with a headlight): width×height grey RGB pixels. Faces with a corner closer than 1 cm
// to the camera plane (or behind it) are skipped. Deterministic. InputError on an invalid mesh.
Image renderPinhole(const TriMesh& mesh, const PinholeCamera& camera,
                    const CameraRigOptions& options = {});

struct CameraView {
  PinholeCamera camera;  // normalised frame (metres, +Y up)
  Image image;
};

// The paper's seven views of a normalised scan (the rig around its bounding-box centre).
std::vector<CameraView> renderCameraViews(const Scan& scan, const CameraRigOptions& options = {});

// The camera in the scan FILE's frame: for p_file = toInputFrame·p it projects p_file to the
// pixel `camera` projects p to. toInputFrame must be a similarity (rotation and uniform scale,
// as normalizeScan makes); t is then in file units. InputError otherwise.
PinholeCamera cameraInFileFrame(const PinholeCamera& camera, const Eigen::Affine3d& toInputFrame);

// {"width", "height", "K" (3×3 rows), "R" (3×3 rows), "t" (3), "centre" (3)} of one camera.
nlohmann::json cameraToJson(const PinholeCamera& camera);
// The OpenCV FileStorage XML OpenPose reads from --camera_parameter_path (one file per camera):
// CameraMatrix 3×4 [R|t], Intrinsics 3×3 K, Distortion 5×1 zeros; 17 significant digits.
std::string cameraToOpenCvXml(const PinholeCamera& camera);

}  // namespace s2p
