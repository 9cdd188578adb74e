// The built-in demo scan used by `scan2pattern demo` until the synthetic clothed-scan
// generator (src/synth) exists: a body mesh coloured in garment-like bands (shoes, trousers,
// a striped long-sleeve shirt, skin), stored in millimetres with +Z up so that reading it back
// exercises unit and axis detection.
#pragma once

#include "io/scan.h"

namespace s2p {

// `body`: a closed mesh in metres, +Y up, feet on y = 0 (e.g. the posed mannequin).
Scan makeDemoScan(const TriMesh& body);

}  // namespace s2p
