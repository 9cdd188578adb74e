// NumPy .npy / .npz reading (and a small writer, for tests and tools). An .npz is a zip archive
// of .npy files, entries STORED or DEFLATED (raw inflate through zlib).
#pragma once

#include <cstddef>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace s2p {

// An n-dimensional array converted to double, in C (row-major) order whatever the file's order.
struct NpyArray {
  std::vector<size_t> shape;  // empty for a scalar
  std::vector<double> data;   // Π shape values, C order

  size_t size() const;                                   // Π shape (1 for a scalar)
  double at(std::initializer_list<size_t> index) const;  // C-order element, bounds unchecked
};

// Decodes one .npy image (header versions 1.0, 2.0, 3.0; dtypes <f8 <f4 <i4 <i8 <u4 |u1 |b1;
// fortran_order true or false). `what` names the source in FormatError messages.
NpyArray decodeNpy(const std::string& bytes, const std::string& what);
NpyArray readNpy(const std::filesystem::path& path);  // missing → IoError, malformed → FormatError

// Every array of an .npz, keyed by entry name without ".npy". Missing → IoError; malformed
// (bad zip, bad CRC, bad .npy, zip64 beyond 4 GiB, encryption) → FormatError naming file and entry.
std::map<std::string, NpyArray> readNpz(const std::filesystem::path& path);

// === Writing

struct NpzEntry {
  std::string name;  // key, ".npy" is appended in the archive
  NpyArray array;
  std::string dtype = "<f8";  // any dtype decodeNpy reads
  bool fortranOrder = false;  // store in Fortran order (values still given in C order)
  bool deflate = false;       // DEFLATED instead of STORED
  std::string rawNpy;         // when non-empty, stored verbatim instead of encoding `array`
};

// Encodes a .npy image (header version 1.0).
std::string encodeNpy(const NpyArray& array, const std::string& dtype, bool fortranOrder);
// Writes an .npz archive with correct CRC-32s; IoError when the file cannot be written.
void writeNpz(const std::filesystem::path& path, const std::vector<NpzEntry>& entries);

}  // namespace s2p
