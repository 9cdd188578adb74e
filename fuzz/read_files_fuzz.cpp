// libFuzzer target for the files the program reads besides scans: bytes → temp file → the
// reader named by S2P_FUZZ_READER (body_json, keypoints, npz, mpfb2_obj, mpfb2_target,
// garment_obj: the exact-index OBJ reader `panels` reads the segment's garments with).
// Typed s2p::Error exceptions are the expected outcome for bad bytes; anything else (a crash,
// a sanitizer report, another exception type such as a raw JSON library error) is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "body/body_json.h"
#include "body/mannequin.h"
#include "body/mpfb2_files.h"
#include "body/smpl_model.h"
#include "core/error.h"
#include "fit/keypoints.h"
#include "io/read_obj.h"

namespace {

constexpr std::string_view kReader = S2P_FUZZ_READER;

std::filesystem::path tempFile() {
  const char* ext = kReader == "npz"           ? ".npz"
                    : kReader == "mpfb2_obj" || kReader == "garment_obj" ? ".obj"
                    : kReader == "mpfb2_target" ? ".target"
                                                : ".json";
  return std::filesystem::temp_directory_path() /
         ("s2p_fuzz_" + std::string(kReader) + "_" + std::to_string(getpid()) + ext);
}

// The built-in model body.json is read against: built once, in LLVMFuzzerInitialize (it takes
// longer than a unit's time limit under the sanitizers).
const s2p::BodyModel& mannequin() {
  static const s2p::BodyModel model = s2p::makeMannequin();
  return model;
}

void read(const std::filesystem::path& file) {
  if (kReader == "body_json") {
    // body.json as `panels --body` reads it.
    s2p::bodyParamsFromJson(s2p::readJsonFile(file), mannequin());
  } else if (kReader == "keypoints") {
    s2p::readKeypoints(file, Eigen::Affine3d::Identity());
  } else if (kReader == "npz") {
    s2p::loadSmplNpz(file);
  } else if (kReader == "mpfb2_obj") {
    s2p::readMpfb2Obj(file);
  } else if (kReader == "mpfb2_target") {
    s2p::readMpfb2Target(file, 20000);
  } else if (kReader == "garment_obj") {
    s2p::readObjGeometry(file);
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (kReader == "body_json") mannequin();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path file = tempFile();
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    read(file);
  } catch (const s2p::Error&) {
  }
  return 0;
}
