// The `scan2pattern` command end to end: every bad input gets its documented exit code and a
// message, good input gives the known answer, and no half-written output is left behind.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "cli_support.h"
#include "core/shapes.h"
#include "io/read_scan.h"
#include "io/write_mesh.h"
#include "test_support.h"

namespace s2p {
namespace {

using test::CliRun;
using test::q;
CliRun run(const std::string& args) {
  return test::runCli(args);
}

// A closed person-sized box figure (1.7 m tall) in millimetres with +Z up: feet blocks, a
// torso and a head, so units and the up axis are detectable.
TriMesh personInMillimetresZUp() {
  TriMesh m = makeIcosphere(2, 1.0);
  // Stretch into a 0.4 × 1.7 × 0.25 m ellipsoid standing on z = 0, in mm, +Z up.
  for (int v = 0; v < m.numVertices(); ++v) {
    const Eigen::RowVector3d p = m.V.row(v);
    m.V.row(v) << 200.0 * p.x(), -125.0 * p.z(), 850.0 * (p.y() + 1.0);
  }
  return m;
}

TEST(Cli, HelpAndVersionAndUsage) {
  EXPECT_EQ(run("--version").code, 0);
  const CliRun help = run("--help");
  EXPECT_EQ(help.code, 0);
  EXPECT_NE(help.out.find("info"), std::string::npos);
  EXPECT_NE(help.out.find("Exit codes"), std::string::npos);
  EXPECT_EQ(run("").code, 2);
  EXPECT_EQ(run("no-such-command").code, 2);
  EXPECT_EQ(run("info").code, 2);  // SCAN missing
}

TEST(Cli, InfoReportsKnownCountsUnitsAndAxis) {
  test::TempDir dir;
  const TriMesh m = personInMillimetresZUp();
  writePly(dir / "person.ply", m);
  const CliRun r = run("info --json " + q(dir / "person.ply"));
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["vertices"].get<int>(), m.numVertices());
  EXPECT_EQ(j["faces"].get<int>(), m.numFaces());
  EXPECT_EQ(j["components"].get<int>(), 1);
  EXPECT_EQ(j["boundary_loops"].get<int>(), 0);
  EXPECT_EQ(j["euler_characteristic"].get<int>(), 2);
  EXPECT_TRUE(j["manifold"].get<bool>());
  EXPECT_EQ(j["units"].get<std::string>(), "mm");
  EXPECT_NEAR(j["height_m"].get<double>(), 1.7, 1e-9);
  EXPECT_NEAR(j["bbox_min_m"][1].get<double>(), 0.0, 1e-9);
  EXPECT_EQ(j["colour_source"].get<std::string>(), "none");
}

TEST(Cli, ConvertWritesMetresYUpAndBackToTheInputFrame) {
  test::TempDir dir;
  writePly(dir / "person.ply", personInMillimetresZUp());
  ASSERT_EQ(run("-q convert " + q(dir / "person.ply") + " " + q(dir / "out.glb")).code, 0);
  const Scan s = readScan(dir / "out.glb");
  const BoundingBox box = boundingBox(s.mesh.V);
  EXPECT_NEAR(box.extent().y(), 1.7, 1e-4);  // GLB stores float32
  EXPECT_NEAR(box.min.y(), 0.0, 1e-4);
  ASSERT_EQ(
      run("-q convert --input-frame " + q(dir / "person.ply") + " " + q(dir / "back.ply")).code, 0);
  const Scan back = readScan(dir / "back.ply");
  EXPECT_NEAR(boundingBox(back.mesh.V).extent().z(), 1700.0, 1e-3);
}

TEST(Cli, BadInputsGetTheirExitCodes) {
  test::TempDir dir;
  // 3: missing file, unwritable output.
  CliRun r = run("info " + q(dir / "missing.ply"));
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("missing.ply"), std::string::npos);
  writePly(dir / "person.ply", personInMillimetresZUp());
  r = run("convert " + q(dir / "person.ply") + " " + q(dir / "no" / "such" / "dir" / "x.ply"));
  EXPECT_EQ(r.code, 3) << r.out;
  // 4: empty, garbage, truncated, unknown format.
  test::writeFile(dir / "empty.ply", "");
  EXPECT_EQ(run("info " + q(dir / "empty.ply")).code, 4);
  const char garbage[] = "\x7f\x01\x02 not an obj \xff\xfe";
  test::writeFile(dir / "garbage.obj", std::string(garbage, sizeof garbage - 1));
  EXPECT_EQ(run("info " + q(dir / "garbage.obj")).code, 4);
  const std::string good = test::readFile(dir / "person.ply");
  test::writeFile(dir / "truncated.ply", good.substr(0, good.size() / 2));
  EXPECT_EQ(run("info " + q(dir / "truncated.ply")).code, 4);
  test::writeFile(dir / "mesh.stl", "solid x\nendsolid x\n");
  EXPECT_EQ(run("info " + q(dir / "mesh.stl")).code, 4);
  // 5: no faces, non-finite coordinates, not a person.
  test::writeFile(dir / "points.ply",
                  "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 0\nproperty list uchar int vertex_indices\n"
                  "end_header\n0 0 0\n1 0 0\n0 1 0\n");
  EXPECT_EQ(run("info " + q(dir / "points.ply")).code, 5);
  test::writeFile(dir / "nan.ply",
                  "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                  "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                  "end_header\n0 0 0\nnan 0 0\n0 1 0\n3 0 1 2\n");
  EXPECT_EQ(run("info " + q(dir / "nan.ply")).code, 5);
  writePly(dir / "tiny.ply", makeIcosphere(2, 0.01));  // 2 cm in metres, 2 m in... no: refuse
  r = run("info --units m " + q(dir / "tiny.ply"));
  EXPECT_EQ(r.code, 5) << r.out;
  EXPECT_NE(r.out.find("not a person"), std::string::npos) << r.out;
  // 2: bad option values.
  EXPECT_EQ(run("info --units furlongs " + q(dir / "person.ply")).code, 2);
  EXPECT_EQ(
      run("preview " + q(dir / "person.ply") + " -o " + q(dir / "p.png") + " --views top").code, 2);
  // Body sources.
  EXPECT_EQ(run("body --model nonsense -o " + q(dir / "b")).code, 5);
  r = run("body --model mpfb2:" + q(dir / "no_such_folder") + " -o " + q(dir / "b"));
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("no_such_folder"), std::string::npos);
  // Nothing half-written.
  EXPECT_FALSE(std::filesystem::exists(dir / "p.png"));
}

