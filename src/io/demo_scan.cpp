#include "io/demo_scan.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include "core/shapes.h"

namespace s2p {
namespace {

// Half-width of the figure (metres, for a 1.75 m person) against height fraction: both legs
// merged into one column, hips, waist, chest, shoulders, neck, head.
constexpr std::array<std::array<double, 2>, 14> kProfile = {{{0.00, 0.00},
                                                             {0.01, 0.13},
                                                             {0.05, 0.11},
                                                             {0.28, 0.14},
                                                             {0.47, 0.18},
                                                             {0.53, 0.19},
                                                             {0.62, 0.15},
                                                             {0.72, 0.17},
                                                             {0.80, 0.21},
                                                             {0.845, 0.07},
                                                             {0.87, 0.065},
                                                             {0.92, 0.095},
                                                             {0.975, 0.075},
                                                             {1.00, 0.00}}};

// Smooth (Catmull-Rom) interpolation of kProfile at height fraction t ∈ [0, 1].
double profileRadius(double t) {
  const int n = static_cast<int>(kProfile.size());
  int i = 0;
  while (i < n - 2 && kProfile[i + 1][0] < t) ++i;
  const auto at = [&](int k) { return kProfile[std::clamp(k, 0, n - 1)][1]; };
  const double t0 = kProfile[i][0], t1 = kProfile[i + 1][0];
  const double s = std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
  const double p0 = at(i - 1), p1 = at(i), p2 = at(i + 1), p3 = at(i + 2);
  const double r = 0.5 * ((2 * p1) + (-p0 + p2) * s + (2 * p0 - 5 * p1 + 4 * p2 - p3) * s * s +
                          (-p0 + 3 * p1 - 3 * p2 + p3) * s * s * s);
  return std::max(r, 0.0);
}

}  // namespace

Scan makeDemoScan(double heightM, int rings, int segments) {
  TriMesh m = makeUvSphere(rings, segments, 1.0);  // poles on ±y
  Scan scan;
  scan.colour.resize(m.numVertices(), 3);
  const double scale = heightM / 1.75;
  for (int v = 0; v < m.numVertices(); ++v) {
    // Use the polar angle (not y) so rings are evenly spread along the height.
    const double theta = std::acos(std::clamp(m.V(v, 1), -1.0, 1.0));
    const double h = 1.0 - theta / std::numbers::pi;
    const double r = profileRadius(h) * scale;
    const double phi = std::atan2(m.V(v, 0), m.V(v, 2));
    const double x = r * std::sin(phi), depth = 0.62 * r * std::cos(phi);
    // Output frame: millimetres, +Z up, the figure faces −Y.
    m.V.row(v) << 1000.0 * x, -1000.0 * depth, 1000.0 * h * heightM;
    Eigen::RowVector3d c;
    if (h < 0.035) c << 0.08, 0.08, 0.09;                 // shoes
    else if (h < 0.58) c << 0.18, 0.22, 0.38;             // trousers
    else if (h < 0.83) c << 0.80, 0.25, 0.20;             // shirt
    else c << 0.87, 0.68, 0.56;                           // skin
    // Stripes on the shirt so the colour is not flat.
    if (h >= 0.58 && h < 0.83 && std::fmod(h * 60.0, 2.0) < 0.5) c *= 0.8;
    scan.colour.row(v) = c;
  }
  scan.mesh = std::move(m);
  scan.colourSource = ColourSource::Vertex;
  scan.sourcePath = "<built-in demo scan>";
  return scan;
}

}  // namespace s2p
