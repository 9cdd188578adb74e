// libFuzzer target: bytes → temp file with extension S2P_FUZZ_EXT → readScan + cleanScan.
// Typed s2p::Error exceptions are the expected outcome for bad bytes; anything else (a crash,
// a sanitizer report, another exception type) is a finding.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "core/error.h"
#include "io/cleanup.h"
#include "io/read_scan.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::filesystem::path file = std::filesystem::temp_directory_path() /
                                            ("s2p_fuzz_" + std::to_string(getpid()) + S2P_FUZZ_EXT);
  {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  try {
    s2p::Scan scan = s2p::readScan(file, {.loadTexture = false});
    s2p::cleanScan(scan);
  } catch (const s2p::Error&) {
  }
  return 0;
}
