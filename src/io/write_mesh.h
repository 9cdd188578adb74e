// Mesh writers: PLY (binary little-endian), OBJ (+ groups, vertex colours, or MTL + PNG
// texture) and GLB (glTF 2.0 binary). Each writes a temporary file beside the target and
// renames it at the end, so a failure never leaves a half-written file.
#pragma once

#include <Eigen/Core>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "core/tri_mesh.h"
#include "io/scan.h"

namespace s2p {

// Optional per-element data written with a mesh; null pointers are left out.
struct MeshAttributes {
  const Eigen::MatrixX3d* colour = nullptr;              // #V×3 sRGB in [0, 1]
  const Eigen::VectorXi* vertexLabels = nullptr;         // #V, written to PLY "label"
  const Eigen::VectorXi* faceLabels = nullptr;           // #F, written to PLY face "label"
  const Eigen::VectorXi* faceGroups = nullptr;           // #F group ids in [0, #groups)
  const std::vector<std::string>* groupNames = nullptr;  // name of each group id
};

// Binary little-endian PLY: double x y z, uchar red green blue, int label; faces as
// "list uchar int vertex_indices" plus int "label" / int "group" when given.
void writePly(const std::filesystem::path& path, const TriMesh& mesh,
              const MeshAttributes& attrs = {});
// Wavefront OBJ: "v x y z [r g b]", faces grouped by "g name" (faces sorted stably by group).
void writeObj(const std::filesystem::path& path, const TriMesh& mesh,
              const MeshAttributes& attrs = {});
// glTF 2.0 binary: POSITION (+ min/max), COLOR_0 (linear RGB float, converted from sRGB as the
// spec requires), one primitive per face group (named in mesh.extras.groups).
void writeGlb(const std::filesystem::path& path, const TriMesh& mesh,
              const MeshAttributes& attrs = {});
// By extension (case-insensitive): .ply, .obj, .glb; anything else → IoError.
void writeMesh(const std::filesystem::path& path, const TriMesh& mesh,
               const MeshAttributes& attrs = {});
// OBJ with "vt" and "f v/vt", a material file <stem>.mtl and the image as <stem>.png beside it.
// texture.FUV must have #F rows; texture.UV is in OpenGL convention.
void writeObjTextured(const std::filesystem::path& path, const TriMesh& mesh,
                      const Texture& texture);

// Writes `bytes` to a temporary file in the target's folder, then renames it onto `path`.
// Throws IoError (naming the path) when the folder is not writable.
void writeFileAtomically(const std::filesystem::path& path, const std::string& bytes);
// Same for writers that open the file themselves (dxflib): `write` writes a temporary path in the
// target's folder, which is renamed onto `path` when it returns and removed when it throws.
void writeFileAtomically(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path& temporary)>& write);

}  // namespace s2p
