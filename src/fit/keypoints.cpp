#include "fit/keypoints.h"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "core/error.h"

namespace s2p {

namespace {

using nlohmann::json;

constexpr std::array<const char*, kBody25Count> kBody25Names = {
    "Nose", "Neck",    "RShoulder", "RElbow", "RWrist",  "LShoulder", "LElbow", "LWrist", "MidHip",
    "RHip", "RKnee",   "RAnkle",    "LHip",   "LKnee",   "LAnkle",    "REye",   "LEye",   "REar",
    "LEar", "LBigToe", "LSmallToe", "LHeel",  "RBigToe", "RSmallToe", "RHeel"};

// BODY_25 index → canonical point. OpenPose's L/R are the person's own sides, as ours; eyes and
// ears (15–18) and small toes (20, 23) have no canonical counterpart.
using C = Canonical;
constexpr std::optional<Canonical> kNone;
constexpr std::array<std::optional<Canonical>, kBody25Count> kBody25Canonical = {
    C::Nose,       C::Neck,        C::RightShoulder,
    C::RightElbow, C::RightWrist,  C::LeftShoulder,
    C::LeftElbow,  C::LeftWrist,   C::Pelvis,
    C::RightHip,   C::RightKnee,   C::RightAnkle,
    C::LeftHip,    C::LeftKnee,    C::LeftAnkle,
    kNone,         kNone,          kNone,
    kNone,         C::LeftToeTip,  kNone,
    C::LeftHeel,   C::RightToeTip, kNone,
    C::RightHeel};

void checkTransform(const Eigen::Affine3d& t, std::string_view what) {
  if (!t.matrix().allFinite())
    throw InputError(fmt::format("{}: the file-to-scan transform has non-finite entries", what));
}

std::string usable(const std::vector<JointTarget>& targets) {
  std::string names;
  for (const JointTarget& t : targets)
    names += std::string(names.empty() ? "" : ", ") + toString(t.joint);
  return names.empty() ? "none" : names;
}

void checkCount(const std::vector<JointTarget>& targets, int dropped, std::string_view what) {
  if (static_cast<int>(targets.size()) >= kMinKeypoints) return;
  throw InputError(fmt::format(
      "{}: only {} usable joint(s) ({}), {} more not detected (score 0); at least {} are needed "
      "to place the body: check that the person is fully visible in the views or give more joints",
      what, targets.size(), usable(targets), dropped, kMinKeypoints));
}

// The names parseCanonical accepts, for the unknown-name message.
std::string canonicalNames() {
  std::string s;
  for (int i = 0; i < kNumCanonical; ++i)
    s += std::string(i ? ", " : "") + toString(static_cast<Canonical>(i));
  return s;
}

// OpenPose: {"people": [{"pose_keypoints_3d": [...]}, ...]}.
std::vector<JointTarget> openPoseTargets(const json& doc, const Eigen::Affine3d& toNorm,
                                         const std::string& what) {
  const json& people = doc["people"];
  if (!people.is_array())
    throw FormatError(fmt::format("{}: \"people\" must be an array of OpenPose people", what));
  if (people.empty())
    throw InputError(fmt::format(
        "{}: OpenPose found no person (\"people\" is empty); check the renders show the whole "
        "scan, or use the geometric pose initialisation (no --keypoints)",
        what));
  const json& person = people[0];
  if (!person.is_object()) throw FormatError(fmt::format("{}: people[0] must be an object", what));
  const auto it = person.find("pose_keypoints_3d");
  if (it == person.end() || (it->is_array() && it->empty())) {
    if (person.contains("pose_keypoints_2d"))
      throw FormatError(fmt::format(
          "{}: people[0] has only 2D keypoints (pose_keypoints_2d); run OpenPose with --3d on "
          "the render-views output so that it writes pose_keypoints_3d",
          what));
    throw FormatError(fmt::format("{}: people[0] has no \"pose_keypoints_3d\"", what));
  }
  if (!it->is_array())
    throw FormatError(fmt::format("{}: people[0].pose_keypoints_3d must be an array", what));
  std::vector<double> flat;
  flat.reserve(it->size());
  for (std::size_t i = 0; i < it->size(); ++i) {
    const json& v = (*it)[i];
    if (!v.is_number())
      throw FormatError(
          fmt::format("{}: people[0].pose_keypoints_3d[{}] is not a number", what, i));
    flat.push_back(v.get<double>());
  }
  return body25Targets(flat, toNorm, what);
}

// {"left_wrist": [x, y, z(, weight)] | null, ...}.
std::vector<JointTarget> mapTargets(const json& joints, const Eigen::Affine3d& toNorm,
                                    const std::string& what) {
  std::vector<JointTarget> out;
  std::array<bool, kNumCanonical> seen{};
  int dropped = 0;
  for (const auto& [name, value] : joints.items()) {
    const std::optional<Canonical> c = parseCanonical(name);
    if (!c)
      throw InputError(
          fmt::format("{}: unknown joint name '{}'; use one of: {}", what, name, canonicalNames()));
    if (seen[static_cast<int>(*c)])
      throw InputError(fmt::format("{}: joint '{}' is given twice", what, name));
    seen[static_cast<int>(*c)] = true;
    if (value.is_null()) {
      ++dropped;
      continue;
    }
    if (!value.is_array() || (value.size() != 3 && value.size() != 4))
      throw FormatError(fmt::format("{}: joint '{}' must be [x, y, z] or [x, y, z, weight], got {}",
                                    what, name, value.dump().substr(0, 80)));
    Eigen::Vector4d p(0, 0, 0, 1);
    for (std::size_t k = 0; k < value.size(); ++k) {
      if (!value[k].is_number())
        throw FormatError(
            fmt::format("{}: joint '{}' component {} is not a number", what, name, k));
      p(static_cast<int>(k)) = value[k].get<double>();
    }
    if (!p.allFinite())
      throw FormatError(fmt::format("{}: joint '{}' has a non-finite coordinate", what, name));
    if (p(3) < 0)
      throw FormatError(fmt::format("{}: joint '{}' has a negative weight {}", what, name, p(3)));
    if (p(3) == 0) {
      ++dropped;
      continue;
    }
    out.push_back({*c, toNorm * p.head<3>(), p(3)});
  }
  checkCount(out, dropped, what);
  return out;
}

}  // namespace

const char* body25Name(int index) {
  return (index >= 0 && index < kBody25Count) ? kBody25Names[index] : "unknown";
}

std::optional<Canonical> body25ToCanonical(int index) {
  if (index < 0 || index >= kBody25Count) return std::nullopt;
  return kBody25Canonical[index];
}

std::vector<JointTarget> body25Targets(const std::vector<double>& flat,
                                       const Eigen::Affine3d& fileToNormalised,
                                       std::string_view what) {
  checkTransform(fileToNormalised, what);
  if (flat.size() % 4 != 0 || flat.size() < 4 * kBody25Count)
    throw FormatError(fmt::format(
        "{}: {} numbers of 3D keypoints; BODY_25 has 25 rows of x, y, z, score (100 numbers): "
        "run OpenPose with the BODY_25 model (--model_pose BODY_25, the default)",
        what, flat.size()));
  if (flat.size() != 4 * kBody25Count)
    throw FormatError(fmt::format(
        "{}: {} keypoint rows; expected the 25 of BODY_25 (face and hands belong in their own "
        "arrays)",
        what, flat.size() / 4));
  std::vector<JointTarget> out;
  int dropped = 0;
  for (int i = 0; i < kBody25Count; ++i) {
    const Eigen::Vector4d row(flat[4 * i], flat[4 * i + 1], flat[4 * i + 2], flat[4 * i + 3]);
    if (!row.allFinite())
      throw FormatError(
          fmt::format("{}: keypoint {} ({}) has a non-finite value", what, i, body25Name(i)));
    if (row(3) < 0)
      throw FormatError(fmt::format("{}: keypoint {} ({}) has a negative score {}", what, i,
                                    body25Name(i), row(3)));
    const std::optional<Canonical> c = body25ToCanonical(i);
    if (!c) continue;
    if (row(3) == 0) {  // not detected: OpenPose writes zeros, which are no position
      ++dropped;
      continue;
    }
    out.push_back({*c, fileToNormalised * row.head<3>(), row(3)});
  }
  checkCount(out, dropped, what);
  return out;
}

std::vector<JointTarget> readKeypoints(const std::filesystem::path& path,
                                       const Eigen::Affine3d& fileToNormalised) {
  const std::string what = "keypoint file " + path.string();
  checkTransform(fileToNormalised, what);
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw IoError(
        fmt::format("{}: no such file (give the JSON OpenPose wrote with --write_json, "
                    "or a joint-name → [x, y, z] map)",
                    what));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(fmt::format("{}: cannot be opened for reading", what));
  std::ostringstream bytes;
  bytes << in.rdbuf();
  json doc;
  try {
    doc = json::parse(bytes.str());
  } catch (const json::exception& e) {
    throw FormatError(fmt::format("{}: not JSON ({})", what, e.what()));
  }
  if (!doc.is_object())
    throw FormatError(fmt::format(
        "{}: expected a JSON object (OpenPose's {{\"people\": [...]}} or a joint-name map)", what));
  if (doc.contains("people")) return openPoseTargets(doc, fileToNormalised, what);
  if (doc.contains("joints")) {
    if (!doc["joints"].is_object())
      throw FormatError(fmt::format("{}: \"joints\" must be an object of name → [x, y, z]", what));
    return mapTargets(doc["joints"], fileToNormalised, what);
  }
  return mapTargets(doc, fileToNormalised, what);
}

}  // namespace s2p
