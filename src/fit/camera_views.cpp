#include "fit/camera_views.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.h"

namespace s2p {

namespace {

constexpr double kNearPlane = 0.01;  // metres in front of the camera

void checkOptions(const CameraRigOptions& o) {
  const auto bad = [](const std::string& m) { throw InputError("camera rig: " + m); };
  if (o.numViews < 1 || o.numViews > 360)
    bad(fmt::format("numViews {} not in [1, 360]", o.numViews));
  if (o.width < 16 || o.width > 8192 || o.height < 16 || o.height > 8192)
    bad(fmt::format("image size {}×{} not in [16, 8192]²", o.width, o.height));
  if (!(o.verticalFovDegrees > 1 && o.verticalFovDegrees < 170))
    bad(fmt::format("vertical field of view {}° not in (1°, 170°)", o.verticalFovDegrees));
  if (!(std::isfinite(o.distance) && o.distance > 0))
    bad(fmt::format("distance {} must be positive", o.distance));
  if (!std::isfinite(o.firstAngle)) bad("firstAngle is not finite");
  if (o.supersample < 1 || o.supersample > 4)
    bad(fmt::format("supersample {} not in [1, 4]", o.supersample));
  if (!(o.ambient >= 0 && o.ambient <= 1)) bad(fmt::format("ambient {} not in [0, 1]", o.ambient));
}

void checkCamera(const PinholeCamera& c) {
  if (c.width < 1 || c.height < 1 || c.width > 16384 || c.height > 16384)
    throw InputError(fmt::format("camera: image size {}×{} out of range", c.width, c.height));
  if (!c.K.allFinite() || !c.R.allFinite() || !c.t.allFinite() || !(c.K(0, 0) > 0) ||
      !(c.K(1, 1) > 0))
    throw InputError("camera: K, R or t is not finite, or a focal length is not positive");
}

nlohmann::json rows(const Eigen::MatrixXd& m) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index c = 0; c < m.cols(); ++c)
      row.push_back(m(r, c) == 0 ? 0.0 : m(r, c));  // no −0
    out.push_back(row);
  }
  return out;
}

std::string xmlMatrix(const char* name, const Eigen::MatrixXd& m) {
  std::string s = fmt::format(
      "<{} type_id=\"opencv-matrix\">\n  <rows>{}</rows>\n  <cols>{}</cols>\n"
      "  <dt>d</dt>\n  <data>",
      name, m.rows(), m.cols());
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    s += "\n   ";
    for (Eigen::Index c = 0; c < m.cols(); ++c)
      s += fmt::format(" {:.17g}", m(r, c) == 0 ? 0.0 : m(r, c));
  }
  return s + "</data></" + name + ">\n";
}

}  // namespace

Eigen::Vector2d PinholeCamera::project(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d h = K * toCamera(p);
  return h.head<2>() / h.z();
}

std::vector<PinholeCamera> cameraRig(const Eigen::Vector3d& target,
                                     const CameraRigOptions& options) {
  checkOptions(options);
  if (!target.allFinite()) throw InputError("camera rig: the target point is not finite");
  const double f =
      0.5 * options.height / std::tan(0.5 * options.verticalFovDegrees * std::numbers::pi / 180);
  Eigen::Matrix3d K;
  K << f, 0, 0.5 * (options.width - 1), 0, f, 0.5 * (options.height - 1), 0, 0, 1;
  std::vector<PinholeCamera> out;
  for (int k = 0; k < options.numViews; ++k) {
    const double a = options.firstAngle + 2 * std::numbers::pi * k / options.numViews;
    const Eigen::Vector3d back(std::sin(a), 0, std::cos(a));  // from the target to the camera
    PinholeCamera cam;
    cam.K = K;
    cam.R.row(0) = Eigen::RowVector3d(std::cos(a), 0, -std::sin(a));  // image right
    cam.R.row(1) = Eigen::RowVector3d(0, -1, 0);                      // image down
    cam.R.row(2) = -back.transpose();                                 // forward
    cam.t = -cam.R * (target + options.distance * back);
    cam.width = options.width;
    cam.height = options.height;
    out.push_back(cam);
  }
  return out;
}

