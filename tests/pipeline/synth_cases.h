// Synthetic clothed scans for the pipeline tests, generated once per (preset, resolution) and
// shared by the tests of the program.
#pragma once

#include <cstdint>
#include <string>

#include "body/body_json.h"
#include "synth/synthesize.h"

namespace s2p {

struct SynthCase {
  SynthScan scan;
  BodyFromJson body;  // the true body under the clothes
};

// seed 0: the preset's own.
const SynthCase& synthCase(const std::string& preset, int vertices, std::uint64_t seed = 0);

}  // namespace s2p
