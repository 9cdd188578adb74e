#include "io/write_mesh.h"

#include "core/colour.h"
#include "io/files.h"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>

#include "core/error.h"
#include "io/image.h"

namespace s2p {

namespace fs = std::filesystem;

// === Helpers

namespace {

fs::path folderOf(const fs::path& path) {
  return path.has_parent_path() ? path.parent_path() : fs::path(".");
}

}  // namespace

void writeFileAtomically(const fs::path& path,
                         const std::function<void(const fs::path& temporary)>& write) {
  static std::atomic<int> counter{0};
  const fs::path tmp = folderOf(path) / fmt::format(".{}.tmp{}_{}", path.filename().string(),
                                                    static_cast<long>(getpid()), counter++);
  try {
    write(tmp);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    std::error_code ec2;
    fs::remove(tmp, ec2);
    throw IoError(fmt::format("{}: cannot replace the file ({})", path.string(), ec.message()));
  }
}

void writeFileAtomically(const fs::path& path, const std::string& bytes) {
  writeFileAtomically(path, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out)
      throw IoError(
          fmt::format("{}: cannot create a file in {}; check the folder exists and is "
                      "writable",
                      path.string(), folderOf(path).string()));
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) throw IoError(fmt::format("{}: writing failed (disk full?)", path.string()));
  });
}

namespace {

template <typename T>
void put(std::string& out, T value) {
  char buf[sizeof(T)];
  std::memcpy(buf, &value, sizeof(T));  // host is little-endian (x86-64, aarch64)
  out.append(buf, sizeof(T));
}

std::uint8_t toByte(double c) {
  if (!std::isfinite(c)) return 0;
  return static_cast<std::uint8_t>(std::lround(std::clamp(c, 0.0, 1.0) * 255.0));
}

void checkAttributes(const fs::path& path, const TriMesh& mesh, const MeshAttributes& attrs) {
  const auto nv = mesh.V.rows(), nf = mesh.F.rows();
  if (attrs.colour && attrs.colour->rows() != nv)
    throw InputError(
        fmt::format("{}: {} colours for {} vertices", path.string(), attrs.colour->rows(), nv));
  if (attrs.vertexLabels && attrs.vertexLabels->size() != nv)
    throw InputError(fmt::format("{}: {} vertex labels for {} vertices", path.string(),
                                 attrs.vertexLabels->size(), nv));
  if (attrs.faceLabels && attrs.faceLabels->size() != nf)
    throw InputError(fmt::format("{}: {} face labels for {} faces", path.string(),
                                 attrs.faceLabels->size(), nf));
  if (attrs.faceGroups && attrs.faceGroups->size() != nf)
    throw InputError(fmt::format("{}: {} face groups for {} faces", path.string(),
                                 attrs.faceGroups->size(), nf));
  if (attrs.faceGroups && attrs.faceGroups->size() > 0 && attrs.faceGroups->minCoeff() < 0)
    throw InputError(fmt::format("{}: negative face group id", path.string()));
  for (int f = 0; f < mesh.numFaces(); ++f)
    for (int k = 0; k < 3; ++k)
      if (mesh.F(f, k) < 0 || mesh.F(f, k) >= nv)
        throw InputError(fmt::format("{}: face {} refers to vertex {} of {}", path.string(), f,
                                     mesh.F(f, k), nv));
}

std::string groupName(const MeshAttributes& attrs, int g) {
  if (attrs.groupNames && g >= 0 && g < static_cast<int>(attrs.groupNames->size()))
    return (*attrs.groupNames)[g];
  return fmt::format("group{}", g);
}

// Face order sorted stably by group id (identity without groups).
std::vector<int> facesByGroup(const TriMesh& mesh, const MeshAttributes& attrs) {
  std::vector<int> order(mesh.numFaces());
  std::iota(order.begin(), order.end(), 0);
  if (attrs.faceGroups)
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return (*attrs.faceGroups)(a) < (*attrs.faceGroups)(b); });
  return order;
}

}  // namespace

// === PLY