Image renderPinhole(const TriMesh& mesh, const PinholeCamera& camera,
                    const CameraRigOptions& options) {
  checkOptions(options);
  checkCamera(camera);
  validateMesh(mesh, "render-views mesh");
  const int ss = options.supersample;
  const int W = camera.width * ss, H = camera.height * ss;
  // Sample (I, J) of the fine grid lies at pixel coordinate ((I + 0.5)/ss − 0.5, ...).
  Eigen::Matrix3d Kf = camera.K;
  Kf.row(0) *= ss;
  Kf.row(1) *= ss;
  Kf(0, 2) += 0.5 * (ss - 1);
  Kf(1, 2) += 0.5 * (ss - 1);
  const Eigen::Matrix3d Kinv = Kf.inverse();

  const int nv = mesh.numVertices();
  Eigen::MatrixX3d screen(nv, 3);  // x, y (fine pixels), 1/z
  std::vector<char> front(nv);
  for (int v = 0; v < nv; ++v) {
    const Eigen::Vector3d pc = camera.toCamera(mesh.V.row(v).transpose());
    front[v] = pc.z() > kNearPlane;
    const Eigen::Vector3d h = Kf * pc;
    screen.row(v) = Eigen::RowVector3d(h.x() / pc.z(), h.y() / pc.z(), 1 / pc.z());
  }
  const Eigen::MatrixX3d normals = (vertexNormals(mesh) * camera.R.transpose());  // camera frame

  std::vector<double> depth(static_cast<std::size_t>(W) * H, 0.0);  // 1/z; 0 = empty
  std::vector<float> shade(static_cast<std::size_t>(W) * H, -1.0f);
  for (int f = 0; f < mesh.numFaces(); ++f) {
    const int a = mesh.F(f, 0), b = mesh.F(f, 1), c = mesh.F(f, 2);
    if (!front[a] || !front[b] || !front[c]) continue;
    const Eigen::Vector2d pa = screen.row(a).head<2>().transpose(),
                          pb = screen.row(b).head<2>().transpose(),
                          pc = screen.row(c).head<2>().transpose();
    const double area = (pb - pa).x() * (pc - pa).y() - (pb - pa).y() * (pc - pa).x();
    if (!(std::abs(area) > 1e-12)) continue;
    const double minX = std::min({pa.x(), pb.x(), pc.x()}),
                 maxX = std::max({pa.x(), pb.x(), pc.x()});
    const double minY = std::min({pa.y(), pb.y(), pc.y()}),
                 maxY = std::max({pa.y(), pb.y(), pc.y()});
    const int x0 = std::max(0, static_cast<int>(std::ceil(minX)));
    const int x1 = std::min(W - 1, static_cast<int>(std::floor(maxX)));
    const int y0 = std::max(0, static_cast<int>(std::ceil(minY)));
    const int y1 = std::min(H - 1, static_cast<int>(std::floor(maxY)));
    if (x0 > x1 || y0 > y1) continue;
    const double iz[3] = {screen(a, 2), screen(b, 2), screen(c, 2)};
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x) {
        const Eigen::Vector2d p(x, y);
        // Screen-space barycentrics (edge functions over the signed area).
        const double l0 = ((pb - p).x() * (pc - p).y() - (pb - p).y() * (pc - p).x()) / area;
        const double l1 = ((pc - p).x() * (pa - p).y() - (pc - p).y() * (pa - p).x()) / area;
        const double l2 = 1 - l0 - l1;
        if (l0 < 0 || l1 < 0 || l2 < 0) continue;
        const double invz = l0 * iz[0] + l1 * iz[1] + l2 * iz[2];
        const std::size_t i = static_cast<std::size_t>(y) * W + x;
        if (!(invz > depth[i])) continue;
        depth[i] = invz;
        // Perspective-correct interpolation of the normal; two-sided Lambert towards the eye.
        const Eigen::Vector3d n = (l0 * iz[0] * normals.row(a) + l1 * iz[1] * normals.row(b) +
                                   l2 * iz[2] * normals.row(c))
                                      .transpose();
        const Eigen::Vector3d ray = (Kinv * Eigen::Vector3d(x, y, 1)).normalized();
        const double nn = n.norm();
        const double lambert = nn > 0 ? std::abs(n.dot(ray)) / nn : 1.0;
        shade[i] = static_cast<float>(options.ambient + (1 - options.ambient) * lambert);
      }
  }

  Image img;
  img.width = camera.width;
  img.height = camera.height;
  img.rgb.resize(static_cast<std::size_t>(img.width) * img.height * 3);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      double sum = 0;
      for (int j = 0; j < ss; ++j)
        for (int i = 0; i < ss; ++i) {
          const float s = shade[static_cast<std::size_t>(y * ss + j) * W + (x * ss + i)];
          sum += s < 0 ? options.background : s * options.surface;
        }
      const auto g = static_cast<std::uint8_t>(std::clamp(std::lround(sum / (ss * ss)), 0L, 255L));
      std::uint8_t* px = &img.rgb[(static_cast<std::size_t>(y) * img.width + x) * 3];
      px[0] = px[1] = px[2] = g;
    }
  return img;
}

