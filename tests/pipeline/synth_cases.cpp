#include "synth_cases.h"

#include <map>

#include "synth/presets.h"

namespace s2p {

const SynthCase& synthCase(const std::string& preset, int vertices, std::uint64_t seed) {
  static std::map<std::string, SynthCase> cache;
  const std::string key = preset + " " + std::to_string(vertices) + " " + std::to_string(seed);
  auto it = cache.find(key);
  if (it == cache.end()) {
    SynthOptions o = presetOptions(preset);
    o.geometry.targetVertices = vertices;
    if (seed != 0) o.seed = seed;
    SynthScan s = synthesize(o);
    BodyFromJson b = bodyFromJson(s.truth.body);
    it = cache.emplace(key, SynthCase{std::move(s), std::move(b)}).first;
  }
  return it->second;
}

}  // namespace s2p
