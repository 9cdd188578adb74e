#include "io/read_scan.h"

#include "core/colour.h"
#include "io/files.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include <algorithm>
#include <assimp/Importer.hpp>
#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <map>

#include "core/error.h"
#include "io/image.h"
#include "io/read_ply.h"
#include "io/write_mesh.h"

namespace s2p {

namespace fs = std::filesystem;

const std::vector<std::string>& supportedScanExtensions() {
  static const std::vector<std::string> exts = {".obj", ".ply", ".gltf", ".glb"};
  return exts;
}

namespace {

std::uint32_t le32(const std::string& b, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, b.data() + at, 4);
  return v;
}

// OBJ: every face index must name an existing v/vt/vn (assimp throws, and leaks, otherwise).
void checkObjIndices(const std::string& bytes, const std::string& what) {
  long counts[3] = {0, 0, 0};  // v, vt, vn so far
  long totals[3] = {0, 0, 0};
  for (std::size_t pos = 0; pos < bytes.size();) {
    std::size_t end = bytes.find('\n', pos);
    if (end == std::string::npos) end = bytes.size();
    std::size_t b = pos;
    while (b < end && (bytes[b] == ' ' || bytes[b] == '\t')) ++b;
    auto starts = [&](const char* key) {
      const std::size_t n = std::strlen(key);
      return end - b > n && bytes.compare(b, n, key) == 0 &&
             (bytes[b + n] == ' ' || bytes[b + n] == '\t');
    };
    if (starts("v"))
      ++totals[0];
    else if (starts("vt"))
      ++totals[1];
    else if (starts("vn"))
      ++totals[2];
    pos = end + 1;
  }
  if (totals[0] == 0)
    throw FormatError(fmt::format("{}: no 'v' vertex lines: not an OBJ mesh", what));
  std::size_t lineNo = 0;
  for (std::size_t pos = 0; pos < bytes.size(); ++lineNo) {
    std::size_t end = bytes.find('\n', pos);
    if (end == std::string::npos) end = bytes.size();
    std::size_t b = pos;
    while (b < end && (bytes[b] == ' ' || bytes[b] == '\t')) ++b;
    const bool isSpace = end - b > 1 && (bytes[b + 1] == ' ' || bytes[b + 1] == '\t');
    const bool isV =
        end - b > 2 && bytes[b] == 'v' && (bytes[b + 2] == ' ' || bytes[b + 2] == '\t');
    if (end - b > 1 && bytes[b] == 'v' && isSpace)
      ++counts[0];
    else if (isV && bytes[b + 1] == 't')
      ++counts[1];
    else if (isV && bytes[b + 1] == 'n')
      ++counts[2];
    else if (end - b > 1 && bytes[b] == 'f' && !isSpace && bytes[b + 1] != '\r')
      throw FormatError(fmt::format("{}: line {}: malformed face line", what, lineNo + 1));
    else if (end - b > 1 && bytes[b] == 'f') {
      std::size_t i = b + 1;
      while (i < end) {
        while (i < end && (bytes[i] == ' ' || bytes[i] == '\t' || bytes[i] == '\r')) ++i;
        if (i >= end || bytes[i] == '#') break;
        for (int slot = 0; slot < 3 && i < end; ++slot) {
          if (slot > 0) {
            if (bytes[i] != '/') break;
            ++i;
          }
          long value = 0;
          const auto [ptr, ec] = std::from_chars(bytes.data() + i, bytes.data() + end, value);
          if (ec != std::errc()) {
            if (slot == 0)
              throw FormatError(fmt::format("{}: line {}: a face corner without a vertex index",
                                            what, lineNo + 1));
            continue;  // "1//3": no texture index
          }
          i = static_cast<std::size_t>(ptr - bytes.data());
          const long available = value < 0 ? counts[slot] : totals[slot];
          if (value == 0 || std::abs(value) > available)
            throw FormatError(fmt::format("{}: line {}: face index {} but the file has {} {}", what,
                                          lineNo + 1, value, available,
                                          slot == 0 ? "v" : (slot == 1 ? "vt" : "vn")));
        }
        if (i < end && bytes[i] != ' ' && bytes[i] != '\t' && bytes[i] != '\r')
          throw FormatError(fmt::format("{}: line {}: malformed face corner", what, lineNo + 1));
      }
    }
    pos = end + 1;
  }
}

// Cheap structural checks before handing bytes to assimp, which is slow or fragile on garbage.
void precheck(const std::string& ext, const std::string& bytes, const std::string& what) {
  if (ext == ".glb") {
    if (bytes.size() < 20)
      throw FormatError(fmt::format("{}: too short for a GLB ({} bytes)", what, bytes.size()));
    if (bytes.compare(0, 4, "glTF") != 0)
      throw FormatError(fmt::format("{}: not a GLB file (no 'glTF' magic)", what));
    if (le32(bytes, 4) != 2)
      throw FormatError(
          fmt::format("{}: GLB version {} is not supported; use glTF 2.0", what, le32(bytes, 4)));
    const std::uint64_t length = le32(bytes, 8);
    if (length > bytes.size())
      throw FormatError(fmt::format("{}: GLB header says {} bytes but the file has {}: truncated",
                                    what, length, bytes.size()));
    const std::uint64_t jsonLength = le32(bytes, 12);
    if (le32(bytes, 16) != 0x4E4F534Au || 20 + jsonLength > length)
      throw FormatError(fmt::format("{}: the GLB JSON chunk is missing or truncated", what));
    if (20 + jsonLength + 8 <= length) {
      const std::uint64_t binLength = le32(bytes, 20 + jsonLength);
      if (28 + jsonLength + binLength > length)
        throw FormatError(fmt::format("{}: the GLB binary chunk is truncated", what));
    }
    return;
  }
  // Text formats: NUL bytes near the start mean binary garbage.
  const std::size_t probe = std::min<std::size_t>(bytes.size(), 4096);
  if (std::memchr(bytes.data(), '\0', probe) != nullptr)
    throw FormatError(fmt::format("{}: binary bytes in a text {} file", what, ext));
  if (ext == ".gltf") {
    const std::size_t first = bytes.find_first_not_of(" \t\r\n\xEF\xBB\xBF");
    if (first == std::string::npos || bytes[first] != '{')
      throw FormatError(fmt::format("{}: not a glTF JSON file", what));
  }
  if (ext == ".obj") checkObjIndices(bytes, what);
}

Eigen::Matrix4d toEigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) e(r, c) = m[r][c];
  return e;
}