TEST(Cli, MissingTextureWarnsAndContinues) {
  test::TempDir dir;
  const TriMesh m = personInMillimetresZUp();
  std::ofstream obj(dir / "scan.obj");
  obj << "mtllib scan.mtl\nusemtl skin\n";
  for (int v = 0; v < m.numVertices(); ++v)
    obj << "v " << m.V(v, 0) << " " << m.V(v, 1) << " " << m.V(v, 2) << "\n";
  obj << "vt 0.5 0.5\n";
  for (int f = 0; f < m.numFaces(); ++f)
    obj << "f " << m.F(f, 0) + 1 << "/1 " << m.F(f, 1) + 1 << "/1 " << m.F(f, 2) + 1 << "/1\n";
  obj.close();
  test::writeFile(dir / "scan.mtl", "newmtl skin\nmap_Kd missing_texture.png\n");
  const CliRun r = run("info " + q(dir / "scan.obj"));
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("missing_texture.png"), std::string::npos) << r.out;
}

TEST(Cli, PreviewWritesAPngOfTheRequestedViews) {
  test::TempDir dir;
  writePly(dir / "person.ply", personInMillimetresZUp());
  const CliRun r = run("-q preview " + q(dir / "person.ply") + " -o " + q(dir / "p.png") +
                       " --views front,left --height 200");
  ASSERT_EQ(r.code, 0) << r.out;
  const std::string png = test::readFile(dir / "p.png");
  ASSERT_GT(png.size(), 24u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  // IHDR height (big-endian at byte 20) is the requested one.
  const auto byte = [&](int i) {
    return static_cast<unsigned>(static_cast<unsigned char>(png[i]));
  };
  EXPECT_EQ((byte(20) << 24) | (byte(21) << 16) | (byte(22) << 8) | byte(23), 200u);
}

}  // namespace
}  // namespace s2p
