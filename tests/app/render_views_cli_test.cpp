// `scan2pattern render-views`: seven 800×600 PNGs, cameras.json with seven cameras in the file's
// frame, one OpenCV XML per view and a README; a missing scan leaves no output folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "cli_support.h"
#include "core/shapes.h"
#include "export/png.h"
#include "io/write_mesh.h"
#include "test_support.h"

namespace s2p {
namespace {

namespace fs = std::filesystem;
using test::CliRun;
using test::q;

// A 1.7 m closed ellipsoid written in centimetres with +Y up.
fs::path writeBlob(const test::TempDir& dir) {
  TriMesh m = makeIcosphere(3, 1.0);
  m.V.col(0) *= 25;
  m.V.col(1) = (m.V.col(1).array() + 1) * 85;
  m.V.col(2) *= 15;
  const fs::path path = dir / "blob.ply";
  writeMesh(path, m);
  return path;
}

TEST(RenderViewsCli, WritesSevenViewsAndTheirCameras) {
  test::TempDir dir;
  const fs::path scan = writeBlob(dir);
  const fs::path out = dir / "views";
  const CliRun r = test::runCli("-q render-views " + q(scan) + " -o " + q(out));
  ASSERT_EQ(r.code, 0) << r.out;
  for (int k = 0; k < 7; ++k) {
    const Image img = readPng(out / ("view_" + std::to_string(k) + ".png"));
    EXPECT_EQ(img.width, 800) << k;
    EXPECT_EQ(img.height, 600) << k;
    // The blob is in the middle of the picture, the corner is background.
    EXPECT_LT(img.rgb[(300 * 800 + 400) * 3], 255) << k;
    EXPECT_EQ(img.rgb[0], 255) << k;
    EXPECT_TRUE(fs::exists(out / "camera_parameters" / ("view_" + std::to_string(k) + ".xml")));
  }
  EXPECT_FALSE(fs::exists(out / "view_7.png"));
  std::ifstream in(out / "cameras.json");
  const nlohmann::json cams = nlohmann::json::parse(in);
  ASSERT_EQ(cams["views"].size(), 7u);
  // Cameras in the file's frame (cm): 4.5 m from the blob's centre (0, 85, 0) cm, at its height.
  for (const auto& v : cams["views"]) {
    const Eigen::Vector3d c(v["centre"][0].get<double>(), v["centre"][1].get<double>(),
                            v["centre"][2].get<double>());
    EXPECT_NEAR((c - Eigen::Vector3d(0, 85, 0)).norm(), 450, 1.0) << v.dump();
    EXPECT_NEAR(c.y(), 85, 1.0);
    EXPECT_EQ(v["width"], 800);
    EXPECT_EQ(v["height"], 600);
  }
  const std::string readme = test::readFile(out / "README.txt");
  EXPECT_NE(readme.find("--3d"), std::string::npos);
  EXPECT_NE(readme.find("--camera_parameter_path"), std::string::npos);
  EXPECT_NE(readme.find("--keypoints"), std::string::npos);
}

TEST(RenderViewsCli, SizeOptionAndRefusals) {
  test::TempDir dir;
  const fs::path scan = writeBlob(dir);
  CliRun r =
      test::runCli("-q render-views " + q(scan) + " -o " + q(dir / "small") + " --size 160x120");
  ASSERT_EQ(r.code, 0) << r.out;
  const Image img = readPng(dir / "small" / "view_3.png");
  EXPECT_EQ(img.width, 160);
  EXPECT_EQ(img.height, 120);

  r = test::runCli("-q render-views " + q(dir / "missing.ply") + " -o " + q(dir / "none"));
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_FALSE(fs::exists(dir / "none"));

  r = test::runCli("-q render-views " + q(scan) + " -o " + q(dir / "bad") + " --size 800by600");
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_FALSE(fs::exists(dir / "bad"));
}

}  // namespace
}  // namespace s2p