struct Builder {
  std::vector<Eigen::Vector3d> V;
  std::vector<Eigen::Vector3i> F;
  std::vector<Eigen::Vector3d> colour;  // per vertex, valid where hasColour
  std::vector<char> hasColour;
  std::vector<Eigen::Vector2d> uv;
  std::vector<const Image*> image;  // per vertex: the image its colour was sampled from
  int skippedFaces = 0;
};

class SceneReader {
 public:
  SceneReader(const aiScene& scene, const fs::path& path, bool linearColours,
              const ReadOptions& options, std::vector<std::string>& warnings)
      : scene_(scene),
        path_(path),
        linearColours_(linearColours),
        options_(options),
        warnings_(warnings) {}

  void readNode(const aiNode& node, const Eigen::Matrix4d& parent, int depth) {
    if (depth > 256) throw FormatError(fmt::format("{}: scene graph too deep", path_.string()));
    const Eigen::Matrix4d M = parent * toEigen(node.mTransformation);
    for (unsigned i = 0; i < node.mNumMeshes; ++i)
      if (node.mMeshes[i] < scene_.mNumMeshes) readMesh(*scene_.mMeshes[node.mMeshes[i]], M);
    for (unsigned c = 0; c < node.mNumChildren; ++c)
      if (node.mChildren[c]) readNode(*node.mChildren[c], M, depth + 1);
  }

