// PNG files of 8-bit RGB images (libpng's simplified API): previews and texture round trips.
#pragma once

#include <filesystem>

#include "io/scan.h"

namespace s2p {

// Writes an 8-bit RGB PNG atomically (temporary file in the same folder, then rename). IoError
// when the file cannot be written (no partial file is left behind), InputError when the image
// is empty or its pixel buffer does not have width·height·3 bytes.
void writePng(const std::filesystem::path& path, const Image& image);

// Reads any PNG as 8-bit RGB (alpha composited onto white, grey expanded). IoError when the file
// cannot be read, FormatError when it is not a valid PNG.
Image readPng(const std::filesystem::path& path);

}  // namespace s2p