void writePly(const fs::path& path, const TriMesh& mesh, const MeshAttributes& attrs) {
  checkAttributes(path, mesh, attrs);
  std::string out;
  out += "ply\nformat binary_little_endian 1.0\ncomment written by scan2pattern\n";
  out += fmt::format("element vertex {}\n", mesh.numVertices());
  out += "property double x\nproperty double y\nproperty double z\n";
  if (attrs.colour) out += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (attrs.vertexLabels) out += "property int label\n";
  out += fmt::format("element face {}\n", mesh.numFaces());
  out += "property list uchar int vertex_indices\n";
  if (attrs.faceLabels) out += "property int label\n";
  if (attrs.faceGroups) out += "property int group\n";
  out += "end_header\n";
  const std::size_t vsize = 24 + (attrs.colour ? 3 : 0) + (attrs.vertexLabels ? 4 : 0);
  const std::size_t fsize = 13 + (attrs.faceLabels ? 4 : 0) + (attrs.faceGroups ? 4 : 0);
  out.reserve(out.size() + vsize * mesh.numVertices() + fsize * mesh.numFaces());
  for (int v = 0; v < mesh.numVertices(); ++v) {
    for (int k = 0; k < 3; ++k) put<double>(out, mesh.V(v, k));
    if (attrs.colour)
      for (int k = 0; k < 3; ++k) put<std::uint8_t>(out, toByte((*attrs.colour)(v, k)));
    if (attrs.vertexLabels) put<std::int32_t>(out, (*attrs.vertexLabels)(v));
  }
  for (int f = 0; f < mesh.numFaces(); ++f) {
    put<std::uint8_t>(out, 3);
    for (int k = 0; k < 3; ++k) put<std::int32_t>(out, mesh.F(f, k));
    if (attrs.faceLabels) put<std::int32_t>(out, (*attrs.faceLabels)(f));
    if (attrs.faceGroups) put<std::int32_t>(out, (*attrs.faceGroups)(f));
  }
  writeFileAtomically(path, out);
}

// === OBJ

void writeObj(const fs::path& path, const TriMesh& mesh, const MeshAttributes& attrs) {
  checkAttributes(path, mesh, attrs);
  std::string out = "# written by scan2pattern\n";
  for (int v = 0; v < mesh.numVertices(); ++v) {
    if (attrs.colour)
      out += fmt::format("v {:.9g} {:.9g} {:.9g} {:.6g} {:.6g} {:.6g}\n", mesh.V(v, 0),
                         mesh.V(v, 1), mesh.V(v, 2), (*attrs.colour)(v, 0), (*attrs.colour)(v, 1),
                         (*attrs.colour)(v, 2));
    else
      out += fmt::format("v {:.9g} {:.9g} {:.9g}\n", mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2));
  }
  int current = -1;
  for (int f : facesByGroup(mesh, attrs)) {
    if (attrs.faceGroups && (*attrs.faceGroups)(f) != current) {
      current = (*attrs.faceGroups)(f);
      out += fmt::format("g {}\n", groupName(attrs, current));
    }
    out += fmt::format("f {} {} {}\n", mesh.F(f, 0) + 1, mesh.F(f, 1) + 1, mesh.F(f, 2) + 1);
  }
  writeFileAtomically(path, out);
}

void writeObjTextured(const fs::path& path, const TriMesh& mesh, const Texture& texture) {
  checkAttributes(path, mesh, {});
  if (texture.FUV.rows() != mesh.F.rows())
    throw InputError(fmt::format("{}: texture has {} UV faces for {} faces", path.string(),
                                 texture.FUV.rows(), mesh.F.rows()));
  if (texture.FUV.size() > 0 &&
      (texture.FUV.minCoeff() < 0 || texture.FUV.maxCoeff() >= texture.UV.rows()))
    throw InputError(fmt::format("{}: a UV index is out of range", path.string()));
  const std::string stem = path.stem().string();
  const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
  const std::string png = encodePng(texture.image);
  writeFileAtomically(dir / (stem + ".png"), png);
  writeFileAtomically(
      dir / (stem + ".mtl"),
      fmt::format("newmtl scan\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nmap_Kd {}.png\n", stem));
  std::string out = fmt::format("# written by scan2pattern\nmtllib {}.mtl\n", stem);
  for (int v = 0; v < mesh.numVertices(); ++v)
    out += fmt::format("v {:.9g} {:.9g} {:.9g}\n", mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2));
  for (int t = 0; t < texture.UV.rows(); ++t)
    out += fmt::format("vt {:.9g} {:.9g}\n", texture.UV(t, 0), texture.UV(t, 1));
  out += "usemtl scan\n";
  for (int f = 0; f < mesh.numFaces(); ++f)
    out += fmt::format("f {}/{} {}/{} {}/{}\n", mesh.F(f, 0) + 1, texture.FUV(f, 0) + 1,
                       mesh.F(f, 1) + 1, texture.FUV(f, 1) + 1, mesh.F(f, 2) + 1,
                       texture.FUV(f, 2) + 1);
  writeFileAtomically(path, out);
}

// === GLB

