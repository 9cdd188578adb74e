// The built-in demo scan used by `scan2pattern demo` until the synthetic clothed-scan
// generator (src/synth) exists: a person-like solid of revolution with garment-coloured bands,
// stored in millimetres with +Z up so that reading it exercises unit and axis detection.
#pragma once

#include "io/scan.h"

namespace s2p {

// A closed, manifold figure `heightM` metres tall (≈ 2·rings·segments triangles) with per-vertex
// colours: shoes, trousers, shirt, skin. Coordinates in millimetres, +Z up, facing −Y.
Scan makeDemoScan(double heightM = 1.75, int rings = 160, int segments = 96);

}  // namespace s2p
