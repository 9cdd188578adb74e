// render-views: the paper's seven views of a scan with their cameras (§4), for a user who runs
// OpenPose in 3D mode and feeds its keypoints back with `fit --keypoints`.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "app/commands.h"
#include "core/error.h"
#include "fit/camera_views.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p::app {
namespace {

struct RenderViewsCommand {
  std::string scan;
  std::string out;
  std::string size = "800x600";
  LoadOptions load;
};

constexpr const char* kCameraFolder = "camera_parameters";

void parseSize(const std::string& text, CameraRigOptions& rig) {
  const auto bad = [&](const char* why) {
    throw CLI::ValidationError("--size", "'" + text + "': " + why);
  };
  const std::size_t x = text.find_first_of("xX");
  const auto digits = [](const std::string& s) {
    return !s.empty() && s.size() <= 5 &&
           std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (x == std::string::npos || !digits(text.substr(0, x)) || !digits(text.substr(x + 1)))
    bad("give WIDTHxHEIGHT in pixels, e.g. 800x600");
  rig.width = std::stoi(text.substr(0, x));
  rig.height = std::stoi(text.substr(x + 1));
  if (rig.width < 16 || rig.height < 16 || rig.width > 8192 || rig.height > 8192)
    bad("each side must be in [16, 8192] pixels");
}

json matrixRows(const Eigen::Matrix4d& m) {
  json out = json::array();
  for (int r = 0; r < 4; ++r) out.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
  return out;
}

std::string readme(const fs::path& scan, const fs::path& dir, int numViews) {
  const std::string d = dir.string();
  return fmt::format(
      R"(Seven views of {scan} rendered by `scan2pattern render-views`, as in the paper (Bang,
Korosteleva and Lee 2021, section 4): cameras on a horizontal circle around the scan's
bounding-box centre, 4.5 m away, at angles 0.2 + 2*pi*k/7 rad about the vertical (angle 0 is in
front of the scan), 35 degree vertical field of view, flat grey shading without texture.

Files
  view_0.png ... view_{last}.png   the renders
  {cams}/view_K.xml   one OpenCV camera file per view, as OpenPose's --camera_parameter_path
                      reads them (CameraMatrix = [R|t], Intrinsics = K, Distortion = 0)
  cameras.json        the same cameras (K, R, t, width, height, centre) and the view angles
Cameras are in the scan FILE's frame and units (OpenCV convention: p_cam = R p + t, x right,
y down, z forward), so the 3D points OpenPose triangulates come out in the file's frame and
units too, which is what `fit --keypoints` expects.

Run OpenPose (BODY_25, built with its 3D module) on them from the OpenPose folder:

  ./build/examples/openpose/openpose.bin --image_dir {dir} --3d --3d_views {n} \
      --3d_min_views 2 --number_people_max 1 \
      --camera_parameter_path {dir}/{cams}/ \
      --write_json {dir}/openpose_json/ --display 0 --render_pose 0

(--image_dir reads the {n} PNGs in name order, matching the camera files' name order; the paper's
code used --3d_min_views 2 so that joints seen by two cameras only are kept.)
Then pick the JSON file in {dir}/openpose_json/ whose people[0].pose_keypoints_3d is not empty
and fit the body with it:

  scan2pattern fit {scan} --keypoints {dir}/openpose_json/<that file>.json -o fit_out

Keypoints with score 0 (not detected) are ignored; the others become the targets of the initial
pose (by BODY_25 name: Nose, Neck, shoulders, elbows, wrists, MidHip, hips, knees, ankles, big
toes, heels). A hand-made file works too: {{"left_wrist": [x, y, z], ...}} in the file's frame.
)",
      fmt::arg("scan", scan.string()), fmt::arg("dir", d), fmt::arg("n", numViews),
      fmt::arg("last", numViews - 1), fmt::arg("cams", kCameraFolder));
}

int runRenderViews(const RenderViewsCommand& cmd, Progress& progress) {
  CameraRigOptions rig;
  parseSize(cmd.size, rig);
  const LoadedScan loaded = loadScan(cmd.scan, cmd.load, progress);
  progress.begin("render seven views");
  const std::vector<CameraView> views = renderCameraViews(loaded.scan, rig);
  progress.end();

  const fs::path dir = cmd.out;
  std::error_code ec;
  fs::create_directories(dir / kCameraFolder, ec);
  if (ec)
    throw IoError(fmt::format("cannot create output folder {}: {}", (dir / kCameraFolder).string(),
                              ec.message()));
  progress.begin("write views and cameras");
  json list = json::array();
  for (std::size_t k = 0; k < views.size(); ++k) {
    const std::string image = fmt::format("view_{}.png", k);
    const std::string xml = fmt::format("{}/view_{}.xml", kCameraFolder, k);
    writePng(dir / image, views[k].image);
    const PinholeCamera fileCam = cameraInFileFrame(views[k].camera, loaded.scan.toInputFrame);
    writeFileAtomically(dir / xml, cameraToOpenCvXml(fileCam));
    json v = cameraToJson(fileCam);
    v["image"] = image;
    v["opencv_xml"] = xml;
    v["angle_rad"] = rig.firstAngle + 2 * std::numbers::pi * static_cast<double>(k) / rig.numViews;
    v["normalised"] = cameraToJson(views[k].camera);
    list.push_back(v);
  }
  const json cams = {
      {"generator", "scan2pattern render-views"},
      {"scan", cmd.scan},
      {"frame", "scan file (its units and axes); 'normalised' per view: metres, +Y up"},
      {"convention",
       "OpenCV: p_cam = R p + t (x right, y down, z forward), pixel = K p_cam / z_cam, (0, 0) "
       "the centre of the top-left pixel"},
      {"distance_m", rig.distance},
      {"vertical_fov_deg", rig.verticalFovDegrees},
      {"normalised_to_file", matrixRows(loaded.scan.toInputFrame.matrix())},
      {"views", list}};
  writeJson(dir / "cameras.json", cams);
  writeFileAtomically(dir / "README.txt", readme(cmd.scan, dir, rig.numViews));
  progress.end();
  progress.message(fmt::format("wrote {} views, cameras.json, {}/*.xml and README.txt to {}",
                               views.size(), kCameraFolder, dir.string()));
  return 0;
}

}  // namespace

void addRenderViewsCommand(CLI::App& app, Commands& out) {
  auto cmd = std::make_shared<RenderViewsCommand>();
  auto* sub = app.add_subcommand(
      "render-views",
      "Render the paper's seven views of a scan with OpenPose camera files (for fit --keypoints)");
  sub->add_option("SCAN", cmd->scan, "Scan file: .obj (+.mtl, texture), .ply, .gltf, .glb")
      ->required();
  sub->add_option("-o,--output", cmd->out, "Output folder")->required();
  sub->add_option("--size", cmd->size, "Image size WIDTHxHEIGHT in pixels")->capture_default_str();
  addLoadOptions(sub, cmd->load);
  out.push_back({sub, [cmd](Progress& progress) { return runRenderViews(*cmd, progress); }});
}

}  // namespace s2p::app
