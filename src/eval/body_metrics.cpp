#include "eval/body_metrics.h"

#include <fmt/format.h>

#include <Eigen/Core>
#include <cmath>
#include <map>

#include "core/error.h"

namespace s2p {
namespace {

std::map<std::string, Eigen::Vector3d> canonicalPoints(const nlohmann::json& body,
                                                       const std::string& what) {
  if (!body.is_object() || !body.contains("canonical") || !body.at("canonical").is_object())
    throw InputError(fmt::format(
        "{} has no \"canonical\" object of joint positions; give a body JSON written by "
        "`scan2pattern body` or the fitter",
        what));
  std::map<std::string, Eigen::Vector3d> out;
  for (const auto& [name, p] : body.at("canonical").items()) {
    if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() ||
        !p[2].is_number())
      throw InputError(fmt::format("{}: canonical joint \"{}\" is not [x, y, z]", what, name));
    const Eigen::Vector3d v(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
    if (!v.allFinite())
      throw InputError(fmt::format("{}: canonical joint \"{}\" is not finite", what, name));
    out[name] = v;
  }
  return out;
}

}  // namespace

BodyScore compareBodies(const nlohmann::json& truthBody, const nlohmann::json& predBody,
                        const std::string& truthWhat, const std::string& predWhat) {
  const auto truth = canonicalPoints(truthBody, truthWhat);
  const auto pred = canonicalPoints(predBody, predWhat);
  BodyScore s;
  for (const auto& [name, p] : truth) {
    const auto it = pred.find(name);
    if (it == pred.end()) {
      s.missing.push_back(name);
      continue;
    }
    const double e = (it->second - p).norm();
    s.joints.push_back({name, e});
    s.meanError += e;
    if (e >= s.maxError) {
      s.maxError = e;
      s.worstJoint = name;
    }
  }
  s.count = static_cast<int>(s.joints.size());
  if (s.count == 0)
    throw InputError(
        fmt::format("{} and {} have no canonical joint name in common", predWhat, truthWhat));
  s.meanError /= s.count;
  return s;
}

}  // namespace s2p
