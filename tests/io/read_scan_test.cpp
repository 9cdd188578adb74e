#include "io/read_scan.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <functional>
#include <nlohmann/json.hpp>
#include <set>

#include "io/cleanup.h"
#include "io/image.h"
#include "io/write_mesh.h"
#include "io_test_util.h"
#include "test_support.h"

namespace s2p {
namespace {

using test::TempDir;
using test::throwsExactly;

// 4×4 image of four 2×2 blocks: red (top-left), green (top-right), blue (bottom-left),
// yellow (bottom-right).
Image blockImage() {
  const std::uint8_t colours[4][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 0}};
  Image img;
  img.width = img.height = 4;
  img.rgb.resize(48);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      for (int c = 0; c < 3; ++c) img.rgb[(y * 4 + x) * 3 + c] = colours[(y / 2) * 2 + x / 2][c];
  return img;
}

Eigen::RowVector3d blockColour(int block) {
  const Image img = blockImage();
  const int x = (block % 2) * 2, y = (block / 2) * 2;
  const std::size_t o = (y * 4 + x) * 3;
  return Eigen::RowVector3d(img.rgb[o], img.rgb[o + 1], img.rgb[o + 2]) / 255.0;
}

// UV of block b's centre (OpenGL convention: v up, image row 0 at v = 1).
Eigen::RowVector2d blockUv(int block) {
  return {((block % 2) * 2 + 1) / 4.0, 1.0 - ((block / 2) * 2 + 1) / 4.0};
}

// 2×2 cells of unequal sizes (columns 1 and 2 wide, rows 1 and 1.5 high) written as quads;
// every corner of cell c has the UV of block c, so each face is one flat colour.
struct TexturedGrid {
  Eigen::MatrixX3d V{9, 3};
  std::vector<std::array<int, 4>> quads;
  TexturedGrid() {
    const double xs[3] = {0, 1, 3}, ys[3] = {0, 1, 2.5};
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) V.row(j * 3 + i) << xs[i], ys[j], 0;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        quads.push_back({j * 3 + i, j * 3 + i + 1, (j + 1) * 3 + i + 1, (j + 1) * 3 + i});
      }
  }
  std::string obj(const std::string& mtl) const {
    std::string s = "mtllib " + mtl + "\n";
    for (int v = 0; v < 9; ++v) s += fmt::format("v {} {} {}\n", V(v, 0), V(v, 1), V(v, 2));
    for (int c = 0; c < 4; ++c) s += fmt::format("vt {} {}\n", blockUv(c)[0], blockUv(c)[1]);
    s += "usemtl skin\n";
    for (int c = 0; c < 4; ++c)
      s += fmt::format("f {}/{} {}/{} {}/{} {}/{}\n", quads[c][0] + 1, c + 1, quads[c][1] + 1,
                       c + 1, quads[c][2] + 1, c + 1, quads[c][3] + 1, c + 1);
    return s;
  }
};

