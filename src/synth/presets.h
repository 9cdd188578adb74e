// The catalogue of named synthetic subjects, like the paper's 14 scanned subjects (Fig. 7 and
// Fig. 18): outfits, the named hard cases (layered r/u, bag a, low contrast t, colour close to
// skin), poses, body shapes, patterns and corruptions, each with a default vertex count between
// 7k and 50k. bench/suite.json lists them with seeds for the benchmark. Pattern periods span
// at least ~4 vertex spacings at the default count, so per-vertex PLY colours resolve them.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "synth/synthesize.h"

namespace s2p {

struct Preset {
  std::string name;         // e.g. "tshirt_trousers"
  std::string description;  // one line for `synth --list`
  SynthOptions options;     // options.preset == name
};

// Every preset, in catalogue order.
const std::vector<Preset>& presets();
std::vector<std::string> presetNames();
// Unknown name → InputError listing the known ones.
const Preset& preset(const std::string& name);
SynthOptions presetOptions(const std::string& name);

// === The benchmark suite (bench/suite.json):
// {"entries": [{"name", "preset", "seed", "vertices", "format" (ply|obj), "scaling"}, ...]}
struct SuiteEntry {
  std::string name;    // output sub-folder, unique
  std::string preset;  // a preset name
  std::uint64_t seed = 1;
  int vertices = 0;  // target vertex count (0: the preset's)
  SynthFormat format = SynthFormat::Ply;
  bool scaling = false;          // a scaling entry (200k, 1M vertices), skipped on request
  SynthOptions options() const;  // the preset's options with this seed and vertex count
};
// Missing file → IoError; bad JSON or entries (unknown preset, duplicate name) → FormatError.
std::vector<SuiteEntry> readSuite(const std::filesystem::path& path);

}  // namespace s2p
