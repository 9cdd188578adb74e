// The drape check's results (issue 19): the placed, remeshed pattern sewn and draped on the
// rest body (drape/drape.h), then compared with the scanned garments brought to the same pose by
// the skinning that unposes the body: how close, in millimetres, the sewn pattern comes to what
// was scanned. The functions are in pipeline.h (they take the pattern stage's results).
#pragma once

#include <string>
#include <vector>

#include "core/tri_mesh.h"
#include "drape/compare.h"
#include "drape/coarse_to_fine.h"
#include "drape/drape.h"

namespace s2p {

struct DrapeStageOptions {
  bool enabled = false;  // the stage runs only when asked (--drape): see DrapeStageOptions
  DrapeOptions drape;
  // Metres: the pattern is first sewn and draped remeshed at this edge, then carried onto its own
  // mesh and settled there (drape/coarse_to_fine.h); 0, or no coarser than the pattern's own
  // mesh: sewn and draped at the pattern's resolution only.
  double coarseEdge = 0.03;
  CoarseToFineOptions coarseToFine;
};

// One garment of the drape: its draped panels against its scanned mesh in the drape pose.
struct GarmentDrape {
  std::string garment;        // "upper", "lower", "onepiece"
  TriMesh draped;             // the garment's panels after the drape, rest frame (metres)
  TriMesh scanned;            // the cut garment of the segmentation in the drape pose
  MeshComparison comparison;  // A = draped, B = scanned
  double topDropMm = 0;       // how far its top hangs below the scanned top (drape/compare.h)
  // Per panel region: the panel's draped vertices to the scanned garment, (panel name, stats).
  std::vector<std::pair<std::string, SurfaceDistanceStats>> panels;
};

struct DrapeStage {
  bool ran = false;            // false: disabled, or nothing to drape (see warnings)
  DrapeResult drape;           // the simulation and its figures (at the pattern's resolution)
  bool coarseToFine = false;   // drape came from a coarse drape carried onto the pattern's mesh
  CoarseToFineDrape twoLevel;  // when coarseToFine: the coarse drape and the carrying (its
                               // `fine` is moved into drape)
  int coarseVertices = 0;      // cloth vertices of the coarse mesh
  std::vector<int> panelOf;    // cloth panel → PatternResult panel
  std::vector<int> garmentOf;  // cloth panel → GarmentDrape (−1: its garment was not compared)
  std::vector<GarmentDrape> garments;
  std::vector<std::string>
      warnings;  // for report.json; a failed drape is a warning, never an error
  double seconds = 0;
};

}  // namespace s2p
