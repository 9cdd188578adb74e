// The synthetic scan generator end to end: options (body source, shape, pose, outfit, geometry,
// colours, corruptions, seed) → a coloured scan with per-vertex and per-face labels and its
// ground truth; and the writer of the scan folder (scan + labels + truth.json + previews).
// Deterministic: the same options give byte-identical files.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "body/body_model.h"
#include "core/progress.h"
#include "export/preview.h"
#include "io/scan.h"
#include "synth/appearance.h"
#include "synth/baked_light.h"
#include "synth/clothed_surface.h"
#include "synth/outfit.h"
#include "synth/raw_scan.h"
#include "synth/truth.h"

namespace s2p {

// === Poses: standardPose + axis-angle edits on canonical joints.
enum class SynthPose {
  APose,     // arms 45° below horizontal
  TPose,     // arms horizontal
  ArmsDown,  // arms 70° below horizontal: down, yet clear of the torso
  Walking,   // mid-stride: left leg forward, right leg back with the knee bent, arms swinging
  BentArm,   // A-pose with the left elbow bent 90° forwards
  Relaxed,   // standing relaxed: arms hanging 86° below horizontal, against the thighs (the
             // level set fuses where they touch), head bowed 15° at the neck
};
// "apose", "tpose", "arms_down", "walking", "bent_arm", "relaxed"
const char* toString(SynthPose pose);
std::optional<SynthPose> parseSynthPose(std::string_view name);
BodyPose synthPose(const BodyModel& model, const Eigen::VectorXd& shape, SynthPose pose);

struct SynthOptions {
  std::string preset = "custom";         // recorded in truth.json
  std::string bodySource = "mannequin";  // "mannequin" | "mpfb2:DIR" | "smpl:FILE" (loadBodyModel)
  std::string shape;                     // "name=value,..." (parseShapeAssignments); empty: β = 0
  SynthPose pose = SynthPose::APose;
  Outfit outfit;
  // voxelSize is lowered automatically when targetVertices needs a finer level set;
  // geometry.seed is derived from `seed`.
  GeometryOptions geometry;
  bool gapColours = false;  // gap faces get meaningless blotches (§5.2) instead of the inside
  double shading = 0.06;    // ± multiplicative shading noise
  double keyLight = 0;      // baked key light strength (AppearanceOptions::keyLight), 0: none
  BakedLightOptions light;  // ambient occlusion, colour bleeding, JPEG chroma blocks (none)
  double yawDegrees = 0;    // scan and truth rotated about +Y (orientation tests)
  RawScanOptions raw;       // raw-scan degradations after the colours (realistic family)
  std::uint64_t seed = 1;
};

// Options as JSON (truth.json "generator") and back; bad entries → InputError naming them.
nlohmann::json synthOptionsToJson(const SynthOptions& options);
SynthOptions synthOptionsFromJson(const nlohmann::json& json);

struct SynthScan {
  Scan scan;                    // mesh (metres, +Y up) + per-vertex sRGB colour
  Eigen::VectorXi vertexLabel;  // #V Label codes
  Eigen::VectorXi faceLabel;    // #F Label codes
  Truth truth;                  // scanFile / labelledMesh are filled by writeSynthScan
  // What the texture baker needs to evaluate colours inside the faces.
  Eigen::MatrixX3d restPosition;  // #V rest-pose body point under each vertex
  Eigen::VectorXi faceLayer;      // #F outfit layer shown (−1 skin)
  Appearance appearance{Outfit{}, AppearanceOptions{}};
};

// Loads the body source and generates. InputError on bad options, IoError/FormatError from the
// body source.
SynthScan synthesize(const SynthOptions& options, Progress& progress = Progress::silent());
// Same with a model already loaded (its source must be options.bodySource's model).
SynthScan synthesize(const BodyModel& model, const SynthOptions& options,
                     Progress& progress = Progress::silent());
// The part after the geometry: colours, yaw and truth from a clothed surface of `model` posed by
// `params` (unrotated). Exposed so it can be tested on surfaces built in tests.
SynthScan assembleSynthScan(const BodyModel& model, const BodyParams& params,
                            const ClothedSurface& surface, const SynthOptions& options);

// The voxel size used for a target vertex count (level-set meshes have about 2.2 m² / voxel²
// vertices): min(requested, √(2.2 / (1.2·target))).
double voxelSizeFor(int targetVertices, double requested);

// === Writing

enum class SynthFormat { Ply, Obj };
std::optional<SynthFormat> parseSynthFormat(std::string_view name);  // "ply" | "obj"

struct SynthWriteOptions {
  bool previews = true;  // preview_scan.png and preview_labels.png (front and back)
  int previewHeightPx = 800;
};

// Writes into `dir` (created if needed): ply → scan.ply (colour + vertex and face labels);
// obj → scan.obj + scan.mtl + scan.png (texture atlas) and labels.ply (same vertices and faces,
// labels); truth.json in both; previews. Everything is computed before the first file is
// written. Returns the files written. Folder not writable → IoError.
std::vector<std::filesystem::path> writeSynthScan(const std::filesystem::path& dir,
                                                  const SynthScan& scan, SynthFormat format,
                                                  const SynthWriteOptions& options = {});

// The texture atlas of a synthetic scan: colours inside each face from the solid textures, equal
// to the vertex colours at the corners.
Texture synthTexture(const SynthScan& scan);

// Preview colours per label: skin tan, upper red, lower blue, shoes dark grey, hair brown,
// other green, gap yellow.
Rgb labelPreviewColour(Label label);
Eigen::MatrixX3d labelColours(const Eigen::VectorXi& labels);  // #N → #N×3 sRGB

}  // namespace s2p
