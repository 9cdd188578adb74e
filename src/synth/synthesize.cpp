#include "synth/synthesize.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <system_error>

#include "body/body_json.h"
#include "body/body_source.h"
#include "body/posing.h"
#include "core/error.h"
#include "export/png.h"
#include "io/write_mesh.h"
#include "synth/atlas.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace s2p {
namespace {

constexpr std::array<std::pair<SynthPose, const char*>, 6> kPoseNames = {{
    {SynthPose::APose, "apose"},
    {SynthPose::TPose, "tpose"},
    {SynthPose::ArmsDown, "arms_down"},
    {SynthPose::Walking, "walking"},
    {SynthPose::BentArm, "bent_arm"},
    {SynthPose::Relaxed, "relaxed"},
}};

double deg(double d) {
  return d * std::numbers::pi / 180.0;
}

Eigen::Matrix3d rotX(double d) {
  return Eigen::AngleAxisd(deg(d), Eigen::Vector3d::UnitX()).toRotationMatrix();
}
Eigen::Matrix3d rotY(double d) {
  return Eigen::AngleAxisd(deg(d), Eigen::Vector3d::UnitY()).toRotationMatrix();
}
Eigen::Matrix3d rotZ(double d) {
  return Eigen::AngleAxisd(deg(d), Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

int jointOf(const BodyModel& model, Canonical c) {
  const int j = model.canonical[static_cast<int>(c)].joint;
  if (j < 0 || j >= model.numJoints())
    throw InputError(fmt::format("{}: synthetic poses need canonical '{}' to be a skeleton joint",
                                 model.source, toString(c)));
  return j;
}

// Applies the world rotation W to joint j (and so to its subtree), about the joint:
// local' = Pᵀ·W·P·local with P the parent's world rotation.
void rotateJoint(const BodyModel& model, const Eigen::VectorXd& shape, BodyPose& pose, Canonical c,
                 const Eigen::Matrix3d& W) {
  const int j = jointOf(model, c);
  const PosedBody posed = poseBody(model, {shape, pose});
  const int parent = model.parents[j];
  const Eigen::Matrix3d P =
      parent >= 0 ? Eigen::Matrix3d(posed.skinning[parent].linear()) : Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d local = axisAngleToMatrix(pose.axisAngle.row(j).transpose());
  pose.axisAngle.row(j) = matrixToAxisAngle(P.transpose() * W * P * local).transpose();
}

// Arms `down` degrees below horizontal, in the frontal plane.
BodyPose armsBelowHorizontal(const BodyModel& model, const Eigen::VectorXd& shape, double down) {
  BodyPose pose = standardPose(model, shape, StandardPose::TPose);
  rotateJoint(model, shape, pose, Canonical::LeftShoulder, rotZ(-down));  // left arm on +X
  rotateJoint(model, shape, pose, Canonical::RightShoulder, rotZ(down));
  return pose;
}

json vec(const Eigen::Vector3d& v) {
  return json::array({v.x(), v.y(), v.z()});
}

Eigen::Vector3d vecFrom(const json& j, const std::string& what) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    throw InputError("synth options: " + what + " must be [r, g, b]");
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

}  // namespace

// === Poses

const char* toString(SynthPose pose) {
  for (const auto& [p, name] : kPoseNames)
    if (p == pose) return name;
  return "invalid";
}

std::optional<SynthPose> parseSynthPose(std::string_view name) {
  for (const auto& [p, n] : kPoseNames)
    if (name == n) return p;
  return std::nullopt;
}

BodyPose synthPose(const BodyModel& model, const Eigen::VectorXd& shape, SynthPose which) {
  switch (which) {
    case SynthPose::APose:
      return standardPose(model, shape, StandardPose::APose);
    case SynthPose::TPose:
      return standardPose(model, shape, StandardPose::TPose);
    case SynthPose::ArmsDown:
      return armsBelowHorizontal(model, shape, 72);
    case SynthPose::Walking: {
      BodyPose pose = armsBelowHorizontal(model, shape, 70);
      rotateJoint(model, shape, pose, Canonical::LeftHip, rotX(-22));        // thigh forwards (+Z)
      rotateJoint(model, shape, pose, Canonical::RightHip, rotX(14));        // thigh backwards
      rotateJoint(model, shape, pose, Canonical::RightKnee, rotX(28));       // shin further back
      rotateJoint(model, shape, pose, Canonical::LeftShoulder, rotX(14));    // arms swing against
      rotateJoint(model, shape, pose, Canonical::RightShoulder, rotX(-14));  // the legs
      return pose;
    }
    case SynthPose::BentArm: {
      BodyPose pose = standardPose(model, shape, StandardPose::APose);
      const PosedBody posed = poseBody(model, {shape, pose});
      const Eigen::Vector3d elbow = posed.canonical.row(static_cast<int>(Canonical::LeftElbow));
      const Eigen::Vector3d wrist = posed.canonical.row(static_cast<int>(Canonical::LeftWrist));
      const Eigen::Vector3d axis = (wrist - elbow).cross(Eigen::Vector3d::UnitZ()).normalized();
      rotateJoint(model, shape, pose, Canonical::LeftElbow,
                  Eigen::AngleAxisd(deg(90), axis).toRotationMatrix());  // forearm to the front
      return pose;
    }
    case SynthPose::Relaxed: {
      BodyPose pose = armsBelowHorizontal(model, shape, 86);
      rotateJoint(model, shape, pose, Canonical::Neck, rotX(15));  // head bowed (top to +Z)
      return pose;
    }
  }
  return standardPose(model, shape, StandardPose::APose);
}

// === Options as JSON

json synthOptionsToJson(const SynthOptions& o) {
  json garments = json::array();
  for (const auto& g : o.outfit.garments)
    garments.push_back({{"type", toString(g.type)},
                        {"name", g.name},
                        {"base", vec(g.look.base)},
                        {"second", vec(g.look.second)},
                        {"pattern", toString(g.look.pattern)},
                        {"period", g.look.period},
                        {"ease", g.ease},
                        {"looseness", g.looseness},
                        {"length", g.length},
                        {"tucked_in", g.tuckedIn}});
  const GeometryOptions& g = o.geometry;
  return {{"preset", o.preset},
          {"body_source", o.bodySource},
          {"shape", o.shape},
          {"pose", toString(o.pose)},
          {"outfit",
           {{"garments", garments}, {"skin", vec(o.outfit.skin)}, {"hair", vec(o.outfit.hair)}}},
          {"geometry",
           {{"voxel_size", g.voxelSize},
            {"target_vertices", g.targetVertices},
            {"noise", g.noise},
            {"holes", g.holes},
            {"hole_radius", g.holeRadius}}},
          {"gap_colours", o.gapColours},
          {"shading", o.shading},
          {"key_light", o.keyLight},
          {"baked_light", bakedLightOptionsToJson(o.light)},
          {"yaw_degrees", o.yawDegrees},
          {"raw_scan", rawScanOptionsToJson(o.raw)},
          {"seed", o.seed}};
}

SynthOptions synthOptionsFromJson(const json& j) {
  SynthOptions o;
  try {
    if (!j.is_object()) throw InputError("synth options: not a JSON object");
    o.preset = j.value("preset", o.preset);
    o.bodySource = j.value("body_source", o.bodySource);
    o.shape = j.value("shape", o.shape);
    const std::string pose = j.value("pose", std::string(toString(o.pose)));
    const auto p = parseSynthPose(pose);
    if (!p)
      throw InputError("synth options: unknown pose '" + pose +
                       "' (apose, tpose, arms_down, walking, bent_arm, relaxed)");
    o.pose = *p;
    if (j.contains("outfit")) {
      const json& oj = j.at("outfit");
      if (oj.contains("skin")) o.outfit.skin = vecFrom(oj.at("skin"), "outfit.skin");
      if (oj.contains("hair")) o.outfit.hair = vecFrom(oj.at("hair"), "outfit.hair");
      for (const json& gj : oj.value("garments", json::array())) {
        GarmentSpec g;
        const std::string type = gj.at("type").get<std::string>();
        const auto t = parseGarmentType(type);
        if (!t) throw InputError("synth options: unknown garment type '" + type + "'");
        g.type = *t;
        g.name = gj.value("name", std::string());
        if (gj.contains("base")) g.look.base = vecFrom(gj.at("base"), "garment base");
        if (gj.contains("second")) g.look.second = vecFrom(gj.at("second"), "garment second");
        const std::string pattern = gj.value("pattern", std::string("solid"));
        const auto pk = parsePatternKind(pattern);
        if (!pk) throw InputError("synth options: unknown pattern '" + pattern + "'");
        g.look.pattern = *pk;
        g.look.period = gj.value("period", g.look.period);
        g.ease = gj.value("ease", g.ease);
        g.looseness = gj.value("looseness", g.looseness);
        g.length = gj.value("length", g.length);
        g.tuckedIn = gj.value("tucked_in", g.tuckedIn);
        o.outfit.garments.push_back(g);
      }
    }
    if (j.contains("geometry")) {
      const json& gj = j.at("geometry");
      o.geometry.voxelSize = gj.value("voxel_size", o.geometry.voxelSize);
      o.geometry.targetVertices = gj.value("target_vertices", o.geometry.targetVertices);
      o.geometry.noise = gj.value("noise", o.geometry.noise);
      o.geometry.holes = gj.value("holes", o.geometry.holes);
      o.geometry.holeRadius = gj.value("hole_radius", o.geometry.holeRadius);
    }
    o.gapColours = j.value("gap_colours", o.gapColours);
    o.shading = j.value("shading", o.shading);
    o.keyLight = j.value("key_light", o.keyLight);
    if (j.contains("baked_light")) o.light = bakedLightOptionsFromJson(j.at("baked_light"));
    o.yawDegrees = j.value("yaw_degrees", o.yawDegrees);
    if (j.contains("raw_scan")) o.raw = rawScanOptionsFromJson(j.at("raw_scan"));
    o.seed = j.value("seed", o.seed);
  } catch (const json::exception& e) {
    throw InputError(std::string("synth options: an entry has the wrong type (") + e.what() + ")");
  }
  return o;
}

// === Generation

double voxelSizeFor(int targetVertices, double requested) {
  if (targetVertices <= 0) return requested;
  return std::min(requested, std::sqrt(2.2 / (1.2 * targetVertices)));
}

namespace {

void validate(const SynthOptions& o) {
  const GeometryOptions& g = o.geometry;
  if (g.targetVertices < 0 || g.targetVertices > 5'000'000)
    throw InputError(fmt::format(
        "synth: target vertex count {} is out of range: use 0 (no decimation) up to 5000000",
        g.targetVertices));
  if (g.targetVertices > 0 && g.targetVertices < 1000)
    throw InputError(
        fmt::format("synth: target vertex count {} is too small for a person: use at least 1000",
                    g.targetVertices));
  if (!std::isfinite(g.voxelSize) || g.voxelSize <= 0 || g.voxelSize > 0.05)
    throw InputError("synth: voxel size must be in (0, 0.05] metres");
  if (!std::isfinite(g.noise) || g.noise < 0 || g.noise > 0.02)
    throw InputError("synth: positional noise must be in [0, 0.02] metres");
  if (g.holes < 0 || g.holes > 64) throw InputError("synth: holes must be in [0, 64]");
  if (!std::isfinite(o.yawDegrees)) throw InputError("synth: yaw must be a finite angle");
  if (!std::isfinite(o.shading) || o.shading < 0 || o.shading > 0.5)
    throw InputError("synth: shading must be in [0, 0.5]");
  if (!std::isfinite(o.keyLight) || o.keyLight < 0 || o.keyLight > 0.8)
    throw InputError("synth: key light strength must be in [0, 0.8]");
  if (!o.outfit.skin.allFinite() || !o.outfit.hair.allFinite())
    throw InputError("synth: skin and hair colours must be finite sRGB");
  validateRawScanOptions(o.raw);
  validateBakedLightOptions(o.light);
}

}  // namespace

SynthScan synthesize(const SynthOptions& options, Progress& progress) {
  validate(options);
  progress.begin("load body model " + options.bodySource);
  const BodyModel model = loadBodyModel(options.bodySource);
  progress.end();
  return synthesize(model, options, progress);
}

SynthScan synthesize(const BodyModel& model, const SynthOptions& options, Progress& progress) {
  validate(options);
  const Eigen::VectorXd shape = options.shape.empty()
                                    ? Eigen::VectorXd::Zero(model.numShapes()).eval()
                                    : parseShapeAssignments(model, options.shape);
  const BodyParams params{shape, synthPose(model, shape, options.pose)};
  GeometryOptions geometry = options.geometry;
  geometry.seed = subSeed(options.seed, 1);
  geometry.voxelSize = voxelSizeFor(geometry.targetVertices, geometry.voxelSize);
  const ClothedSurface surface =
      makeClothedSurface(model, params, options.outfit, geometry, progress);
  progress.begin("colours and truth");
  SynthScan out = assembleSynthScan(model, params, surface, options);
  progress.end();
  if (options.light.any()) {
    progress.begin("baked light (occlusion, bleeding, JPEG blocks)");
    bakeLight(out.scan.mesh, out.restPosition, out.scan.colour, options.light,
              subSeed(options.seed, 4));
    progress.end();
  }
  if (options.raw.any()) {
    progress.begin("raw-scan degradations");
    const RawScanStats st = degradeScan(out, options.raw, subSeed(options.seed, 3));
    progress.end();
    progress.message(fmt::format(
        "synth: raw scan: {} holes, {} faces unseen under the hem, {} floor faces, {} texture "
        "charts ({} vertex copies)",
        st.holes, st.unseenFaces, st.floorFaces, st.charts, st.duplicatedVertices));
  }
  return out;
}

SynthScan assembleSynthScan(const BodyModel& model, const BodyParams& params,
                            const ClothedSurface& surface, const SynthOptions& options) {
  const TriMesh& mesh = surface.mesh;
  const Eigen::Index nv = mesh.V.rows(), nf = mesh.F.rows();
  if (surface.vertexLabel.size() != nv || surface.vertexLayer.size() != nv ||
      surface.restPosition.rows() != nv || surface.faceLabel.size() != nf ||
      surface.faceLayer.size() != nf)
    throw InputError(fmt::format(
        "synth: the clothed surface's labels, layers and rest positions do not match its {} "
        "vertices and {} faces",
        nv, nf));
  if (params.pose.axisAngle.rows() != model.numJoints() ||
      (params.shape.size() != 0 && params.shape.size() != model.numShapes()))
    throw InputError(fmt::format("synth: body parameters do not fit {} ({} joints, {} shapes)",
                                 model.source, model.numJoints(), model.numShapes()));
  for (Eigen::Index f = 0; f < nf; ++f)
    if (!isValidLabel(surface.faceLabel(f)))
      throw InputError(fmt::format("synth: face {} has invalid label {}", f, surface.faceLabel(f)));

  SynthScan out;
  out.appearance = Appearance(options.outfit, {.shading = options.shading,
                                               .gapColours = options.gapColours,
                                               .keyLight = options.keyLight,
                                               .seed = subSeed(options.seed, 2)});
  out.scan.colour = out.appearance.colours(surface.vertexLayer, surface.vertexLabel,
                                           surface.restPosition, vertexNormals(mesh));
  out.scan.colourSource = ColourSource::Vertex;
  out.scan.sourcePath = "synthetic:" + options.preset;
  out.vertexLabel = surface.vertexLabel;
  out.faceLabel = surface.faceLabel;
  out.restPosition = surface.restPosition;
  out.faceLayer = surface.faceLayer;

  // Yaw about +Y through the origin: mesh and curves rotated; the body re-posed with the root
  // rotated and the translation moved so that every posed point is R·p.
  const Eigen::Matrix3d R = rotY(options.yawDegrees);
  out.scan.mesh.F = mesh.F;
  out.scan.mesh.V = mesh.V * R.transpose();
  BodyParams yawed = params;
  if (yawed.shape.size() == 0) yawed.shape = Eigen::VectorXd::Zero(model.numShapes());
  const Eigen::Vector3d j0 = restJoints(model, yawed.shape).row(0).transpose();
  yawed.pose.axisAngle.row(0) =
      matrixToAxisAngle(R * axisAngleToMatrix(params.pose.axisAngle.row(0).transpose()))
          .transpose();
  yawed.pose.translation = R * params.pose.translation + R * j0 - j0;
  const PosedBody posed = poseBody(model, yawed);

  Truth& t = out.truth;
  t.preset = options.preset;
  t.seed = options.seed;
  t.garments = surface.garments;
  t.body = bodyToJson(model, yawed, posed);
  t.boundaries = surface.boundaries;
  for (TrueBoundary& b : t.boundaries)
    for (Eigen::MatrixX3d& c : b.curves) c = (c * R.transpose()).eval();
  t.generator = synthOptionsToJson(options);
  return out;
}

// === Writing

std::optional<SynthFormat> parseSynthFormat(std::string_view name) {
  if (name == "ply") return SynthFormat::Ply;
  if (name == "obj") return SynthFormat::Obj;
  return std::nullopt;
}

Rgb labelPreviewColour(Label label) {
  switch (label) {
    case Label::Skin:
      return {222, 184, 135};
    case Label::Upper:
      return {210, 40, 40};
    case Label::Lower:
      return {40, 70, 200};
    case Label::Shoes:
      return {60, 60, 60};
    case Label::Hair:
      return {110, 70, 30};
    case Label::Other:
      return {40, 160, 60};
    case Label::Gap:
      return {240, 220, 30};
  }
  return {255, 0, 255};
}

Eigen::MatrixX3d labelColours(const Eigen::VectorXi& labels) {
  Eigen::MatrixX3d c(labels.size(), 3);
  for (Eigen::Index i = 0; i < labels.size(); ++i) {
    const Rgb rgb = isValidLabel(labels(i)) ? labelPreviewColour(static_cast<Label>(labels(i)))
                                            : Rgb{255, 0, 255};
    c.row(i) << rgb.r / 255.0, rgb.g / 255.0, rgb.b / 255.0;
  }
  return c;
}

Texture synthTexture(const SynthScan& s) {
  const TriMesh& mesh = s.scan.mesh;
  const int nf = mesh.numFaces();
  const Eigen::MatrixX3d faceN = faceNormals(mesh);
  // Unrotated normals for the shading term (yaw is about +Y, so n.y is unchanged).
  // Corner detail of each face with the face's own layer and label, so that
  // colour(f, b) = Σ b_k·vertexColour_k + detail(f, p(b)) − Σ b_k·detail(f, p_k):
  // the vertex colours at the corners, the face's solid texture inside.
  std::vector<std::array<Eigen::Vector3d, 3>> cornerDetail(static_cast<std::size_t>(nf));
  for (int f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      cornerDetail[f][k] = s.appearance.colour(s.faceLayer(f), static_cast<Label>(s.faceLabel(f)),
                                               s.restPosition.row(mesh.F(f, k)).transpose(),
                                               faceN.row(f).transpose());
  const FaceColourFn colour = [&](int f, const Eigen::Vector3d& b) -> Eigen::Vector3d {
    Eigen::Vector3d rest = Eigen::Vector3d::Zero(), base = Eigen::Vector3d::Zero(),
                    detail = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.F(f, k);
      rest += b[k] * s.restPosition.row(v).transpose();
      base += b[k] * s.scan.colour.row(v).transpose();
      detail += b[k] * cornerDetail[f][k];
    }
    return base +
           s.appearance.colour(s.faceLayer(f), static_cast<Label>(s.faceLabel(f)), rest,
                               faceN.row(f).transpose()) -
           detail;
  };
  Texture t = bakeAtlas(nf, colour);
  t.path = "scan.png";
  return t;
}

std::vector<fs::path> writeSynthScan(const fs::path& dir, const SynthScan& s, SynthFormat format,
                                     const SynthWriteOptions& options) {
  if (s.scan.colour.rows() != s.scan.mesh.V.rows() ||
      s.vertexLabel.size() != s.scan.mesh.V.rows() || s.faceLabel.size() != s.scan.mesh.F.rows())
    throw InputError("writeSynthScan: colours or labels do not match the scan's mesh");
  // === Everything in memory first.
  Truth truth = s.truth;
  truth.scanFile = format == SynthFormat::Ply ? "scan.ply" : "scan.obj";
  truth.labelledMesh = format == SynthFormat::Ply ? "scan.ply" : "labels.ply";
  std::optional<Texture> texture;
  if (format == SynthFormat::Obj) texture = synthTexture(s);
  Image previewScan, previewLabels;
  const Eigen::MatrixX3d byLabel = labelColours(s.vertexLabel);
  if (options.previews) {
    RenderOptions ro;
    ro.views = {View::Front, View::Back};
    ro.captions = {"front", "back"};
    ro.heightPx = options.previewHeightPx;
    Scene scene;
    scene.meshes.push_back({&s.scan.mesh, &s.scan.colour});
    previewScan = renderScene(scene, ro);
    scene.meshes[0].colour = &byLabel;
    previewLabels = renderScene(scene, ro);
  }
  // === Then the files.
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw IoError(fmt::format("cannot create the output folder {} ({}): choose a writable place",
                              dir.string(), ec ? ec.message() : "not a folder"));
  std::vector<fs::path> written;
  MeshAttributes attrs;
  attrs.vertexLabels = &s.vertexLabel;
  attrs.faceLabels = &s.faceLabel;
  if (format == SynthFormat::Ply) {
    attrs.colour = &s.scan.colour;
    writePly(dir / "scan.ply", s.scan.mesh, attrs);
    written.push_back(dir / "scan.ply");
  } else {
    writeObjTextured(dir / "scan.obj", s.scan.mesh, *texture);
    writePly(dir / "labels.ply", s.scan.mesh, attrs);
    for (const char* name : {"scan.obj", "scan.mtl", "scan.png", "labels.ply"})
      written.push_back(dir / name);
  }
  writeTruth(dir / "truth.json", truth);
  written.push_back(dir / "truth.json");
  if (options.previews) {
    writePng(dir / "preview_scan.png", previewScan);
    writePng(dir / "preview_labels.png", previewLabels);
    written.push_back(dir / "preview_scan.png");
    written.push_back(dir / "preview_labels.png");
  }
  return written;
}

}  // namespace s2p
