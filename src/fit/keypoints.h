// 3D keypoints from outside (the paper's path, §4: OpenPose BODY_25 triangulated from seven
// renders, see camera_views.h) read as joint targets for solveInverseKinematics (pose_init.h).
//
// Two JSON layouts, told apart by their content:
//   - OpenPose with --3d --write_json: {"people": [{"pose_keypoints_3d": [x,y,z,score, ...]}]},
//     25 rows of BODY_25; the first person is used. Rows with score 0 (not detected) are
//     dropped, never averaged (the pitfall of the paper's code, research note E §4); the score
//     becomes the target's weight. BODY_25 points without a canonical counterpart (eyes, ears,
//     small toes) are ignored.
//   - A plain map by canonical name (toString(Canonical)): {"left_wrist": [x, y, z], ...} or
//     {"joints": {...}}; a value may carry a fourth number, its weight (0: not detected, dropped),
//     or be null (not detected).
// The paper's own "3D_keypoints.txt" is not read: its layout is not documented.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <filesystem>
#include <optional>
#include <string_view>
#include <vector>

#include "body/body_model.h"
#include "fit/pose_init.h"

namespace s2p {

// === OpenPose BODY_25

constexpr int kBody25Count = 25;
// Name of BODY_25 keypoint i as OpenPose prints it ("Nose", "Neck", "RShoulder", ...).
const char* body25Name(int index);
// The canonical point BODY_25 keypoint i stands for; nullopt for eyes, ears and small toes.
// MidHip → pelvis, BigToe → toe tip, Heel → heel, the rest by name.
std::optional<Canonical> body25ToCanonical(int index);

// Joint targets from an OpenPose BODY_25 3D array (#rows ≥ 25 of x, y, z, score, flattened as
// OpenPose writes it), mapped by `fileToNormalised`. `what` names the source in messages.
std::vector<JointTarget> body25Targets(const std::vector<double>& flat,
                                       const Eigen::Affine3d& fileToNormalised,
                                       std::string_view what = "keypoints");

// === Keypoint files

// Reads a keypoint file (either layout above) whose coordinates are in the scan FILE's frame and
// units; `fileToNormalised` (the scan's toInputFrame.inverse()) brings them to the normalised
// frame (metres, +Y up). Throws IoError when the file cannot be read, FormatError when it is not
// JSON or an entry has the wrong shape or a non-finite number, InputError for an unknown joint
// name, no person, or fewer than kMinKeypoints usable joints.
std::vector<JointTarget> readKeypoints(const std::filesystem::path& path,
                                       const Eigen::Affine3d& fileToNormalised);

constexpr int kMinKeypoints = 4;  // fewer joints cannot fix a pose (root rotation + translation)

}  // namespace s2p
