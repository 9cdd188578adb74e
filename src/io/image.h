// 8-bit RGB images for scan textures: decoding (PNG/JPG via stb_image), PNG encoding and
// bilinear sampling at OpenGL-convention UVs.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "io/scan.h"

namespace s2p {

// Decodes a PNG/JPG/... held in memory. `what` names the source in messages. Throws
// FormatError when the bytes are not a decodable image.
Image decodeImage(const std::uint8_t* data, std::size_t size, const std::string& what);
// Reads and decodes an image file. Missing/unreadable → IoError; undecodable → FormatError.
Image readImage(const std::filesystem::path& path);
// Encodes as PNG (8-bit RGB). Throws IoError if encoding fails.
std::string encodePng(const Image& image);

// Bilinear sample at (u, v) in OpenGL convention ((0,0) = bottom-left), wrapping outside
// [0, 1) (REPEAT, as OBJ and glTF default). Returns sRGB in [0, 1]. Pixel centres at
// ((i + 0.5)/w, 1 − (j + 0.5)/h).
Eigen::Vector3d sampleBilinear(const Image& image, double u, double v);

}  // namespace s2p
