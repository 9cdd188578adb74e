// Clean-up of a freshly read scan (paper §3 preprocessing): weld coincident vertices, drop
// degenerate and duplicate faces and unreferenced vertices, split non-manifold vertices and
// edges, and report what remains wrong (components, holes).
#pragma once

#include <string>
#include <vector>

#include "io/scan.h"

namespace s2p {

struct CleanupOptions {
  double weldTolerance = 1e-6;  // relative to the bounding-box diagonal; 0 welds exact copies
};

struct CleanupReport {
  int weldedVertices = 0;            // vertices merged into another one
  int degenerateFaces = 0;           // zero area or repeated index, removed
  int duplicateFaces = 0;            // same vertex set as an earlier face, removed
  int unreferencedVertices = 0;      // removed
  int splitNonManifoldVertices = 0;  // vertices whose faces formed > 1 fan (one copy per fan)
  int splitNonManifoldEdges = 0;     // edges with > 2 faces, split apart (fans join only across
                                     // edges with two faces: a fin comes off as a piece)
  int nonManifoldEdges = 0;          // edges with > 2 faces left (none after the split)
  int components = 0;                // connected components of faces
  int boundaryLoops = 0;             // holes (a closed scan has none)
  double largestHolePerimeter = 0;   // in the scan's units
  double seconds = 0;
  std::vector<std::string> warnings;
};

// Cleans in place. Colours of welded vertices are averaged with weights = incident face areas
// (so a vertex split by UV seams gets the area-weighted mean of its corners); Scan::texture's
// UV and FUV stay per corner (FUV rows follow the kept faces). Throws InputError when the
// mesh has non-finite coordinates or no face survives.
CleanupReport cleanScan(Scan& scan, const CleanupOptions& options = {});

}  // namespace s2p
