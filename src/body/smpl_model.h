// A user's SMPL / SMPL-H / SMPL-X model from its .npz (paper §4 fits SMPL). The model files are
// licensed and never shipped: the user points at their own copy.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "body/body_model.h"
#include "body/npz.h"

namespace s2p {

// Reads v_template (#V×3), shapedirs (#V×3×#S), posedirs (#V×3×9(#J−1)), J_regressor
// (#J×#V, dense), weights (#V×#J), kintree_table (2×#J, root parent 2³²−1 or −1) and f
// (#F×3). The joint count selects the joint names: 24 SMPL, 52 SMPL-H, 55 SMPL-X (names as in
// the smplx package). Canonical joints map by name; the surface landmarks (hand tips, toe
// tips, heels, head top, nose) are chosen by geometric rules on the template. Missing file →
// IoError; missing key, wrong shape, bad kinematic tree → FormatError naming the key.
BodyModel loadSmplNpz(const std::filesystem::path& path);

// The same from arrays already in memory; `source` names them in messages.
BodyModel smplModelFromArrays(const std::map<std::string, NpyArray>& arrays,
                              const std::string& source);

// Joint names of the SMPL family by joint count (24, 52 or 55); FormatError otherwise.
std::vector<std::string> smplJointNames(int numJoints);

}  // namespace s2p
