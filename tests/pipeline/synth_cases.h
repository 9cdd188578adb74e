// Synthetic clothed scans for the pipeline tests, generated once per (preset, resolution) and
// shared by the tests of the program.
#pragma once

#include <string>

#include "body/body_json.h"
#include "synth/synthesize.h"

namespace s2p {

struct SynthCase {
  SynthScan scan;
  BodyFromJson body;  // the true body under the clothes
};

const SynthCase& synthCase(const std::string& preset, int vertices);

}  // namespace s2p