std::vector<CameraView> renderCameraViews(const Scan& scan, const CameraRigOptions& options) {
  validateMesh(scan.mesh, scan.sourcePath.empty() ? "scan" : scan.sourcePath);
  const BoundingBox box = boundingBox(scan.mesh.V);
  const std::vector<PinholeCamera> cams = cameraRig(0.5 * (box.min + box.max), options);
  std::vector<CameraView> out(cams.size());
  tbb::parallel_for(std::size_t{0}, cams.size(), [&](std::size_t k) {
    out[k].camera = cams[k];
    out[k].image = renderPinhole(scan.mesh, cams[k], options);
  });
  return out;
}

PinholeCamera cameraInFileFrame(const PinholeCamera& camera, const Eigen::Affine3d& toInputFrame) {
  if (!toInputFrame.matrix().allFinite())
    throw InputError("camera: the scan's file transform is not finite");
  const Eigen::Affine3d toNorm = toInputFrame.inverse();
  const Eigen::Matrix3d M = toNorm.linear();
  const double det = M.determinant();
  if (!(det > 0))
    throw InputError("camera: the scan's file transform is not a proper similarity (det ≤ 0)");
  const double s = std::cbrt(det);
  const Eigen::Matrix3d Q = M / s;
  if ((Q.transpose() * Q - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6)
    throw InputError(
        "camera: the scan's file transform is not a rotation with uniform scale; cameras cannot "
        "be written in the file's frame");
  // p_cam = R(sQ·q + b) + t = s·(RQ·q + (R·b + t)/s), and the projection ignores the factor s.
  PinholeCamera out = camera;
  out.R = camera.R * Q;
  out.t = (camera.R * toNorm.translation() + camera.t) / s;
  return out;
}

nlohmann::json cameraToJson(const PinholeCamera& camera) {
  const Eigen::Vector3d c = camera.centre();
  return {{"width", camera.width},
          {"height", camera.height},
          {"K", rows(camera.K)},
          {"R", rows(camera.R)},
          {"t", {camera.t.x(), camera.t.y(), camera.t.z()}},
          {"centre", {c.x(), c.y(), c.z()}}};
}

std::string cameraToOpenCvXml(const PinholeCamera& camera) {
  Eigen::Matrix<double, 3, 4> Rt;
  Rt << camera.R, camera.t;
  std::string s = "<?xml version=\"1.0\"?>\n<opencv_storage>\n";
  s += fmt::format(
      "<!-- scan2pattern render-views: {}x{} px, translation in the scan file's units -->\n",
      camera.width, camera.height);
  s += xmlMatrix("CameraMatrix", Rt);
  s += xmlMatrix("Intrinsics", camera.K);
  s += xmlMatrix("Distortion", Eigen::Matrix<double, 5, 1>::Zero());
  return s + "</opencv_storage>\n";
}

}  // namespace s2p
