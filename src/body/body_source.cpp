#include "body/body_source.h"

#include <fmt/format.h>
#include <sstream>

#include "body/mannequin.h"
#include "body/mpfb2_model.h"
#include "body/smpl_model.h"
#include "core/error.h"

namespace s2p {

BodyModel loadBodyModel(const std::string& spec) {
  if (spec == "mannequin") return makeMannequin();
  if (spec.rfind("mpfb2:", 0) == 0) return loadMpfb2(spec.substr(6));
  if (spec.rfind("smpl:", 0) == 0) return loadSmplNpz(spec.substr(5));
  throw InputError(fmt::format(
      "unknown body model '{}': use mannequin, mpfb2:DIR (an MPFB2 / MakeHuman folder) or "
      "smpl:FILE.npz",
      spec));
}

Eigen::VectorXd parseShapeAssignments(const BodyModel& model, const std::string& text) {
  Eigen::VectorXd shape = Eigen::VectorXd::Zero(model.numShapes());
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    const auto eq = item.find('=');
    const std::string name = item.substr(0, eq);
    int index = -1;
    for (int s = 0; s < model.numShapes(); ++s)
      if (model.shapeParams[s].name == name) index = s;
    if (index < 0 || eq == std::string::npos) {
      std::string names;
      for (const auto& p : model.shapeParams) names += (names.empty() ? "" : ", ") + p.name;
      throw InputError(fmt::format("--shape: '{}' is not name=value with a parameter of {} ({})",
                                   item, model.source, names));
    }
    try {
      size_t used = 0;
      const double value = std::stod(item.substr(eq + 1), &used);
      if (used != item.size() - eq - 1) throw std::invalid_argument("trailing characters");
      shape(index) = value;
    } catch (const std::exception&) {
      throw InputError(fmt::format("--shape: '{}' has no number after '='", item));
    }
  }
  return shape;
}

}  // namespace s2p
