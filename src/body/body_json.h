// Body parameters and posed results as JSON (the `body.json` output, DESIGN.md "Outputs"):
// everything by name (shape parameters, joints, canonical points), never by index.
#pragma once

#include <nlohmann/json.hpp>

#include "body/body_model.h"
#include "body/features.h"
#include "body/posing.h"

namespace s2p {

// {"source", "shape": {name: value}, "pose": {joint: [ax, ay, az]}, "translation": [x, y, z],
//  "joints": {joint: [x, y, z]} (posed), "canonical": {canonical name: [x, y, z]} (posed)}.
nlohmann::json bodyToJson(const BodyModel& model, const BodyParams& params, const PosedBody& posed);

// Reads "shape", "pose" and "translation" back (absent entries are zero; joints may also be
// given by canonical name). Unknown names or malformed values → InputError naming them.
BodyParams bodyParamsFromJson(const nlohmann::json& json, const BodyModel& model);

// A body JSON made whole: its model loaded from "source", posed, with its feature set (on the
// posed mesh's faces). IoError/FormatError from the body source; InputError as above.
struct BodyFromJson {
  BodyModel model;
  BodyParams params;
  PosedBody posed;
  FeatureSet features;
};
BodyFromJson bodyFromJson(const nlohmann::json& json);

}  // namespace s2p
