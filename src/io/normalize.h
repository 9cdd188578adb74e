// Unit and up-axis normalisation (paper §3): the scan moves to metres, +Y up, feet on y = 0,
// centred in x/z on the bounding-box centre of its lowest 5 %. The inverse transform is kept
// in Scan::toInputFrame so results can be written back in the file's frame.
//
// Units: a standing person is 0.5–2.5 m tall; the ranges 0.5–2.5 (m), 5–25 (dm), 50–250 (cm)
// and 500–2500 (mm) do not overlap, so the height along the up axis picks the unit.
// Up axis: the larger of the Y and Z extents. Its sign combines three cues, each a vote:
//   - contact regions (weight 2): the faces touching the lowest / highest 5 % slab form two
//     or more separate groups at the feet end and one at the head end;
//   - width (weight 1): the horizontal bounding box of the feet-end slab is larger (feet point
//     forward and stand apart) than that of the head top (≥ 1.5× to count);
//   - area centroid (weight 1): the surface's area centroid lies above mid-height (torso,
//     arms and head carry more area than the legs), if it is off by > 2 % of the height.
// A positive sum means the +axis is up, negative −axis; a zero sum is ambiguous: +Y/+Z is
// taken and NormalizeReport::upAmbiguous says so.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/scan.h"

namespace s2p {

enum class Units { Auto, Millimetres, Centimetres, Decimetres, Metres };
enum class UpAxis { Auto, PosY, NegY, PosZ, NegZ };

struct NormalizeOptions {
  Units units = Units::Auto;  // Auto: detect from the height; otherwise forced (no size check)
  UpAxis up = UpAxis::Auto;   // Auto: detect; otherwise forced
};

struct NormalizeReport {
  Units units = Units::Metres;  // the file's units (detected or forced)
  UpAxis up = UpAxis::PosY;     // the file's up axis (detected or forced)
  double scale = 1;             // metres per file unit
  double heightMetres = 0;      // extent along the up axis after scaling
  bool unitsDetected = false;   // true when units were detected (Units::Auto)
  bool upDetected = false;      // true when the up axis was detected (UpAxis::Auto)
  bool upAmbiguous = false;     // detection had no clear sign: +Y/+Z assumed
  int upScore = 0;              // sum of the sign votes (see above); 0 when forced
  std::string upCues;           // the cues and their votes, for the report
  std::vector<std::string> warnings;
};

// Transforms scan.mesh in place and sets scan.toInputFrame (p_file = toInputFrame · p).
// Throws InputError "not a person: height X in file units; give --units" when no unit gives a
// plausible height, and for an empty or non-finite mesh.
NormalizeReport normalizeScan(Scan& scan, const NormalizeOptions& options = {});

// Metres per file unit (1 for Auto).
double metresPerUnit(Units units);
// The rotation taking the file's frame to +Y up (a proper rotation, det = +1).
Eigen::Matrix3d upRotation(UpAxis up);

const char* toString(Units units);  // "auto", "mm", "cm", "dm", "m"
const char* toString(UpAxis up);    // "auto", "+y", "-y", "+z", "-z"
// CLI strings: units "auto|mm|cm|dm|m" (also full names), up "auto|+y|y|-y|+z|z|-z".
// Case-insensitive; nullopt when unknown.
std::optional<Units> parseUnits(std::string_view text);
std::optional<UpAxis> parseUpAxis(std::string_view text);

}  // namespace s2p