TEST(ReadScan, TexturedObjGivesBlockColoursAfterWeld) {
  TempDir dir;
  const TexturedGrid g;
  test::writeFile(dir / "blocks.png", encodePng(blockImage()));
  test::writeFile(dir / "a.mtl", "newmtl skin\nKd 1 1 1\nmap_Kd blocks.png\n");
  test::writeFile(dir / "a.obj", g.obj("a.mtl"));
  ReadReport report;
  Scan scan = readScan(dir / "a.obj", {}, &report);
  EXPECT_EQ(report.format, "obj");
  EXPECT_TRUE(report.warnings.empty());
  EXPECT_EQ(scan.colourSource, ColourSource::Texture);
  ASSERT_TRUE(scan.texture.has_value());
  EXPECT_EQ(scan.texture->image.width, 4);
  EXPECT_EQ(scan.texture->image.rgb, blockImage().rgb);
  EXPECT_EQ(scan.mesh.numFaces(), 8);  // quads triangulated

  cleanScan(scan);
  ASSERT_EQ(scan.mesh.numVertices(), 9);
  ASSERT_EQ(scan.mesh.numFaces(), 8);
  // Same vertices (as a set) and every face inside one original quad with its block's UV.
  std::vector<int> toOriginal(9, -1);
  for (int v = 0; v < 9; ++v)
    for (int w = 0; w < 9; ++w)
      if ((scan.mesh.V.row(v) - g.V.row(w)).norm() < 1e-12) toOriginal[v] = w;
  for (int v = 0; v < 9; ++v) ASSERT_GE(toOriginal[v], 0);
  std::set<std::set<int>> cornersByCell;
  // Expected colour: mean of the corners' block colours weighted by their triangle's area.
  Eigen::MatrixX3d want = Eigen::MatrixX3d::Zero(9, 3);
  Eigen::VectorXd weight = Eigen::VectorXd::Zero(9);
  const Eigen::VectorXd area = faceAreas(scan.mesh);
  for (int f = 0; f < 8; ++f) {
    const std::set<int> tri = {toOriginal[scan.mesh.F(f, 0)], toOriginal[scan.mesh.F(f, 1)],
                               toOriginal[scan.mesh.F(f, 2)]};
    int cell = -1;
    for (int c = 0; c < 4; ++c)
      if (std::includes(g.quads[c].begin(), g.quads[c].end(), tri.begin(), tri.end()) ||
          std::all_of(tri.begin(), tri.end(), [&](int v) {
            return std::find(g.quads[c].begin(), g.quads[c].end(), v) != g.quads[c].end();
          }))
        cell = c;
    ASSERT_GE(cell, 0) << "face " << f << " is not inside an original quad";
    EXPECT_TRUE(cornersByCell.insert(tri).second) << "face " << f << " repeated";
    for (int k = 0; k < 3; ++k) {
      EXPECT_LT((scan.texture->UV.row(scan.texture->FUV(f, k)) - blockUv(cell)).norm(), 1e-9);
      want.row(scan.mesh.F(f, k)) += area(f) * blockColour(cell);
      weight(scan.mesh.F(f, k)) += area(f);
    }
  }
  EXPECT_NEAR(area.sum(), 7.5, 1e-12);
  for (int v = 0; v < 9; ++v) {
    want.row(v) /= weight(v);
    EXPECT_LE((scan.colour.row(v) - want.row(v)).cwiseAbs().maxCoeff(), 1.0 / 255)
        << "vertex at " << scan.mesh.V.row(v) << " has " << scan.colour.row(v) << ", want "
        << want.row(v);
  }
  // Corners of the grid touch one cell only: exactly its block colour.
  for (int v = 0; v < 9; ++v)
    if (toOriginal[v] == 0) {
      EXPECT_LE((scan.colour.row(v) - blockColour(0)).norm(), 1e-9);
    }
}

TEST(ReadScan, MissingTextureIsAWarning) {
  TempDir dir;
  const TexturedGrid g;
  test::writeFile(dir / "a.mtl", "newmtl skin\nKd 1 1 1\nmap_Kd nowhere.png\n");
  test::writeFile(dir / "a.obj", g.obj("a.mtl"));
  ReadReport report;
  const Scan scan = readScan(dir / "a.obj", {}, &report);
  EXPECT_EQ(scan.colourSource, ColourSource::None);
  EXPECT_FALSE(scan.texture.has_value());
  ASSERT_EQ(report.warnings.size(), 1u);
  EXPECT_NE(report.warnings[0].find("nowhere.png"), std::string::npos);
  // loadTexture = false: no image, no warning.
  ReadReport quiet;
  readScan(dir / "a.obj", {.loadTexture = false}, &quiet);
  EXPECT_TRUE(quiet.warnings.empty());
}

// Rewrites a GLB written by writeGlb: `edit` changes its JSON, `extra` is appended to the
// binary chunk (offset returned through the callback's argument).
std::string editGlb(const std::string& glb,
                    const std::function<void(nlohmann::json&, std::string&)>& edit) {
  auto u32 = [&](std::size_t at) {
    std::uint32_t v;
    std::memcpy(&v, glb.data() + at, 4);
    return v;
  };
  const std::uint32_t jsonLen = u32(12);
  nlohmann::json j = nlohmann::json::parse(glb.substr(20, jsonLen));
  std::string bin = glb.substr(20 + jsonLen + 8, u32(20 + jsonLen));
  edit(j, bin);
  while (bin.size() % 4) bin.push_back('\0');
  j["buffers"][0]["byteLength"] = bin.size();
  std::string text = j.dump();
  while (text.size() % 4) text.push_back(' ');
  std::string out;
  auto put = [&](std::uint32_t v) { out.append(reinterpret_cast<const char*>(&v), 4); };
  put(0x46546C67u);
  put(2);
  put(static_cast<std::uint32_t>(28 + text.size() + bin.size()));
  put(static_cast<std::uint32_t>(text.size()));
  put(0x4E4F534Au);
  out += text;
  put(static_cast<std::uint32_t>(bin.size()));
  put(0x004E4942u);
  return out + bin;
}

