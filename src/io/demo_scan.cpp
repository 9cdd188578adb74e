#include "io/demo_scan.h"

#include <cmath>

#include "core/error.h"

namespace s2p {

Scan makeDemoScan(const TriMesh& body) {
  validateMesh(body, "demo body");
  const BoundingBox box = boundingBox(body.V);
  const double height = box.extent().y();
  Scan scan;
  scan.mesh.F = body.F;
  scan.mesh.V.resize(body.numVertices(), 3);
  scan.colour.resize(body.numVertices(), 3);
  for (int v = 0; v < body.numVertices(); ++v) {
    const double h = (body.V(v, 1) - box.min.y()) / height;  // 0 at the soles, 1 at the head top
    Eigen::RowVector3d c;
    if (h < 0.04) c << 0.08, 0.08, 0.09;                     // shoes
    else if (h < 0.56) c << 0.18, 0.22, 0.38;                // trousers
    else if (h < 0.82 && std::abs(body.V(v, 0)) < 0.1 * height + 0.4 * (0.82 - h) * height)
      c << 0.80, 0.25, 0.20;                                 // shirt (sleeves to the wrists)
    else c << 0.87, 0.68, 0.56;                              // skin: head, hands
    if (h >= 0.56 && h < 0.82 && c(0) > 0.5 && std::fmod(h * 60.0, 2.0) < 0.5) c *= 0.8;
    scan.colour.row(v) = c;
    // Output frame: millimetres, +Z up, facing −Y (a rotation of +90° about x).
    scan.mesh.V.row(v) << 1000.0 * body.V(v, 0), -1000.0 * body.V(v, 2), 1000.0 * body.V(v, 1);
  }
  scan.colourSource = ColourSource::Vertex;
  scan.sourcePath = "<built-in demo scan>";
  return scan;
}

}  // namespace s2p