void writeGlb(const fs::path& path, const TriMesh& mesh, const MeshAttributes& attrs) {
  checkAttributes(path, mesh, attrs);
  if (mesh.numFaces() == 0)  // glTF accessors must have count ≥ 1
    throw InputError(fmt::format("{}: a GLB needs at least one face", path.string()));
  using nlohmann::json;
  const int nv = mesh.numVertices();
  std::string bin;
  auto align4 = [&]() {
    while (bin.size() % 4) bin.push_back('\0');
  };
  json bufferViews = json::array(), accessors = json::array();

  // Positions (float32 VEC3) with the min/max the spec requires.
  const std::size_t posOffset = bin.size();
  Eigen::Vector3f lo = Eigen::Vector3f::Zero(), hi = Eigen::Vector3f::Zero();
  for (int v = 0; v < nv; ++v)
    for (int k = 0; k < 3; ++k) {
      const float x = static_cast<float>(mesh.V(v, k));
      put<float>(bin, x);
      lo[k] = v == 0 ? x : std::min(lo[k], x);
      hi[k] = v == 0 ? x : std::max(hi[k], x);
    }
  bufferViews.push_back({{"buffer", 0},
                         {"byteOffset", posOffset},
                         {"byteLength", bin.size() - posOffset},
                         {"target", 34962}});
  accessors.push_back({{"bufferView", 0},
                       {"componentType", 5126},
                       {"count", nv},
                       {"type", "VEC3"},
                       {"min", {lo[0], lo[1], lo[2]}},
                       {"max", {hi[0], hi[1], hi[2]}}});
  json attributes = {{"POSITION", 0}};

  if (attrs.colour) {
    align4();
    const std::size_t offset = bin.size();
    for (int v = 0; v < nv; ++v)
      for (int k = 0; k < 3; ++k)
        put<float>(bin, static_cast<float>(srgbToLinear(std::clamp((*attrs.colour)(v, k), 0.0, 1.0))));
    bufferViews.push_back({{"buffer", 0},
                           {"byteOffset", offset},
                           {"byteLength", bin.size() - offset},
                           {"target", 34962}});
    accessors.push_back({{"bufferView", bufferViews.size() - 1},
                         {"componentType", 5126},
                         {"count", nv},
                         {"type", "VEC3"}});
    attributes["COLOR_0"] = accessors.size() - 1;
  }

  // Indices (uint32), sorted by group; one accessor (and primitive) per group run.
  align4();
  const std::size_t idxOffset = bin.size();
  const std::vector<int> order = facesByGroup(mesh, attrs);
  for (int f : order)
    for (int k = 0; k < 3; ++k) put<std::uint32_t>(bin, static_cast<std::uint32_t>(mesh.F(f, k)));
  bufferViews.push_back({{"buffer", 0},
                         {"byteOffset", idxOffset},
                         {"byteLength", bin.size() - idxOffset},
                         {"target", 34963}});
  const int idxView = static_cast<int>(bufferViews.size()) - 1;
  json primitives = json::array(), groupNames = json::array();
  std::size_t start = 0;
  while (start < order.size()) {
    std::size_t end = order.size();
    int group = -1;
    if (attrs.faceGroups) {
      group = (*attrs.faceGroups)(order[start]);
      end = start;
      while (end < order.size() && (*attrs.faceGroups)(order[end]) == group) ++end;
    }
    accessors.push_back({{"bufferView", idxView},
                         {"byteOffset", start * 12},
                         {"componentType", 5125},
                         {"count", (end - start) * 3},
                         {"type", "SCALAR"}});
    primitives.push_back(
        {{"attributes", attributes}, {"indices", accessors.size() - 1}, {"mode", 4}});
    if (group >= 0) groupNames.push_back(groupName(attrs, group));
    start = end;
  }
  align4();

  json meshJson = {{"name", "scan"}, {"primitives", primitives}};
  if (!groupNames.empty()) meshJson["extras"] = {{"groups", groupNames}};
  const json doc = {{"asset", {{"version", "2.0"}, {"generator", "scan2pattern"}}},
                    {"scene", 0},
                    {"scenes", {{{"nodes", {0}}}}},
                    {"nodes", {{{"mesh", 0}}}},
                    {"meshes", {meshJson}},
                    {"accessors", accessors},
                    {"bufferViews", bufferViews},
                    {"buffers", {{{"byteLength", bin.size()}}}}};
  std::string text = doc.dump();
  while (text.size() % 4) text.push_back(' ');

  std::string out;
  const std::uint32_t total = static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size());
  put<std::uint32_t>(out, 0x46546C67u);  // "glTF"
  put<std::uint32_t>(out, 2u);
  put<std::uint32_t>(out, total);
  put<std::uint32_t>(out, static_cast<std::uint32_t>(text.size()));
  put<std::uint32_t>(out, 0x4E4F534Au);  // "JSON"
  out += text;
  put<std::uint32_t>(out, static_cast<std::uint32_t>(bin.size()));
  put<std::uint32_t>(out, 0x004E4942u);  // "BIN\0"
  out += bin;
  writeFileAtomically(path, out);
}

void writeMesh(const fs::path& path, const TriMesh& mesh, const MeshAttributes& attrs) {
  const std::string ext = lowerExtension(path);
  if (ext == ".ply") return writePly(path, mesh, attrs);
  if (ext == ".obj") return writeObj(path, mesh, attrs);
  if (ext == ".glb") return writeGlb(path, mesh, attrs);
  throw IoError(
      fmt::format("{}: unknown mesh extension '{}'; use .ply, .obj or .glb", path.string(), ext));
}

}  // namespace s2p
