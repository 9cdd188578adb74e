// The paper's predefined feature points (§5.1.1, Fig. 4; §6.1.1, Fig. 11), defined once by
// rules on canonical joints and body-part geometry — never by vertex ids — so that they exist on
// every body source and follow shape and pose: they are surface points (face + barycentric) of
// the body mesh, computed on the shaped rest body and carried to any pose by the same faces.
#pragma once

#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "body/body_model.h"
#include "core/surface_point.h"

namespace s2p {

// Labels of the region points that feed the colour model (§5.1.4).
enum class RegionLabel { Skin, Upper, Lower, Foot };
const char* toString(RegionLabel label);

// A spline through a few anchor points on the body surface.
struct FeatureSpline {
  std::string name;                   // "neck", "left_wrist", "waist", "left_underarm", ...
  std::vector<SurfacePoint> anchors;  // in order along the curve
  bool closed = true;
};

// A point with a sign: which side of the boundary or seam it lies on. Seams use pairs: when one
// point of a pair is dropped as ill-projected its partner is dropped too (§6.1.2).
struct SignPoint {
  std::string name;
  SurfacePoint point;
  double value = 1.0;  // +1 or −1
  int pair = -1;       // index of the paired sign point in the same list, or −1
};

// The splines and sign points of one boundary (B(U|S), B(L|S), B(U|L)) or one seam.
struct CurveFeatures {
  std::string name;  // "U|S", "L|S", "U|L", "upper_side", "shoulder", "lower_side", "crotch"
  std::vector<FeatureSpline> splines;
  std::vector<SignPoint> signs;
};

struct RegionPoint {
  SurfacePoint point;
  RegionLabel label;
};

struct FeatureSet {
  CurveFeatures upperSkin;   // B(U|S): neck and wrist loops
  CurveFeatures lowerSkin;   // B(L|S): ankle loops
  CurveFeatures upperLower;  // B(U|L): waist loop
  std::vector<CurveFeatures> seams;  // upper_side, shoulder, lower_side, crotch
  std::vector<RegionPoint> regions;

  const CurveFeatures* seam(const std::string& name) const;  // nullptr when absent
};

struct FeatureOptions {
  int loopAnchors = 8;       // anchors on each closed boundary loop
  int regionLoopPoints = 12;  // points taken from each section loop of a labelled region
};

// Computes the feature set of `model` with shape β on its rest pose. Throws InputError when a
// rule finds no surface (e.g. a model without arms).
FeatureSet computeFeatures(const BodyModel& model, const Eigen::VectorXd& shape,
                           const FeatureOptions& options = {});

// JSON with surface points (face, bary) and their 3D positions on `mesh` (the body the set
// is evaluated on: rest or posed).
nlohmann::json featuresToJson(const FeatureSet& features, const TriMesh& mesh);
FeatureSet featuresFromJson(const nlohmann::json& j);

}  // namespace s2p
