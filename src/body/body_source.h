// One entry point for the three body sources, as the command line names them:
// "mannequin" (built in, the default), "mpfb2:DIR" (an MPFB2 / MakeHuman folder) and
// "smpl:FILE" (a user's SMPL / SMPL-H / SMPL-X .npz).
#pragma once

#include <Eigen/Core>
#include <string>

#include "body/body_model.h"

namespace s2p {

// Loads the model named by `spec`. Unknown spec → InputError listing the accepted forms;
// missing files → IoError; malformed files → FormatError (each naming the file).
BodyModel loadBodyModel(const std::string& spec);

// Parses "name=value,name=value" into a shape vector of `model` (unlisted parameters stay 0).
// Unknown names → InputError listing the model's parameters.
Eigen::VectorXd parseShapeAssignments(const BodyModel& model, const std::string& text);

}  // namespace s2p
