#include "io/write_mesh.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "io/cleanup.h"
#include "io/read_ply.h"
#include "io/read_scan.h"
#include "io_test_util.h"
#include "test_support.h"

namespace s2p {
namespace {

using test::TempDir;
using test::throwsExactly;

// A mesh with distinct per-vertex colours and labels.
struct Sample {
  TriMesh mesh = makeIcosphere(2, 0.8);
  Eigen::MatrixX3d colour;
  Eigen::VectorXi labels;
  Sample() {
    const int n = mesh.numVertices();
    colour.resize(n, 3);
    labels.resize(n);
    for (int v = 0; v < n; ++v) {
      colour.row(v) << (v % 256) / 255.0, ((v * 7) % 256) / 255.0, ((v * 13) % 256) / 255.0;
      labels(v) = v % 5 - 2;
    }
    mesh.V.col(1).array() += 0.3;  // off-centre so that min/max are not symmetric
  }
};

// Index of the vertex of `V` at `p` (nearest).
int nearest(const Eigen::MatrixX3d& V, const Eigen::RowVector3d& p) {
  int best = 0;
  (V.rowwise() - p).rowwise().squaredNorm().minCoeff(&best);
  return best;
}

TEST(WritePly, BinaryRoundTripKeepsVerticesColoursLabels) {
  TempDir dir;
  const Sample s;
  Eigen::VectorXi faceLabels(s.mesh.numFaces());
  for (int f = 0; f < s.mesh.numFaces(); ++f) faceLabels(f) = (f * 7) % 6;
  writePly(dir / "a.ply", s.mesh,
           {.colour = &s.colour, .vertexLabels = &s.labels, .faceLabels = &faceLabels});
  const PlyData back = readPly(dir / "a.ply");
  EXPECT_EQ(back.faceLabels, faceLabels);
  ASSERT_EQ(back.mesh.numVertices(), s.mesh.numVertices());
  EXPECT_EQ(back.mesh.F, s.mesh.F);
  EXPECT_LT((back.mesh.V - s.mesh.V).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LE((back.colour - s.colour).cwiseAbs().maxCoeff(), 1.0 / 255 + 1e-12);
  EXPECT_EQ(back.labels, s.labels);
  // readScan gives the same mesh with vertex colours.
  const Scan scan = readScan(dir / "a.ply");
  EXPECT_EQ(scan.colourSource, ColourSource::Vertex);
  EXPECT_EQ(scan.mesh.F, s.mesh.F);
}

TEST(ReadPly, AsciiAndBigEndianWithColoursAndQuads) {
  TempDir dir;
  // A unit square as one quad (fan-triangulated), float colours, an extra element to skip.
  const std::string ascii =
      "ply\nformat ascii 1.0\ncomment hand written\nelement vertex 4\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty int label\n"
      "element face 1\nproperty list uchar int vertex_indices\n"
      "element extra 2\nproperty list uchar float junk\nend_header\n"
      "0 0 0 255 0 0 7\n1 0 0 0 255 0 -3\n1 1 0 0 0 255 0\n0 1 0 10 20 30 1\n"
      "4 0 1 2 3\n2 1.5 2.5\n0\n";
  test::writeFile(dir / "a.ply", ascii);
  const PlyData a = readPly(dir / "a.ply");
  ASSERT_EQ(a.mesh.numVertices(), 4);
  ASSERT_EQ(a.mesh.numFaces(), 2);
  EXPECT_EQ(a.mesh.F.row(0), Eigen::RowVector3i(0, 1, 2));
  EXPECT_EQ(a.mesh.F.row(1), Eigen::RowVector3i(0, 2, 3));
  EXPECT_EQ(a.mesh.V.row(2), Eigen::RowVector3d(1, 1, 0));
  EXPECT_NEAR(a.colour(3, 1), 20 / 255.0, 1e-12);
  EXPECT_EQ(a.labels, (Eigen::VectorXi(4) << 7, -3, 0, 1).finished());

  // The same square, binary big-endian with double coordinates.
  std::string be =
      "ply\nformat binary_big_endian 1.0\nelement vertex 4\nproperty double x\n"
      "property double y\nproperty double z\nelement face 1\n"
      "property list uchar uint vertex_indices\nend_header\n";
  auto putBe = [&](const void* p, std::size_t n) {
    const char* c = static_cast<const char*>(p);
    for (std::size_t i = 0; i < n; ++i) be.push_back(c[n - 1 - i]);
  };
  for (int v = 0; v < 4; ++v)
    for (int k = 0; k < 3; ++k) {
      const double x = a.mesh.V(v, k) + 0.25;
      putBe(&x, 8);
    }
  be.push_back(4);
  for (std::uint32_t i : {0u, 1u, 2u, 3u}) putBe(&i, 4);
  test::writeFile(dir / "b.ply", be);
  const PlyData b = readPly(dir / "b.ply");
  EXPECT_EQ(b.mesh.F, a.mesh.F);
  EXPECT_TRUE(b.mesh.V.isApprox((a.mesh.V.array() + 0.25).matrix()));
}

TEST(WriteObj, GroupsAndColoursRoundTripThroughAssimp) {
  TempDir dir;
  const Sample s;
  Eigen::VectorXi groups(s.mesh.numFaces());
  for (int f = 0; f < groups.size(); ++f) groups(f) = s.mesh.V(s.mesh.F(f, 0), 0) > 0 ? 1 : 0;
  const std::vector<std::string> names = {"left", "right"};
  writeObj(dir / "a.obj", s.mesh,
           {.colour = &s.colour, .faceGroups = &groups, .groupNames = &names});
  const std::string text = test::readFile(dir / "a.obj");
  EXPECT_NE(text.find("g left\n"), std::string::npos);
  EXPECT_NE(text.find("g right\n"), std::string::npos);
  Scan scan = readScan(dir / "a.obj");
  EXPECT_EQ(scan.colourSource, ColourSource::Vertex);
  cleanScan(scan);
  ASSERT_EQ(scan.mesh.numVertices(), s.mesh.numVertices());
  ASSERT_EQ(scan.mesh.numFaces(), s.mesh.numFaces());
  for (int v = 0; v < s.mesh.numVertices(); ++v) {
    const int w = nearest(scan.mesh.V, s.mesh.V.row(v));
    EXPECT_LT((scan.mesh.V.row(w) - s.mesh.V.row(v)).norm(), 1e-6);
    EXPECT_LT((scan.colour.row(w) - s.colour.row(v)).cwiseAbs().maxCoeff(), 1.0 / 255);
  }
}

struct GlbParts {
  std::uint32_t magic = 0, version = 0, length = 0;
  nlohmann::json json;
  std::string bin;
};

// Splits a GLB into its chunks, asserting the container's structural rules.
GlbParts parseGlb(const std::string& bytes) {
  auto u32 = [&](std::size_t at) {
    std::uint32_t v;
    std::memcpy(&v, bytes.data() + at, 4);
    return v;
  };
  GlbParts p;
  EXPECT_GE(bytes.size(), 28u);
  p.magic = u32(0);
  p.version = u32(4);
  p.length = u32(8);
  EXPECT_EQ(p.magic, 0x46546C67u);
  EXPECT_EQ(p.version, 2u);
  EXPECT_EQ(p.length, bytes.size());
  const std::uint32_t jsonLen = u32(12);
  EXPECT_EQ(u32(16), 0x4E4F534Au);
  EXPECT_EQ(jsonLen % 4, 0u);
  p.json = nlohmann::json::parse(bytes.substr(20, jsonLen));
  const std::size_t binHeader = 20 + jsonLen;
  const std::uint32_t binLen = u32(binHeader);
  EXPECT_EQ(u32(binHeader + 4), 0x004E4942u);
  EXPECT_EQ(binLen % 4, 0u);
  EXPECT_EQ(binHeader + 8 + binLen, bytes.size());
  p.bin = bytes.substr(binHeader + 8, binLen);
  return p;
}

TEST(WriteGlb, StructureIsValidGltf) {
  TempDir dir;
  const Sample s;
  Eigen::VectorXi groups = Eigen::VectorXi::Zero(s.mesh.numFaces());
  groups.tail(10).setConstant(2);
  writeGlb(dir / "a.glb", s.mesh, {.colour = &s.colour, .faceGroups = &groups});
  const GlbParts p = parseGlb(test::readFile(dir / "a.glb"));
  const auto& j = p.json;
  EXPECT_EQ(j["asset"]["version"], "2.0");
  EXPECT_EQ(j["buffers"][0]["byteLength"], p.bin.size());
  for (const auto& view : j["bufferViews"]) {
    EXPECT_TRUE(view.contains("target"));
    EXPECT_EQ(view["byteOffset"].get<std::size_t>() % 4, 0u);
    EXPECT_LE(view["byteOffset"].get<std::size_t>() + view["byteLength"].get<std::size_t>(),
              p.bin.size());
  }
  const auto& prims = j["meshes"][0]["primitives"];
  ASSERT_EQ(prims.size(), 2u);  // groups 0 and 2
  std::size_t indexCount = 0;
  for (const auto& prim : prims) {
    const auto& pos = j["accessors"][prim["attributes"]["POSITION"].get<int>()];
    EXPECT_EQ(pos["count"], s.mesh.numVertices());
    EXPECT_EQ(pos["type"], "VEC3");
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(pos["min"][k].get<double>(), s.mesh.V.col(k).minCoeff(), 1e-6);
      EXPECT_NEAR(pos["max"][k].get<double>(), s.mesh.V.col(k).maxCoeff(), 1e-6);
    }
    EXPECT_EQ(j["accessors"][prim["attributes"]["COLOR_0"].get<int>()]["count"],
              s.mesh.numVertices());
    const auto& idx = j["accessors"][prim["indices"].get<int>()];
    EXPECT_EQ(idx["componentType"], 5125);
    indexCount += idx["count"].get<std::size_t>();
  }
  EXPECT_EQ(indexCount, 3u * s.mesh.numFaces());
  EXPECT_EQ(j["accessors"][prims[1]["indices"].get<int>()]["count"], 30);
  // Positions in the buffer are the mesh's vertices (float32).
  const auto& pos = j["accessors"][0];
  const auto& view = j["bufferViews"][pos["bufferView"].get<int>()];
  float first[3];
  std::memcpy(first, p.bin.data() + view["byteOffset"].get<std::size_t>(), 12);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(first[k], s.mesh.V(0, k), 1e-6);
}

TEST(WriteGlb, RoundTripThroughAssimp) {
  TempDir dir;
  const Sample s;
  Eigen::VectorXi groups = Eigen::VectorXi::Zero(s.mesh.numFaces());
  groups.head(40).setConstant(1);  // two primitives: assimp reads two meshes
  writeGlb(dir / "a.glb", s.mesh, {.colour = &s.colour, .faceGroups = &groups});
  ReadReport report;
  Scan scan = readScan(dir / "a.glb", {}, &report);
  EXPECT_EQ(report.format, "glb");
  EXPECT_EQ(scan.colourSource, ColourSource::Vertex);
  cleanScan(scan);
  ASSERT_EQ(scan.mesh.numVertices(), s.mesh.numVertices());
  ASSERT_EQ(scan.mesh.numFaces(), s.mesh.numFaces());
  const Eigen::MatrixX3d N = faceNormals(scan.mesh);
  for (int v = 0; v < s.mesh.numVertices(); ++v) {
    const int w = nearest(scan.mesh.V, s.mesh.V.row(v));
    EXPECT_LT((scan.mesh.V.row(w) - s.mesh.V.row(v)).norm(), 1e-6);
    EXPECT_LE((scan.colour.row(w) - s.colour.row(v)).cwiseAbs().maxCoeff(), 1.0 / 255) << v;
  }
  // Orientation kept: normals still point outwards from the sphere's centre.
  const Eigen::RowVector3d centre(0, 0.3, 0);
  for (int f = 0; f < scan.mesh.numFaces(); ++f)
    EXPECT_GT(N.row(f).dot(scan.mesh.V.row(scan.mesh.F(f, 0)) - centre), 0);
}

TEST(WriteMesh, ChoosesByExtensionAndRejectsOthers) {
  TempDir dir;
  const TriMesh m = makeGrid(2, 2);
  writeMesh(dir / "a.PLY", m);
  writeMesh(dir / "a.obj", m);
  writeMesh(dir / "a.glb", m);
  EXPECT_EQ(test::readFile(dir / "a.PLY").substr(0, 4), "ply\n");
  EXPECT_EQ(test::readFile(dir / "a.glb").substr(0, 4), "glTF");
  EXPECT_EQ(test::readFile(dir / "a.obj").substr(0, 1), "#");
  EXPECT_TRUE(throwsExactly<IoError>([&] { writeMesh(dir / "a.stl", m); }));
}

TEST(WriteMesh, UnwritablePathThrowsAndLeavesNothing) {
  TempDir dir;
  const TriMesh m = makeGrid(2, 2);
  const auto missing = dir / "no" / "such" / "dir" / "a.ply";
  EXPECT_TRUE(throwsExactly<IoError>([&] { writePly(missing, m); }));
  EXPECT_TRUE(throwsExactly<IoError>([&] { writeGlb(dir / "no" / "a.glb", m); }));
  // A failing write keeps the previous file intact and leaves no temporary behind.
  writePly(dir / "keep.ply", m);
  const std::string before = test::readFile(dir / "keep.ply");
  const Eigen::MatrixX3d colour = Eigen::MatrixX3d::Zero(2, 3);  // wrong row count
  EXPECT_TRUE(
      throwsExactly<InputError>([&] { writePly(dir / "keep.ply", m, {.colour = &colour}); }));
  EXPECT_EQ(test::readFile(dir / "keep.ply"), before);
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.path())) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 1);
}

}  // namespace
}  // namespace s2p
