// An OBJ's geometry as the file indexes it: its `v` records in file order and its `f` records
// (polygons fan-triangulated, `v/vt/vn` references reduced to the vertex), with no vertex split
// per corner and none welded. For meshes this program wrote itself (a cut garment of `segment`),
// whose topology must come back exactly: assimp splits vertices per corner, and welding them
// again by position joins distinct vertices that round to the same written coordinates (the
// exact cut's new vertices a hair from an old one), which makes a manifold garment non-manifold.
// A scan a user brings goes through readScan (materials, textures, groups).
#pragma once

#include <filesystem>
#include <string>

#include "core/tri_mesh.h"

namespace s2p {

// Missing/unreadable → IoError; a record that does not parse, an index out of range or a file
// with no vertex → FormatError naming the file and line.
TriMesh readObjGeometry(const std::filesystem::path& path);
// The same on text in memory; `what` names the source in messages.
TriMesh parseObjGeometry(const std::string& text, const std::string& what);

}  // namespace s2p
