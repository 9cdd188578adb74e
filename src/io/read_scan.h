// Reads a scan file into a Scan: OBJ (+MTL + diffuse texture), PLY (ASCII/binary, vertex
// colours) and glTF/GLB (base colour texture, embedded or external, or COLOR_0). Paper §3.
//
// OBJ and glTF go through assimp with triangulation only (no welding, no normal generation),
// so vertices come split per face corner/UV seam: run cleanScan (cleanup.h) afterwards to weld
// them. PLY is read by our own reader (read_ply.h), which keeps the file's vertices.
// Textures become per-vertex colours by bilinear sampling at each vertex's UV; the texture
// itself (image, UV, FUV) is kept in Scan::texture for export.
//
// Errors: missing/unreadable file → IoError; empty, truncated, garbage bytes, unknown
// extension or a file with no mesh → FormatError; a mesh without faces or with non-finite
// coordinates → InputError; a missing texture image → a warning in ReadReport.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "io/scan.h"

namespace s2p {

struct ReadOptions {
  bool loadTexture = true;  // false: skip images (vertex colours are still read)
};

struct ReadReport {
  std::string format;  // "obj", "ply", "gltf" or "glb"
  double seconds = 0;
  std::vector<std::string> warnings;
};

Scan readScan(const std::filesystem::path& path, const ReadOptions& options = {},
              ReadReport* report = nullptr);

// Extensions readScan accepts, lower case with the dot.
const std::vector<std::string>& supportedScanExtensions();

}  // namespace s2p
