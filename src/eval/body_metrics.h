// Body metric (issue 4 "Metrics"): canonical-joint position error of a fitted body against the
// true body under the clothes, both given as body JSON (src/body/body_json.h, "canonical").
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace s2p {

struct JointError {
  std::string name;  // canonical joint name
  double error = 0;  // m, |predicted − true|
};

struct BodyScore {
  int count = 0;                     // canonical joints present in both
  double meanError = 0;              // m
  double maxError = 0;               // m
  std::string worstJoint;            // name of the joint with maxError
  std::vector<JointError> joints;    // per joint, sorted by name
  std::vector<std::string> missing;  // true joints the prediction lacks
};

// Compares "canonical": {name: [x, y, z]} of two body JSONs over the names in common. A
// missing or malformed "canonical" → InputError naming `predWhat` / `truthWhat`; no name in
// common → InputError.
BodyScore compareBodies(const nlohmann::json& truthBody, const nlohmann::json& predBody,
                        const std::string& truthWhat = "truth body",
                        const std::string& predWhat = "predicted body");

}  // namespace s2p
