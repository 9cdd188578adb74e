#include "body/body_json.h"

#include <cmath>
#include <string>

#include "body/body_source.h"
#include "core/error.h"

namespace s2p {

namespace {

nlohmann::json vec3(const Eigen::Vector3d& v) {
  return {v.x(), v.y(), v.z()};
}

Eigen::Vector3d readVec3(const nlohmann::json& v, const std::string& what) {
  if (!v.is_array() || v.size() != 3)
    throw InputError("body JSON: '" + what + "' must be an array of 3 numbers");
  Eigen::Vector3d out;
  for (int k = 0; k < 3; ++k) {
    if (!v[k].is_number())
      throw InputError("body JSON: '" + what + "' must be an array of 3 numbers");
    out(k) = v[k].get<double>();
  }
  if (!out.allFinite()) throw InputError("body JSON: '" + what + "' is not finite");
  return out;
}

}  // namespace

nlohmann::json bodyToJson(const BodyModel& model, const BodyParams& params,
                          const PosedBody& posed) {
  if (posed.joints.rows() != model.numJoints() || posed.canonical.rows() != kNumCanonical ||
      params.pose.axisAngle.rows() != model.numJoints())
    throw InputError("bodyToJson: pose or posed body does not match body model '" + model.source +
                     "'");
  if (static_cast<int>(model.jointNames.size()) != model.numJoints() ||
      static_cast<int>(model.shapeParams.size()) != model.numShapes())
    throw InputError("bodyToJson: body model '" + model.source +
                     "' lacks joint or shape parameter names");
  if (params.shape.size() != 0 && params.shape.size() != model.numShapes())
    throw InputError("bodyToJson: " + std::to_string(params.shape.size()) + " shape values for " +
                     std::to_string(model.numShapes()) + " shape parameters");
  nlohmann::json j;
  j["source"] = model.source;
  nlohmann::json shape = nlohmann::json::object();
  for (int s = 0; s < model.numShapes(); ++s)
    shape[model.shapeParams[s].name] = params.shape.size() ? params.shape(s) : 0.0;
  j["shape"] = shape;
  nlohmann::json pose = nlohmann::json::object(), joints = nlohmann::json::object(),
                 canonical = nlohmann::json::object();
  for (int k = 0; k < model.numJoints(); ++k) {
    pose[model.jointNames[k]] = vec3(params.pose.axisAngle.row(k).transpose());
    joints[model.jointNames[k]] = vec3(posed.joints.row(k).transpose());
  }
  for (int c = 0; c < kNumCanonical; ++c)
    canonical[toString(static_cast<Canonical>(c))] = vec3(posed.canonical.row(c).transpose());
  j["pose"] = pose;
  j["translation"] = vec3(params.pose.translation);
  j["joints"] = joints;
  j["canonical"] = canonical;
  return j;
}

BodyParams bodyParamsFromJson(const nlohmann::json& json, const BodyModel& model) {
  if (!json.is_object()) throw InputError("body JSON: expected an object");
  if (static_cast<int>(model.shapeParams.size()) != model.numShapes())
    throw InputError("body JSON: body model '" + model.source + "' lacks shape parameter names");
  BodyParams p;
  p.shape = Eigen::VectorXd::Zero(model.numShapes());
  p.pose = BodyPose::zero(model.numJoints());
  if (json.contains("shape")) {
    const nlohmann::json& shape = json["shape"];
    if (!shape.is_object()) throw InputError("body JSON: 'shape' must be an object {name: value}");
    for (const auto& [name, value] : shape.items()) {
      int s = -1;
      for (int k = 0; k < model.numShapes(); ++k)
        if (model.shapeParams[k].name == name) s = k;
      if (s < 0)
        throw InputError("body JSON: unknown shape parameter '" + name + "' for body model '" +
                         model.source + "'");
      if (!value.is_number() || !std::isfinite(value.get<double>()))
        throw InputError("body JSON: shape parameter '" + name + "' must be a finite number");
      p.shape(s) = value.get<double>();
    }
  }
  if (json.contains("pose")) {
    const nlohmann::json& pose = json["pose"];
    if (!pose.is_object())
      throw InputError("body JSON: 'pose' must be an object {joint: [ax, ay, az]}");
    for (const auto& [name, value] : pose.items()) {
      int j = model.jointIndex(name);
      if (j < 0)
        if (const auto c = parseCanonical(name)) j = model.canonical[static_cast<int>(*c)].joint;
      if (j < 0)
        throw InputError("body JSON: unknown joint '" + name + "' for body model '" + model.source +
                         "'");
      p.pose.axisAngle.row(j) = readVec3(value, "pose." + name).transpose();
    }
  }
  if (json.contains("translation"))
    p.pose.translation = readVec3(json["translation"], "translation");
  return p;
}

BodyFromJson bodyFromJson(const nlohmann::json& json) {
  if (!json.is_object() || !json.contains("source") || !json["source"].is_string())
    throw FormatError(
        "the body JSON has no \"source\" (mannequin, mpfb2:DIR or smpl:FILE.npz)");
  BodyFromJson out{loadBodyModel(json["source"].get<std::string>()), {}, {}, {}};
  out.params = bodyParamsFromJson(json, out.model);
  out.posed = poseBody(out.model, out.params);
  out.features = computeFeatures(out.model, out.params.shape);
  return out;
}

}  // namespace s2p