  void readMesh(const aiMesh& mesh, const Eigen::Matrix4d& M) {
    const int base = static_cast<int>(b.V.size());
    const Image* image = mesh.HasTextureCoords(0) ? textureOf(mesh.mMaterialIndex) : nullptr;
    const bool vc = mesh.HasVertexColors(0);
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D& p = mesh.mVertices[v];
      const Eigen::Vector4d q = M * Eigen::Vector4d(p.x, p.y, p.z, 1.0);
      b.V.emplace_back(q.head<3>() / (q[3] != 0 ? q[3] : 1.0));
      Eigen::Vector2d t = Eigen::Vector2d::Zero();
      if (mesh.HasTextureCoords(0)) t = {mesh.mTextureCoords[0][v].x, mesh.mTextureCoords[0][v].y};
      b.uv.push_back(t);
      b.image.push_back(image);
      if (image) {
        b.colour.push_back(sampleBilinear(*image, t.x(), t.y()));
        b.hasColour.push_back(1);
      } else if (vc) {
        const aiColor4D& c = mesh.mColors[0][v];
        Eigen::Vector3d rgb(c.r, c.g, c.b);
        for (int k = 0; k < 3; ++k) {
          if (!std::isfinite(rgb[k])) rgb[k] = 0;
          rgb[k] = linearColours_ ? linearToSrgb(std::clamp(rgb[k], 0.0, 1.0)) : std::clamp(rgb[k], 0.0, 1.0);
        }
        b.colour.push_back(rgb);
        b.hasColour.push_back(1);
      } else {
        b.colour.emplace_back(Eigen::Vector3d::Constant(0.5));
        b.hasColour.push_back(0);
      }
    }
    anyVertexColour_ = anyVertexColour_ || (vc && !image);
    anyTextureColour_ = anyTextureColour_ || image;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) {  // points and lines
        ++b.skippedFaces;
        continue;
      }
      Eigen::Vector3i tri;
      for (int k = 0; k < 3; ++k) {
        if (face.mIndices[k] >= mesh.mNumVertices)
          throw FormatError(fmt::format("{}: face {} of mesh '{}' has an index out of range",
                                        path_.string(), f, mesh.mName.C_Str()));
        tri[k] = base + static_cast<int>(face.mIndices[k]);
      }
      b.F.push_back(tri);
    }
  }

  Builder b;
  bool anyVertexColour_ = false;
  bool anyTextureColour_ = false;
  std::map<std::string, Image> images_;  // by texture reference
  std::string firstImage_;
  std::string firstImagePath_;

 private:
  const Image* textureOf(unsigned materialIndex) {
    if (!options_.loadTexture || materialIndex >= scene_.mNumMaterials) return nullptr;
    const aiMaterial* mat = scene_.mMaterials[materialIndex];
    aiString ref;
    if (mat->GetTexture(aiTextureType_BASE_COLOR, 0, &ref) != AI_SUCCESS &&
        mat->GetTexture(aiTextureType_DIFFUSE, 0, &ref) != AI_SUCCESS)
      return nullptr;
    const std::string key = ref.C_Str();
    if (key.empty()) return nullptr;
    if (auto it = images_.find(key); it != images_.end())
      return it->second.width > 0 ? &it->second : nullptr;
    Image& slot = images_[key];  // an empty image marks a failed load
    std::string where = key;
    try {
      if (const aiTexture* tex = scene_.GetEmbeddedTexture(key.c_str())) {
        where = fmt::format("{} (embedded texture {})", path_.string(), key);
        if (tex->mHeight == 0) {
          slot =
              decodeImage(reinterpret_cast<const std::uint8_t*>(tex->pcData), tex->mWidth, where);
        } else {
          slot.width = static_cast<int>(tex->mWidth);
          slot.height = static_cast<int>(tex->mHeight);
          slot.rgb.resize(static_cast<std::size_t>(tex->mWidth) * tex->mHeight * 3);
          for (std::size_t i = 0; i < static_cast<std::size_t>(tex->mWidth) * tex->mHeight; ++i) {
            slot.rgb[3 * i] = tex->pcData[i].r;
            slot.rgb[3 * i + 1] = tex->pcData[i].g;
            slot.rgb[3 * i + 2] = tex->pcData[i].b;
          }
        }
      } else {
        std::string rel = key;
        std::replace(rel.begin(), rel.end(), '\\', '/');
        fs::path file = fs::path(rel);
        if (file.is_relative()) file = path_.parent_path() / file;
        where = file.string();
        std::error_code ec;
        if (!fs::is_regular_file(file, ec)) {
          warnings_.push_back(
              fmt::format("{}: texture '{}' not found; continuing without its "
                          "colours",
                          path_.string(), file.string()));
          return nullptr;
        }
        slot = readImage(file);
      }
    } catch (const Error& e) {
      slot = Image{};
      warnings_.push_back(fmt::format("texture {} unusable: {}", where, e.what()));
      return nullptr;
    }
    if (firstImage_.empty()) {
      firstImage_ = key;
      firstImagePath_ = where;
    } else if (key != firstImage_) {
      warnings_.push_back(
          fmt::format("{}: several textures; colours are sampled from each but "
                      "only '{}' is kept for export",
                      path_.string(), firstImage_));
    }
    return &slot;
  }

  const aiScene& scene_;
  fs::path path_;
  bool linearColours_;
  const ReadOptions& options_;
  std::vector<std::string>& warnings_;
};

