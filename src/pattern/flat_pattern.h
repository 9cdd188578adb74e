// Patterns II (paper §6.2): every panel of Patterns I flattened (Boundary First Flattening with
// u = 0, then the warp/weft refinement: flatten.h), its edges between the corners fitted with
// cubic Bézier chains (bezier_outline.h), and remeshed with CGAL's constrained Delaunay mesher
// (remesh.h) from the Béziers resampled so that two stitched edges get the same number of
// vertices; every new vertex located in the flattened panel so that the 3D shape and the scan's
// colours travel with the pattern.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/surface_point.h"
#include "pattern/bezier_outline.h"
#include "pattern/body_frame.h"
#include "pattern/flatten.h"
#include "pattern/flatten_metrics.h"
#include "pattern/panel_denoise.h"
#include "pattern/panels.h"
#include "pattern/remesh.h"

namespace s2p {

struct FlatPatternOptions {
  // Scan noise filtered out of each 3D panel before it is flattened (panel_denoise.h): the
  // pattern is cut to the garment, not to its scanner's noise. Strain is measured against it.
  PanelDenoiseOptions denoise;
  // Without the boundary term (boundaryWeight 0): on the demo scan it held seam lengths better
  // (partners within 2.3 mm at weight 4, 5.9 mm at 1, 9.9 mm at 0) but doubled the strain (p95 up
  // to 9.7 % at 4, 4.9 % at 0) and inverted more faces; the strain bound of cloth wins.
  FlattenOptions flatten;
  // Seam truing (flatten.h): the two edges of a seam get the same 2D length. Without it the
  // suite's partner edges differed by 3.7 mm (median) after the warp/weft refinement.
  bool trueSeams = true;
  SeamTruing truing;
  // Seam walking: where truing left the two sides' Bézier chains of a seam apart, each is
  // stretched or flattened across its chord (an affine map: corners and G1 joints kept) to the
  // pair's mean length, when that moves no point of it by more than walkLimit (metres) and leaves
  // the outline simple.
  bool walkSeams = true;
  double walkLimit = 0.01;
  BezierFitOptions bezier;  // 1 mm by default
  RemeshOptions remesh;     // 10 mm target edge, ≥ 20.7°
};

// A shape to flatten a panel as instead of its scanned one (same vertices and faces): a sleeve
// scanned on a bent arm, with the bend taken out (pipeline/limb_straightening.h). The pattern is
// cut to it; colours, placement and stitches still use the scanned panel.
struct PanelReshape {
  Eigen::MatrixX3d V;  // #V of the panel × 3; empty: the panel is flattened as scanned
  Eigen::Vector3d grain = Eigen::Vector3d::Zero();  // its grain; zero: panelGrain's
  std::string why;  // for the report, e.g. "left elbow straightened (bent 88°)"
};

struct FlatEdge {
  BezierChain chain;          // in the panel's 2D frame (metres)
  double length2d = 0;        // of the flattened boundary polyline (m)
  double fitError = 0;        // max distance between the chain and that polyline (m)
  std::vector<int> vertices;  // remeshed vertex ids along the edge, corner to corner
};

struct FlatPanel {
  int panel = -1;                                    // index into PanelsResult::panels
  Eigen::Vector3d grain = Eigen::Vector3d::UnitY();  // the 3D direction that maps to +y
  Eigen::MatrixX2d uv;                               // #V of the 3D panel × 2, metres
  TriMesh surface;  // the 3D panel as flattened: its faces, scan noise filtered (denoise)
  double denoiseShiftMean = 0, denoiseShiftMax = 0;  // m: how far the filter moved its vertices
  PanelFlattening flattening;
  FlatteningMetrics metrics;  // of uv against the 3D panel (reshaped when reshaped)
  std::string reshaped;       // why it was flattened as another shape (PanelReshape), or empty
  FlatteningMetrics scannedMetrics;  // of uv against the panel as scanned, when reshaped
  std::vector<FlatEdge> edges;       // as Panel::edges
  RemeshedPanel remeshed;
  Eigen::MatrixX3d position;           // #V of the remeshed panel × 3: its point on the 3D panel
  std::vector<SurfacePoint> location;  // #V of the remeshed panel: where in the 3D panel
  Eigen::VectorXi scanFace;            // #V of the remeshed panel: the scan face it lies in
  Eigen::MatrixX3d scanBary;           // #V × 3: its barycentric weights in that scan face
  double seconds = 0;
  std::string error;  // non-empty: this panel could not be flattened (the others still are)
};

// One pair of partner seam edges.
struct SeamPair {
  int panelA = -1, edgeA = -1, panelB = -1, edgeB = -1;  // indices into PanelsResult
  double lengthA = 0, lengthB = 0;                       // 2D lengths of the two Bézier chains (m)
  int samples = 0;                                       // vertices on each after remeshing
};

struct FlatPatternResult {
  std::vector<FlatPanel> panels;  // one per Patterns I panel, same order
  std::vector<SeamPair> seams;
  std::vector<std::string> warnings;
  double seconds = 0;
};

// The grain of a panel: along the arm (wrist → shoulder) for sleeves, the body's up otherwise.
Eigen::Vector3d panelGrain(const Panel& panel, const BodyFrame& frame);

// Flattens, outlines and remeshes every panel. scan: the scan mesh the panels' faceOrigin refer
// to (for the scan face and weights of each new vertex). A panel that fails gets an error
// naming it; the others are still done.
// reshape: empty, or one per panel (PanelReshape).
FlatPatternResult runFlatPattern(const PanelsResult& panels, const TriMesh& scan,
                                 const BodyFrame& frame, const FlatPatternOptions& options = {},
                                 const std::vector<PanelReshape>& reshape = {});

// The same pattern at another resolution: every flattened panel's outline (its Bézier edges as
// they are) remeshed with `options`, each stitched pair of flat.seams given one sample count as
// runFlatPattern does, so that FlatEdge k of a panel is edgeVertices[k] of its new mesh and
// stitched edges still pair vertex to vertex (a coarse copy for the drape). A panel that was not
// flattened, or that cannot be remeshed so, gets an empty mesh and, in errors (#panels), why.
std::vector<RemeshedPanel> remeshOutlines(const FlatPatternResult& flat,
                                          const RemeshOptions& options,
                                          std::vector<std::string>* errors = nullptr);

}  // namespace s2p
