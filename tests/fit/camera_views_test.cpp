// The seven pinhole views: the rig's geometry (aim, distance, field of view), the renders
// (covered vs background pixels), and the cameras as written (JSON, OpenCV XML, in the file's
// frame) projecting like the renderer's.
#include "fit/camera_views.h"

#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include "core/error.h"
#include "core/shapes.h"
#include "fit/keypoints.h"
#include "test_support.h"

namespace s2p {
namespace {

// A 1.7 m person-sized capsule stand-in: a closed icosphere stretched along Y, feet at y = 0,
// centred off the origin so the rig's aim matters.
Scan tallBlob() {
  Scan scan;
  scan.mesh = makeIcosphere(3, 1.0);
  scan.mesh.V.col(0) *= 0.25;
  scan.mesh.V.col(1) = (scan.mesh.V.col(1).array() + 1) * 0.85;
  scan.mesh.V.col(2) *= 0.15;
  scan.mesh.V.col(0).array() += 0.3;
  scan.mesh.V.col(2).array() -= 0.2;
  return scan;
}

Eigen::Vector3d boxCentre(const TriMesh& m) {
  const BoundingBox b = boundingBox(m.V);
  return 0.5 * (b.min + b.max);
}

std::uint8_t grey(const Image& img, int x, int y) {
  return img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3];
}

TEST(CameraViews, RigAimsAtTheCentreFromTheRightDistance) {
  const Eigen::Vector3d target(0.3, 0.85, -0.2);
  const CameraRigOptions o;
  const auto cams = cameraRig(target, o);
  ASSERT_EQ(cams.size(), 7u);
  for (std::size_t k = 0; k < cams.size(); ++k) {
    const PinholeCamera& c = cams[k];
    const Eigen::Vector2d px = c.project(target);
    EXPECT_NEAR(px.x(), 399.5, 1e-9) << k;
    EXPECT_NEAR(px.y(), 299.5, 1e-9) << k;
    EXPECT_NEAR((c.centre() - target).norm(), 4.5, 1e-12) << k;
    EXPECT_NEAR(c.centre().y(), target.y(), 1e-12) << k;  // elevation 0
    EXPECT_LT((c.R * c.R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(c.R.determinant(), 1, 1e-12);
    const double a = 0.2 + 2 * std::numbers::pi * k / 7;
    EXPECT_LT((c.centre() - target - 4.5 * Eigen::Vector3d(std::sin(a), 0, std::cos(a))).norm(),
              1e-12);
    // Vertical FOV 35°: a point at the half angle above the target reaches the top edge (−0.5).
    const Eigen::Vector3d top = target + (c.centre() - target).norm() *
                                             std::tan(17.5 * std::numbers::pi / 180) *
                                             Eigen::Vector3d::UnitY();
    EXPECT_NEAR(c.project(top).y(), -0.5, 1e-9) << k;
    // Image up is +Y, and the camera sees the world upright.
    EXPECT_LT(c.project(target + 0.1 * Eigen::Vector3d::UnitY()).y(), px.y());
  }
  // The first camera is on the front (+Z) side: x to the image's right is roughly +X.
  EXPECT_GT(cams[0].project(target + 0.1 * Eigen::Vector3d::UnitX()).x(), 399.5);
}

TEST(CameraViews, FrontPointIsNearerTheFrontCamera) {
  const Scan scan = tallBlob();
  const auto cams = cameraRig(boxCentre(scan.mesh), {});
  // The point of the surface furthest along +Z.
  Eigen::Index v;
  scan.mesh.V.col(2).maxCoeff(&v);
  const Eigen::Vector3d p = scan.mesh.V.row(v).transpose();
  // Opposite of camera 0 (angle 0.2): the camera whose direction is most nearly reversed.
  std::size_t opposite = 1;
  for (std::size_t k = 1; k < cams.size(); ++k)
    if ((cams[k].centre() - p).z() < (cams[opposite].centre() - p).z()) opposite = k;
  EXPECT_TRUE(opposite == 3 || opposite == 4) << opposite;
  EXPECT_LT(cams[0].toCamera(p).z(), cams[opposite].toCamera(p).z() - 0.25);
  EXPECT_GT(cams[0].toCamera(p).z(), 0);
}

TEST(CameraViews, RendersCoverTheScanAndLeaveTheBackgroundEmpty) {
  Scan scan = tallBlob();
  CameraRigOptions o;
  const auto views = renderCameraViews(scan, o);
  ASSERT_EQ(views.size(), 7u);
  const Eigen::Vector3d c = boxCentre(scan.mesh);
  for (const CameraView& v : views) {
    ASSERT_EQ(v.image.width, 800);
    ASSERT_EQ(v.image.height, 600);
    // The centre pixel sees the blob's body: lit grey, not the white background.
    const Eigen::Vector2d px = v.camera.project(c);
    const std::uint8_t centre =
        grey(v.image, static_cast<int>(std::lround(px.x())), static_cast<int>(std::lround(px.y())));
    EXPECT_LT(centre, 210);
    EXPECT_GT(centre, 100);
    // Corners and a point 1.2 m to the side of the blob are background.
    EXPECT_EQ(grey(v.image, 0, 0), 255);
    EXPECT_EQ(grey(v.image, 799, 599), 255);
    const Eigen::Vector3d side = c + 1.2 * v.camera.R.row(0).transpose();
    const Eigen::Vector2d ps = v.camera.project(side);
    EXPECT_EQ(grey(v.image, static_cast<int>(ps.x()), static_cast<int>(ps.y())), 255);
    // The silhouette's height in pixels: 1.7 m at ≈4.5 m with f = 300/tan(17.5°) ≈ 951 px.
    int top = -1, bottom = -1;
    const int col = static_cast<int>(std::lround(px.x()));
    for (int y = 0; y < 600; ++y)
      if (grey(v.image, col, y) != 255) {
        if (top < 0) top = y;
        bottom = y;
      }
    const double f = v.camera.K(0, 0);
    EXPECT_NEAR(bottom - top + 1, 1.7 * f / 4.5, 0.05 * 1.7 * f / 4.5);
  }
  // Bad options are refused.
  o.width = 4;
  EXPECT_THROW(renderCameraViews(scan, o), InputError);
  scan.mesh.V(0, 0) = std::nan("");
  EXPECT_THROW(renderCameraViews(scan, {}), InputError);
}

TEST(CameraViews, NearerSurfaceHidesTheFartherOne) {
  // A small square facing the camera (z = 0.5) in front of a large one turned 60° about Y
  // (centred at z = −0.5): the near one is lit head-on (grey 200), the far one at ≈ cos 60°
  // (0.25 + 0.75·0.5 of 200 ≈ 125); the order of the faces does not matter.
  TriMesh near = makeGrid(1, 1, 0.4, 0.4), far = makeGrid(1, 1, 2, 2);
  near.V.col(0).array() -= 0.2;
  near.V.col(1).array() -= 0.2;
  near.V.col(2).setConstant(0.5);
  far.V.col(0).array() -= 1;
  far.V.col(1).array() -= 1;
  const Eigen::Matrix3d turn =
      Eigen::AngleAxisd(std::numbers::pi / 3, Eigen::Vector3d::UnitY()).matrix();
  far.V = (far.V * turn.transpose()).rowwise() + Eigen::RowVector3d(0, 0, -0.5);
  TriMesh both;
  both.V.resize(8, 3);
  both.V << near.V, far.V;
  both.F.resize(4, 3);
  both.F << near.F, far.F.array() + 4;
  CameraRigOptions o;
  o.firstAngle = 0;
  o.numViews = 1;
  const PinholeCamera cam = cameraRig(Eigen::Vector3d::Zero(), o)[0];
  TriMesh swapped = both;
  swapped.F << far.F.array() + 4, near.F;
  const Image a = renderPinhole(both, cam, o), b = renderPinhole(swapped, cam, o);
  EXPECT_EQ(a.rgb, b.rgb);
  const Eigen::Vector2d pn = cam.project(Eigen::Vector3d(0, 0, 0.5));
  const Eigen::Vector2d pf =
      cam.project(turn * Eigen::Vector3d(0.8, 0.3, 0) + Eigen::Vector3d(0, 0, -0.5));
  EXPECT_EQ(grey(a, static_cast<int>(pn.x()), static_cast<int>(pn.y())), 200);
  const int farGrey = grey(a, static_cast<int>(pf.x()), static_cast<int>(pf.y()));
  EXPECT_GT(farGrey, 110);
  EXPECT_LT(farGrey, 145);
  // Without the near square, the far one shows at the centre.
  const Image farOnly = renderPinhole(far, cam, o);
  EXPECT_LT(grey(farOnly, static_cast<int>(pn.x()), static_cast<int>(pn.y())), 145);
}

// Reads <Name type_id="opencv-matrix"><rows>r</rows><cols>c</cols><dt>d</dt><data>…</data></Name>
// from OpenCV XML.
Eigen::MatrixXd xmlMatrix(const std::string& xml, const std::string& name) {
  const auto between = [&](std::size_t from, const std::string& open, const std::string& close) {
    const std::size_t a = xml.find(open, from);
    const std::size_t b = a == std::string::npos ? a : xml.find(close, a);
    return b == std::string::npos ? std::string()
                                  : xml.substr(a + open.size(), b - a - open.size());
  };
  const std::size_t at = xml.find("<" + name + " type_id=\"opencv-matrix\">");
  EXPECT_NE(at, std::string::npos) << name;
  if (at == std::string::npos) return {};
  EXPECT_EQ(between(at, "<dt>", "</dt>"), "d");
  EXPECT_NE(xml.find("</data></" + name + ">", at), std::string::npos) << name;
  const int r = std::stoi(between(at, "<rows>", "</rows>"));
  const int c = std::stoi(between(at, "<cols>", "</cols>"));
  std::istringstream in(between(at, "<data>", "</data>"));
  Eigen::MatrixXd out(r, c);
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < c; ++j) in >> out(i, j);
  EXPECT_FALSE(in.fail()) << name;
  double extra;
  EXPECT_FALSE(in >> extra) << name << ": more numbers than rows×cols";
  return out;
}

Eigen::Vector2d projectWith(const Eigen::Matrix3d& K, const Eigen::MatrixXd& Rt,
                            const Eigen::Vector3d& p) {
  const Eigen::Vector3d h = K * (Rt.leftCols<3>() * p + Rt.col(3));
  return h.head<2>() / h.z();
}

TEST(CameraViews, WrittenCamerasProjectLikeTheRendererInTheFileFrame) {
  // A file in millimetres with +Z up, moved: p_file = toInput·p_norm.
  Eigen::Affine3d toInput = Eigen::Affine3d::Identity();
  toInput.translate(Eigen::Vector3d(120, -40, 7));
  toInput.rotate(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitX()));
  toInput.rotate(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()));
  toInput.scale(1000);
  const Scan scan = tallBlob();
  const auto cams = cameraRig(boxCentre(scan.mesh), {});
  for (const PinholeCamera& cam : cams) {
    const PinholeCamera fileCam = cameraInFileFrame(cam, toInput);
    EXPECT_LT((fileCam.R * fileCam.R.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    // Camera centre in the file frame is the normalised centre mapped.
    EXPECT_LT((fileCam.centre() - toInput * cam.centre()).norm(), 1e-9);
    const nlohmann::json j = nlohmann::json::parse(cameraToJson(fileCam).dump());
    Eigen::Matrix3d K, R;
    Eigen::Vector3d t;
    for (int r = 0; r < 3; ++r) {
      t(r) = j["t"][r].get<double>();
      for (int c = 0; c < 3; ++c) {
        K(r, c) = j["K"][r][c].get<double>();
        R(r, c) = j["R"][r][c].get<double>();
      }
    }
    EXPECT_EQ(j["width"], 800);
    EXPECT_EQ(j["height"], 600);
    const std::string xml = cameraToOpenCvXml(fileCam);
    const Eigen::MatrixXd Rt = xmlMatrix(xml, "CameraMatrix");
    const Eigen::MatrixXd Kx = xmlMatrix(xml, "Intrinsics");
    const Eigen::MatrixXd D = xmlMatrix(xml, "Distortion");
    ASSERT_EQ(Rt.rows(), 3);
    ASSERT_EQ(Rt.cols(), 4);
    ASSERT_EQ(Kx.rows(), 3);
    ASSERT_EQ(D.rows(), 5);
    EXPECT_EQ(D.norm(), 0);
    EXPECT_EQ(Kx(1, 0), 0);  // OpenPose needs an upper triangular K
    Eigen::MatrixXd RtJson(3, 4);
    RtJson << R, t;
    for (int v = 0; v < scan.mesh.numVertices(); v += 37) {
      const Eigen::Vector3d p = scan.mesh.V.row(v).transpose();
      const Eigen::Vector3d q = toInput * p;
      const Eigen::Vector2d expected = cam.project(p);
      EXPECT_LT((projectWith(K, RtJson, q) - expected).norm(), 0.5) << v;
      EXPECT_LT((projectWith(Kx, Rt, q) - expected).norm(), 0.5) << v;
      EXPECT_LT((projectWith(Kx, Rt, q) - expected).norm(), 1e-6) << v;  // 17 digits
    }
  }
  // A shear is not a camera frame.
  Eigen::Affine3d shear = Eigen::Affine3d::Identity();
  shear.linear()(0, 1) = 0.5;
  EXPECT_THROW(cameraInFileFrame(cams[0], shear), InputError);
}

// The OpenPose path end to end without OpenPose: BODY_25 points in the normalised frame are
// projected with the written (file-frame) XML cameras, triangulated by DLT as OpenPose's 3D
// module does, written as its JSON, and read back by readKeypoints onto the original points.
TEST(CameraViews, TriangulatedKeypointsComeBackInTheNormalisedFrame) {
  Eigen::Affine3d toInput = Eigen::Affine3d::Identity();  // a file in mm, +Z up, shifted
  toInput.translate(Eigen::Vector3d(-300, 25, 1000));
  toInput.rotate(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitX()));
  toInput.scale(1000);
  const auto cams = cameraRig(Eigen::Vector3d(0, 0.9, 0), {});
  std::vector<Eigen::Matrix<double, 3, 4>> P;  // K·[R|t] read back from the XML
  for (const PinholeCamera& c : cams) {
    const std::string xml = cameraToOpenCvXml(cameraInFileFrame(c, toInput));
    P.emplace_back(xmlMatrix(xml, "Intrinsics") * xmlMatrix(xml, "CameraMatrix"));
  }
  nlohmann::json flat = nlohmann::json::array();
  std::vector<Eigen::Vector3d> truth(kBody25Count);
  for (int i = 0; i < kBody25Count; ++i) {
    truth[i] = Eigen::Vector3d(0.02 * i - 0.25, 0.1 + 0.06 * i, 0.01 * (i % 5));  // normalised
    const Eigen::Vector3d q = toInput * truth[i];
    Eigen::MatrixXd A(2 * P.size(), 4);
    for (std::size_t k = 0; k < P.size(); ++k) {
      const Eigen::Vector3d h = P[k] * q.homogeneous();
      const Eigen::Vector2d uv = h.head<2>() / h.z();
      A.row(2 * k) = uv.x() * P[k].row(2) - P[k].row(0);
      A.row(2 * k + 1) = uv.y() * P[k].row(2) - P[k].row(1);
    }
    const Eigen::Vector4d X =
        Eigen::JacobiSVD<Eigen::MatrixXd>(A, Eigen::ComputeFullV).matrixV().col(3);
    const Eigen::Vector3d tri = X.head<3>() / X(3);
    const bool detected = i != 6;  // LElbow not detected
    for (double v : {tri.x(), tri.y(), tri.z(), detected ? 0.9 : 0.0})
      flat.push_back(detected ? v : 0.0);
  }
  test::TempDir dir;
  const nlohmann::json doc = {{"people", {{{"pose_keypoints_3d", flat}}}}};
  test::writeFile(dir / "op.json", doc.dump());
  const auto targets = readKeypoints(dir / "op.json", toInput.inverse());
  EXPECT_EQ(targets.size(), 18u);  // 19 mapped BODY_25 points, one not detected
  for (const JointTarget& t : targets) {
    int i = 0;
    while (body25ToCanonical(i) != t.joint) ++i;
    EXPECT_NE(i, 6);
    EXPECT_LT((t.position - truth[i]).norm(), 1e-6) << toString(t.joint);
    EXPECT_EQ(t.weight, 0.9);
  }
}

}  // namespace
}  // namespace s2p
