// Offscreen preview renderer: a small software rasteriser (z-buffer, Lambert shading with a
// little ambient and a soft headlight, per-vertex or flat colours, polylines and points over the
// surface, supersampling) that draws a scene from one or several orthographic views side by side
// into one RGB image. Every stage shows its result with it (report PNGs).
//
// Scene conventions (DESIGN.md "Units"): metres, +Y up, the person faces +Z. The person's right
// hand is on −X. Views (image right / image up / towards the camera):
//   Front         camera on +Z looking along −Z: +X is on the image's right (so the person's
//                 right hand, −X, appears on the image's left, as when facing someone).
//   Back          camera on −Z looking along +Z: +X is on the image's left.
//   Left          the person's left side, camera on +X looking along −X: +Z (the person's
//                 front) is on the image's left.
//   Right         the person's right side, camera on −X looking along +X: +Z on the image's right.
//   ThreeQuarter  Front rotated 45° about +Y: camera on the (+X, +Z) diagonal, i.e. between
//                 Front and Left (the person's front-left).
// Auto-framing: all drawn geometry (meshes, lines, points) is fitted with a margin, at one
// scale (pixels per metre) shared by all views of the image; each view gets a panel as wide as
// its content needs and panels are laid out left to right with a gap.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/tri_mesh.h"
#include "export/png.h"  // writePng, readPng
#include "io/scan.h"

namespace s2p {

struct Rgb {
  std::uint8_t r = 0, g = 0, b = 0;
  bool operator==(const Rgb&) const = default;
};

enum class View { Front, Back, Left, Right, ThreeQuarter };

// "front", "back", "left", "right", "three-quarter" (also "three_quarter", "3/4"); else nullopt.
std::optional<View> parseView(std::string_view name);
// The canonical name parseView accepts ("three-quarter" for ThreeQuarter).
const char* toString(View view);

// World → camera rotation of a view: rows are image right, image up, towards the camera.
Eigen::Matrix3d viewRotation(View view);

// A curve drawn over the surfaces, e.g. a seam or a boundary on the scan.
struct Polyline {
  Eigen::MatrixX3d points{};  // #P×3, metres
  Rgb colour{220, 30, 30};
  float widthPx = 2;    // in output pixels, (0, 64] (round caps and joins)
  bool closed = false;  // also draw the segment from the last point back to the first
  bool onTop = false;   // drawn without depth test (always visible)
};

// Dots drawn over the surfaces, e.g. feature points.
struct PointSet {
  Eigen::MatrixX3d points{};  // #P×3, metres
  Rgb colour{30, 30, 220};
  float radiusPx = 4;  // in output pixels, (0, 64]
  bool onTop = false;  // drawn without depth test (always visible)
};

struct SceneMesh {
  const TriMesh* mesh = nullptr;             // not owned; must outlive renderScene
  const Eigen::MatrixX3d* colour = nullptr;  // #V×3 sRGB in [0, 1]; nullptr: flatColour
  Rgb flatColour{200, 200, 200};
  // In [0, 1]. Below 1 the mesh is blended over everything drawn before it (opaque meshes and
  // curves behind it), showing its own nearest surface only, e.g. a scan over the fitted body.
  float opacity = 1.0f;
  bool smooth = true;  // interpolate vertex normals (false: one normal per face)
};

struct Scene {
  std::vector<SceneMesh> meshes;
  std::vector<Polyline> lines;
  std::vector<PointSet> points;
};

struct RenderOptions {
  std::vector<View> views{View::Front};  // left to right in the image
  int heightPx = 1024;                   // output height, in [8, 16384]
  int supersample = 2;                   // samples per pixel along each axis, in [1, 8]
  Rgb background{255, 255, 255};
  double margin = 0.05;    // free border on each side, as a fraction of heightPx, in [0, 0.45]
  int gapPx = 16;          // background columns between two views
  int maxViewWidthPx = 0;  // widest panel allowed (very wide content is scaled down); 0: 4·heightPx
  // Curves and points (not onTop) stay visible when at most this far behind the surface, as a
  // fraction of the scene's largest extent, plus their own half width: curves ON a surface are
  // not lost to z-fighting while curves behind the body stay hidden.
  double overlayDepthBias = 0.01;
  // One caption per view (or none at all), centred in the panel's top margin in a small built-in
  // font (bitmap_text.h), e.g. toString(view); an empty string leaves that view blank.
  std::vector<std::string> captions{};
};

// Where each view landed in the image.
struct ViewPanel {
  View view = View::Front;
  int x0 = 0;                 // first column of the panel
  int width = 0;              // panel width in pixels (panel height is the image height)
  double pixelsPerMetre = 0;  // same for every panel of an image
  // Camera-space point (image right, image up; metres) drawn at the panel's centre.
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
};

// Renders the scene, views side by side. Meshes without faces are ignored; a scene with nothing
// to draw gives square background panels. Throws InputError on bad options or geometry (null mesh, wrong colour rows, non-finite
// coordinates, out-of-range sizes). Deterministic: the same input gives the same bytes.
Image renderScene(const Scene& scene, const RenderOptions& options);
// Same, and reports the panel of each view (in the order of options.views).
Image renderScene(const Scene& scene, const RenderOptions& options, std::vector<ViewPanel>* panels);

}  // namespace s2p