TEST(ReadScan, GlbNodesAreConcatenatedWithTransforms) {
  TempDir dir;
  const TriMesh m = makeIcosphere(1, 0.5);
  writeGlb(dir / "one.glb", m);
  // Two nodes instancing the mesh: one translated by (2, 0, 0), one scaled by 2 about the origin.
  test::writeFile(dir / "two.glb",
                  editGlb(test::readFile(dir / "one.glb"), [](nlohmann::json& j, std::string&) {
                    j["nodes"] = {{{"mesh", 0}, {"translation", {2, 0, 0}}},
                                  {{"mesh", 0}, {"scale", {2, 2, 2}}}};
                    j["scenes"][0]["nodes"] = {0, 1};
                  }));
  Scan scan = readScan(dir / "two.glb");
  cleanScan(scan);
  ASSERT_EQ(scan.mesh.numVertices(), 2 * m.numVertices());
  const BoundingBox box = boundingBox(scan.mesh.V);
  EXPECT_NEAR(box.max.x(), 2.5, 1e-6);   // translated copy
  EXPECT_NEAR(box.min.x(), -1.0, 1e-6);  // scaled copy
  EXPECT_NEAR(box.max.y(), 1.0, 1e-6);
  EXPECT_NEAR(surfaceArea(scan.mesh), 5 * surfaceArea(m), 1e-4);
}

TEST(ReadScan, GlbEmbeddedBaseColourTexture) {
  TempDir dir;
  TriMesh quad;  // unit square, two faces
  quad.V.resize(4, 3);
  quad.V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  quad.F.resize(2, 3);
  quad.F << 0, 1, 2, 0, 2, 3;
  writeGlb(dir / "plain.glb", quad);
  // UVs: vertex v samples block v (red, green, blue, yellow).
  const std::string png = encodePng(blockImage());
  test::writeFile(
      dir / "tex.glb",
      editGlb(test::readFile(dir / "plain.glb"), [&](nlohmann::json& j, std::string& bin) {
        const std::size_t uvOffset = bin.size();
        for (int v = 0; v < 4; ++v) {
          // glTF UVs have v down: (u, 1 − v_GL).
          const float uv[2] = {static_cast<float>(blockUv(v)[0]),
                               static_cast<float>(1.0 - blockUv(v)[1])};
          bin.append(reinterpret_cast<const char*>(uv), 8);
        }
        const std::size_t imgOffset = bin.size();
        bin += png;
        j["bufferViews"].push_back(
            {{"buffer", 0}, {"byteOffset", uvOffset}, {"byteLength", 32}, {"target", 34962}});
        j["bufferViews"].push_back(
            {{"buffer", 0}, {"byteOffset", imgOffset}, {"byteLength", png.size()}});
        const int nViews = static_cast<int>(j["bufferViews"].size());
        j["accessors"].push_back(
            {{"bufferView", nViews - 2}, {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}});
        j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] = j["accessors"].size() - 1;
        j["meshes"][0]["primitives"][0]["material"] = 0;
        j["images"] = {{{"bufferView", nViews - 1}, {"mimeType", "image/png"}}};
        j["samplers"] = {{{"magFilter", 9729}, {"minFilter", 9729}}};
        j["textures"] = {{{"source", 0}, {"sampler", 0}}};
        j["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
      }));
  ReadReport report;
  Scan scan = readScan(dir / "tex.glb", {}, &report);
  EXPECT_TRUE(report.warnings.empty());
  ASSERT_EQ(scan.colourSource, ColourSource::Texture);
  ASSERT_TRUE(scan.texture.has_value());
  EXPECT_EQ(scan.texture->image.rgb, blockImage().rgb);
  cleanScan(scan);
  ASSERT_EQ(scan.mesh.numVertices(), 4);
  for (int v = 0; v < 4; ++v) {
    int w = 0;
    (scan.mesh.V.rowwise() - quad.V.row(v)).rowwise().squaredNorm().minCoeff(&w);
    EXPECT_LE((scan.colour.row(w) - blockColour(v)).cwiseAbs().maxCoeff(), 1.0 / 255) << v;
  }
}