Scan readWithAssimp(const fs::path& path, const std::string& ext, const ReadOptions& options,
                    std::vector<std::string>& warnings) {
  Assimp::Importer importer;
  const aiScene* scene =
      importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_ValidateDataStructure);
  if (scene == nullptr)
    throw FormatError(fmt::format("{}: cannot be read as {} ({}); re-export the file",
                                  path.string(), ext, importer.GetErrorString()));
  if (scene->mNumMeshes == 0 || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw FormatError(fmt::format("{}: the file contains no mesh", path.string()));

  SceneReader reader(*scene, path, ext == ".gltf" || ext == ".glb", options, warnings);
  if (scene->mRootNode) reader.readNode(*scene->mRootNode, Eigen::Matrix4d::Identity(), 0);
  if (reader.b.V.empty())  // meshes not attached to any node
    for (unsigned m = 0; m < scene->mNumMeshes; ++m)
      reader.readMesh(*scene->mMeshes[m], Eigen::Matrix4d::Identity());

  Builder& b = reader.b;
  Scan scan;
  const auto nv = static_cast<Eigen::Index>(b.V.size());
  scan.mesh.V.resize(nv, 3);
  for (Eigen::Index v = 0; v < nv; ++v) scan.mesh.V.row(v) = b.V[v].transpose();
  scan.mesh.F.resize(static_cast<Eigen::Index>(b.F.size()), 3);
  for (std::size_t f = 0; f < b.F.size(); ++f)
    scan.mesh.F.row(static_cast<Eigen::Index>(f)) = b.F[f].transpose();
  if (b.skippedFaces > 0)
    warnings.push_back(
        fmt::format("{}: {} point/line primitives ignored", path.string(), b.skippedFaces));

  if (reader.anyTextureColour_ || reader.anyVertexColour_) {
    scan.colour.resize(nv, 3);
    for (Eigen::Index v = 0; v < nv; ++v) scan.colour.row(v) = b.colour[v].transpose();
    scan.colourSource = reader.anyTextureColour_ ? ColourSource::Texture : ColourSource::Vertex;
  }
  if (reader.anyTextureColour_) {
    Texture tex;
    tex.image = reader.images_.at(reader.firstImage_);
    tex.path = reader.firstImagePath_;
    tex.UV.resize(nv, 2);
    for (Eigen::Index v = 0; v < nv; ++v) tex.UV.row(v) = b.uv[v].transpose();
    tex.FUV = scan.mesh.F;  // one UV per assimp vertex
    scan.texture = std::move(tex);
  }
  return scan;
}

}  // namespace

Scan readScan(const fs::path& path, const ReadOptions& options, ReadReport* report) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string ext = lowerExtension(path);
  const auto& exts = supportedScanExtensions();
  std::error_code ec;
  if (!fs::exists(path, ec))
    throw IoError(fmt::format("{}: no such file; check the path", path.string()));
  if (std::find(exts.begin(), exts.end(), ext) == exts.end())
    throw FormatError(fmt::format("{}: unknown scan format '{}'; use .obj, .ply, .gltf or .glb",
                                  path.string(), ext));
  const std::string bytes = readFileBytes(path);
  if (bytes.empty()) throw FormatError(fmt::format("{}: the file is empty", path.string()));

  std::vector<std::string> warnings;
  Scan scan;
  if (ext == ".ply") {
    PlyData ply = parsePly(bytes, path.string());
    scan.mesh = std::move(ply.mesh);
    if (ply.colour.rows() > 0) {
      scan.colour = std::move(ply.colour);
      scan.colourSource = ColourSource::Vertex;
    }
    warnings = std::move(ply.warnings);
  } else {
    precheck(ext, bytes, path.string());
    scan = readWithAssimp(path, ext, options, warnings);
  }
  scan.sourcePath = path.string();
  validateMesh(scan.mesh, path.string());  // no faces / non-finite → InputError

  if (report) {
    report->format = ext.substr(1);
    report->warnings.insert(report->warnings.end(), warnings.begin(), warnings.end());
    report->seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return scan;
}

}  // namespace s2p
