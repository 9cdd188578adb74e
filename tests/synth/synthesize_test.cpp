// The generator end to end: poses, yaw consistency of scan and truth, files that are identical
// per seed, OBJ + texture atlas read back with the PLY's colours, labels agreeing with truth.
#include "synth/synthesize.h"

#include <cstdio>
#include <gtest/gtest.h>

#include <map>
#include <tuple>

#include "body/body_source.h"
#include "body/mannequin.h"
#include "body/posing.h"
#include "core/error.h"
#include "core/shapes.h"
#include "io/read_ply.h"
#include "io/read_scan.h"
#include "synth/presets.h"
#include "test_support.h"

namespace s2p {
namespace {

const BodyModel& mannequin() {
  static const BodyModel model = makeMannequin();
  return model;
}

// A small, fast scan of a preset (coarse level set) for file tests.
SynthOptions smallOptions(std::uint64_t seed) {
  SynthOptions o = presetOptions("tshirt_trousers");
  o.outfit.garments[0].look.pattern = PatternKind::Stripes;
  o.outfit.garments[0].look.second = Eigen::Vector3d(0.9, 0.9, 0.9);
  o.geometry.voxelSize = 0.012;
  o.geometry.targetVertices = 3000;
  o.seed = seed;
  return o;
}

TEST(SynthPose, PosesHaveTheirKnownShape) {
  const BodyModel& m = mannequin();
  const Eigen::VectorXd beta = Eigen::VectorXd::Zero(m.numShapes());
  std::map<SynthPose, PosedBody> posed;
  for (SynthPose p : {SynthPose::APose, SynthPose::TPose, SynthPose::ArmsDown, SynthPose::Walking,
                      SynthPose::BentArm})
    posed.emplace(p, poseBody(m, {beta, synthPose(m, beta, p)}));
  const auto at = [&](SynthPose p, Canonical c) -> Eigen::Vector3d {
    return posed.at(p).canonical.row(static_cast<int>(c)).transpose();
  };
  using C = Canonical;
  // Arm angle below horizontal, from shoulder to wrist.
  const auto armDown = [&](SynthPose p, C s, C w) {
    const Eigen::Vector3d d = at(p, w) - at(p, s);
    return std::atan2(-d.y(), std::hypot(d.x(), d.z())) * 180 / M_PI;
  };
  EXPECT_NEAR(armDown(SynthPose::APose, C::LeftShoulder, C::LeftWrist), 45, 1);
  EXPECT_NEAR(armDown(SynthPose::TPose, C::RightShoulder, C::RightWrist), 0, 1);
  EXPECT_NEAR(armDown(SynthPose::ArmsDown, C::LeftShoulder, C::LeftWrist), 72, 1);
  EXPECT_NEAR(armDown(SynthPose::ArmsDown, C::RightShoulder, C::RightWrist), 72, 1);
  // Arms down yet clear of the hips: wrists further out than the hip joints by ≥ 10 cm.
  EXPECT_GT(at(SynthPose::ArmsDown, C::LeftWrist).x() - at(SynthPose::ArmsDown, C::LeftHip).x(),
            0.10);
  EXPECT_LT(at(SynthPose::ArmsDown, C::RightWrist).x() - at(SynthPose::ArmsDown, C::RightHip).x(),
            -0.10);
  // Walking: left foot forwards, right foot back, right knee bent (ankle behind the knee).
  EXPECT_GT(at(SynthPose::Walking, C::LeftAnkle).z(), 0.1);
  EXPECT_LT(at(SynthPose::Walking, C::RightAnkle).z(), -0.1);
  EXPECT_LT(at(SynthPose::Walking, C::RightAnkle).z(), at(SynthPose::Walking, C::RightKnee).z());
  // Bent arm: the left forearm at 90° to the upper arm, pointing forwards; the right arm as in A.
  const Eigen::Vector3d upper =
      at(SynthPose::BentArm, C::LeftElbow) - at(SynthPose::BentArm, C::LeftShoulder);
  const Eigen::Vector3d fore =
      at(SynthPose::BentArm, C::LeftWrist) - at(SynthPose::BentArm, C::LeftElbow);
  EXPECT_NEAR(upper.normalized().dot(fore.normalized()), 0, 0.02);
  EXPECT_GT(fore.normalized().z(), 0.99);
  EXPECT_TRUE(
      at(SynthPose::BentArm, C::RightWrist).isApprox(at(SynthPose::APose, C::RightWrist), 1e-9));
}

// A hand-built clothed surface: a unit-ish sphere at chest height, upper half Upper, lower Lower.
ClothedSurface sphereSurface() {
  ClothedSurface s;
  s.mesh = makeIcosphere(2, 0.3);
  s.mesh.V.col(1).array() += 1.2;
  const int nv = s.mesh.numVertices(), nf = s.mesh.numFaces();
  s.restPosition = s.mesh.V;
  s.vertexLabel.resize(nv);
  s.vertexLayer.resize(nv);
  for (int v = 0; v < nv; ++v) {
    const bool up = s.mesh.V(v, 1) > 1.2;
    s.vertexLabel(v) = static_cast<int>(up ? Label::Upper : Label::Lower);
    s.vertexLayer(v) = up ? 0 : 1;
  }
  s.faceLabel.resize(nf);
  s.faceLayer.resize(nf);
  for (int f = 0; f < nf; ++f) {
    s.faceLabel(f) = s.vertexLabel(s.mesh.F(f, 0));
    s.faceLayer(f) = s.vertexLayer(s.mesh.F(f, 0));
  }
  TrueBoundary b;
  b.a = Label::Upper;
  b.b = Label::Lower;
  b.curves.push_back((Eigen::MatrixX3d(3, 3) << 0.3, 1.2, 0, 0, 1.2, 0.3, -0.3, 1.2, 0).finished());
  b.closed.push_back(false);
  s.boundaries.push_back(b);
  return s;
}

TEST(Synthesize, YawRotatesScanCurvesAndBodyConsistently) {
  const BodyModel& m = mannequin();
  const Eigen::VectorXd beta = Eigen::VectorXd::Zero(m.numShapes());
  BodyParams params{beta, synthPose(m, beta, SynthPose::Walking)};
  params.pose.translation = Eigen::Vector3d(0.05, 0.02, -0.03);
  const ClothedSurface surface = sphereSurface();
  SynthOptions o = presetOptions("tshirt_trousers");
  const SynthScan a = assembleSynthScan(m, params, surface, o);
  o.yawDegrees = 90;
  const SynthScan b = assembleSynthScan(m, params, surface, o);
  // +90° about +Y: (x, y, z) → (z, y, −x).
  const auto rot = [](const Eigen::RowVector3d& p) {
    return Eigen::RowVector3d(p.z(), p.y(), -p.x());
  };
  for (int v = 0; v < surface.mesh.numVertices(); ++v)
    EXPECT_TRUE(b.scan.mesh.V.row(v).isApprox(rot(a.scan.mesh.V.row(v)), 1e-12));
  EXPECT_TRUE(
      b.truth.boundaries[0].curves[0].row(1).isApprox(rot(a.truth.boundaries[0].curves[0].row(1))));
  // Every posed joint of the truth body turned with the scan.
  for (const auto& [name, pj] : a.truth.body["joints"].items()) {
    const Eigen::RowVector3d p(pj[0].get<double>(), pj[1].get<double>(), pj[2].get<double>());
    const auto& qj = b.truth.body["joints"][name];
    const Eigen::RowVector3d q(qj[0].get<double>(), qj[1].get<double>(), qj[2].get<double>());
    EXPECT_LT((q - rot(p)).norm(), 1e-9) << name;
  }
  // Colours and labels do not depend on the yaw; colours follow the layers.
  EXPECT_EQ(a.scan.colour, b.scan.colour);
  EXPECT_EQ(a.faceLabel, surface.faceLabel);
  const Eigen::Vector3d red = o.outfit.garments[0].look.base;
  for (int v = 0; v < surface.mesh.numVertices(); ++v)
    if (surface.vertexLabel(v) == static_cast<int>(Label::Upper)) {
      EXPECT_LT((a.scan.colour.row(v).transpose() - red).norm(), 0.12 * red.norm());
    }
  EXPECT_EQ(a.truth.generator["yaw_degrees"].get<double>(), 0.0);
  EXPECT_EQ(b.truth.generator["yaw_degrees"].get<double>(), 90.0);
}

TEST(Synthesize, BadSurfaceOrOptionsThrow) {
  const BodyModel& m = mannequin();
  ClothedSurface s = sphereSurface();
  s.faceLabel(3) = 42;
  EXPECT_THROW(assembleSynthScan(m, {}, s, {}), InputError);
  s = sphereSurface();
  EXPECT_THROW(assembleSynthScan(m, {}, s, {}), InputError);  // no pose
  s.vertexLayer.resize(2);
  EXPECT_THROW(assembleSynthScan(m, {}, s, {}), InputError);
  SynthOptions o = smallOptions(1);
  o.geometry.targetVertices = -5;
  EXPECT_THROW(synthesize(m, o), InputError);
  o = smallOptions(1);
  o.yawDegrees = std::nan("");
  EXPECT_THROW(synthesize(m, o), InputError);
  o = smallOptions(1);
  o.shape = "no_such_param=3";
  EXPECT_THROW(synthesize(m, o), InputError);
  o = smallOptions(1);
  o.bodySource = "nonsense";
  EXPECT_THROW(synthesize(o), InputError);
}

TEST(Synthesize, PresetShapesAreMannequinParameters) {
  for (const Preset& p : presets())
    EXPECT_NO_THROW(parseShapeAssignments(mannequin(), p.options.shape)) << p.name;
  EXPECT_GT(parseShapeAssignments(mannequin(), presetOptions("plus_size").shape).norm(), 10);
}

TEST(Synthesize, VoxelSizeFollowsTheTargetVertexCount) {
  EXPECT_DOUBLE_EQ(voxelSizeFor(20000, 0.004), 0.004);
  EXPECT_NEAR(voxelSizeFor(1'000'000, 0.004), std::sqrt(2.2 / 1.2e6), 1e-12);
  EXPECT_DOUBLE_EQ(voxelSizeFor(0, 0.004), 0.004);
}

// Files of one run, by name.
std::map<std::string, std::string> files(const std::filesystem::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    out[e.path().filename().string()] = test::readFile(e.path());
  return out;
}

TEST(Synthesize, SameSeedSameBytesAndLabelsAgreeWithTruth_Slow) {
  test::TempDir dir;
  const BodyModel& m = mannequin();
  writeSynthScan(dir / "a", synthesize(m, smallOptions(7)), SynthFormat::Ply, {.previews = false});
  writeSynthScan(dir / "b", synthesize(m, smallOptions(7)), SynthFormat::Ply, {.previews = false});
  writeSynthScan(dir / "c", synthesize(m, smallOptions(8)), SynthFormat::Ply, {.previews = false});
  const auto a = files(dir / "a"), b = files(dir / "b"), c = files(dir / "c");
  ASSERT_EQ(a.size(), 2u);  // scan.ply, truth.json
  EXPECT_TRUE(a.at("scan.ply") == b.at("scan.ply"));
  EXPECT_TRUE(a.at("truth.json") == b.at("truth.json"));
  EXPECT_FALSE(a.at("scan.ply") == c.at("scan.ply"));
  EXPECT_FALSE(a.at("truth.json") == c.at("truth.json"));
  // Labels in the PLY agree with truth.json.
  const PlyData ply = readPly(dir / "a" / "scan.ply");
  const Truth truth = readTruth(dir / "a" / "truth.json");
  EXPECT_EQ(truth.scanFile, "scan.ply");
  EXPECT_EQ(truth.labelledMesh, "scan.ply");
  EXPECT_EQ(truth.seed, 7u);
  EXPECT_EQ(truth.preset, "tshirt_trousers");
  ASSERT_EQ(ply.faceLabels.size(), ply.mesh.numFaces());
  ASSERT_EQ(ply.labels.size(), ply.mesh.numVertices());
  for (int l = 0; l < kNumLabels; ++l) {
    if (static_cast<Label>(l) == Label::Skin || static_cast<Label>(l) == Label::Gap) continue;
    bool inTruth = false;
    for (const auto& g : truth.garments)
      inTruth |= static_cast<int>(g.label) == l && g.visibleArea > 0;
    EXPECT_EQ((ply.faceLabels.array() == l).any(), inTruth) << toString(static_cast<Label>(l));
  }
  EXPECT_TRUE((ply.faceLabels.array() == static_cast<int>(Label::Upper)).any());
  EXPECT_EQ(truth.generator["seed"].get<std::uint64_t>(), 7u);
}

TEST(Synthesize, ObjTextureReadsBackWithThePlyColours_Slow) {
  test::TempDir dir;
  const SynthScan s = synthesize(mannequin(), smallOptions(3));
  const auto written =
      writeSynthScan(dir / "obj", s, SynthFormat::Obj, {.previews = true, .previewHeightPx = 200});
  for (const char* name : {"scan.obj", "scan.mtl", "scan.png", "labels.ply", "truth.json",
                           "preview_scan.png", "preview_labels.png"})
    EXPECT_TRUE(std::filesystem::exists(dir / "obj" / name)) << name;
  EXPECT_EQ(written.size(), 7u);
  writeSynthScan(dir / "ply", s, SynthFormat::Ply, {.previews = false});
  const PlyData ply = readPly(dir / "ply" / "scan.ply");
  const Scan obj = readScan(dir / "obj" / "scan.obj");
  ASSERT_EQ(obj.colourSource, ColourSource::Texture);
  // The OBJ comes split per corner (and in single precision): find each vertex of the PLY by
  // its position, in 0.1 mm cells and their neighbours.
  std::map<std::tuple<long, long, long>, std::vector<int>> cells;
  const double h = 1e-4;
  for (int v = 0; v < ply.mesh.numVertices(); ++v) {
    const Eigen::RowVector3d p = ply.mesh.V.row(v);
    cells[{std::lround(p.x() / h), std::lround(p.y() / h), std::lround(p.z() / h)}].push_back(v);
  }
  double sum = 0;
  int n = 0;
  for (int v = 0; v < obj.mesh.numVertices(); ++v) {
    const Eigen::RowVector3d p = obj.mesh.V.row(v);
    int best = -1;
    double bestD = 1e-5;
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find({std::lround(p.x() / h) + dx, std::lround(p.y() / h) + dy,
                                      std::lround(p.z() / h) + dz});
          if (it == cells.end()) continue;
          for (int w : it->second)
            if ((ply.mesh.V.row(w) - p).norm() < bestD)
              bestD = (ply.mesh.V.row(w) - p).norm(), best = w;
        }
    ASSERT_GE(best, 0) << "OBJ vertex " << v << " is at no PLY vertex";
    sum += (obj.colour.row(v) - ply.colour.row(best)).cwiseAbs().mean();
    ++n;
  }
  EXPECT_LE(sum / n, 2.0 / 255);
  std::printf("mean |OBJ texture - PLY| colour difference: %.3f / 255 over %d vertices\n",
              255 * sum / n, n);
  // labels.ply carries the same vertices and faces as the scan, with labels.
  const PlyData labels = readPly(dir / "obj" / "labels.ply");
  EXPECT_EQ(labels.mesh.F, ply.mesh.F);
  EXPECT_EQ(labels.faceLabels, ply.faceLabels);
  EXPECT_EQ(readTruth(dir / "obj" / "truth.json").labelledMesh, "labels.ply");
}

TEST(Synthesize, UnwritableFolderThrowsAndWritesNothing) {
  test::TempDir dir;
  test::writeFile(dir / "file", "x");
  const SynthScan s = synthesize(mannequin(), smallOptions(1));
  EXPECT_THROW(writeSynthScan(dir / "file" / "sub", s, SynthFormat::Ply), IoError);
  SynthScan broken = s;
  broken.faceLabel.resize(1);
  EXPECT_THROW(writeSynthScan(dir / "out", broken, SynthFormat::Ply), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

}  // namespace
}  // namespace s2p