TEST(ReadScan, ObjRelativeIndicesCommentsAndPolygons) {
  TempDir dir;
  test::writeFile(dir / "a.obj",
                  "# square and a pentagon\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                  "f -4 -3 -2 -1\nv 2 0 0\nv 2 1 0\nf 2 5 6 3\r\nf 1 2 3 4 1\n");
  Scan scan = readScan(dir / "a.obj");
  EXPECT_EQ(scan.mesh.numFaces(), 2 + 2 + 3);  // quad, quad, pentagon (repeats vertex 1)
  const CleanupReport r = cleanScan(scan);
  EXPECT_EQ(scan.mesh.numVertices(), 6);
  EXPECT_NEAR(surfaceArea(scan.mesh), 2.0, 1e-12);
  EXPECT_EQ(r.degenerateFaces + r.duplicateFaces, 3);  // the pentagon repeats the first quad
}

// === Bad input: each yields its documented error type.

TEST(ReadScan, MissingFileIsIoError) {
  TempDir dir;
  for (const char* name : {"nope.ply", "nope.obj", "nope.glb", "nope.xyz"})
    EXPECT_TRUE(throwsExactly<IoError>([&] { readScan(dir / name); })) << name;
}

TEST(ReadScan, EmptyGarbageTruncatedAndUnknownAreFormatErrors) {
  TempDir dir;
  const TriMesh m = makeIcosphere(2);
  writePly(dir / "good.ply", m);
  writeGlb(dir / "good.glb", m);
  const std::string ply = test::readFile(dir / "good.ply");
  const std::string glb = test::readFile(dir / "good.glb");
  std::string garbage;
  for (int i = 0; i < 3000; ++i) garbage.push_back(static_cast<char>((i * 7919 + 13) % 256));
  const std::pair<std::string, std::string> cases[] = {
      {"empty.ply", ""},
      {"empty.obj", ""},
      {"empty.glb", ""},
      {"empty.gltf", ""},
      {"garbage.ply", garbage},
      {"garbage.obj", garbage},
      {"garbage.glb", garbage},
      {"garbage.gltf", garbage},
      {"text.obj", "hello world\nthis is not a mesh\n"},
      {"text.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": 7}"},
      {"truncated.ply", ply.substr(0, ply.size() / 2)},
      {"header.ply", ply.substr(0, ply.find("end_header"))},
      {"truncated.glb", glb.substr(0, glb.size() / 2)},
      {"short.glb", glb.substr(0, 10)},
      {"badcount.ply",
       "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\n"
       "property float y\nproperty float z\nend_header\n\x01\x02"},
      {"badindex.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
       "0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n"},
      {"words.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n0 0 zero\n1 0 0\n0 1 0\n"},
      {"mesh.stl", "solid x\nendsolid x\n"},
      {"badindex.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 103\n"},
      {"badvt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/2 3/1\n"},
      {"zero.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"},
      {"relative.obj", "v 0 0 0\nv 1 0 0\nf -1 -2 -3\nv 0 1 0\n"},
      {"corner.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x3\n"},
  };
  for (const auto& [name, bytes] : cases) {
    test::writeFile(dir / name, bytes);
    EXPECT_TRUE(throwsExactly<FormatError>([&] { readScan(dir / name); })) << name;
  }
}

TEST(ReadScan, NoFacesAndNonFiniteAreInputErrors) {
  TempDir dir;
  const std::string header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const std::pair<std::string, std::string> cases[] = {
      {"points.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n"},
      {"nan.ply", header + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n"},
      {"inf.ply", header + "0 0 0\n1 0 0\n0 1e999 0\n3 0 1 2\n"},
      {"nan.obj", "v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n"},
      {"lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\n"},
  };
  for (const auto& [name, bytes] : cases) {
    test::writeFile(dir / name, bytes);
    EXPECT_TRUE(throwsExactly<InputError>([&] { readScan(dir / name); })) << name;
  }
}

}  // namespace
}  // namespace s2p
