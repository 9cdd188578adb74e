// Colours of a synthetic scan: solid textures evaluated at the rest-pose body point under each
// surface point (so stripes follow the body through any pose), skin tones from light to dark,
// mild low-frequency shading, and the meaningless colours of gap-filling triangles (§5.2).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "synth/outfit.h"
#include "synth/truth.h"

namespace s2p {

// === Noise of our own (value noise on an integer lattice, quintic fade: C² smooth)

// Value noise at p (lattice spacing 1), in [0, 1]. Deterministic per seed.
double valueNoise(const Eigen::Vector3d& p, std::uint64_t seed);
// Sum of `octaves` value-noise octaves (frequency ×2, amplitude ×½), rescaled to [0, 1].
double fractalNoise(const Eigen::Vector3d& p, std::uint64_t seed, int octaves = 3);
// Seed of a named sub-stream (geometry, appearance, ...) of a user seed: splitmix64 mixing.
std::uint64_t subSeed(std::uint64_t seed, std::uint64_t stream);

// === Patterns (no shading): `rest` is the rest-pose point, metres.
// Solid: base. Stripes: bands across +Y, one base + one second band per `period`.
// Checks: 3D checkerboard of cells period/2 wide. Dots: discs of radius period/4 at the nodes
// of a lattice of spacing `period`. Noise: base↔second mixed by fractal noise at scale `period`.
Eigen::Vector3d patternColour(const Look& look, const Eigen::Vector3d& rest, std::uint64_t seed);

// === Skin tones and hard cases

// Skin tones from light (first) to dark (last), sRGB.
const std::vector<Eigen::Vector3d>& skinToneTable();
// Piecewise-linear along the table: t = 0 lightest, t = 1 darkest (clamped).
Eigen::Vector3d skinTone(double t);
// A colour at CIELAB distance ΔE*ab = `deltaE` from `srgb` in a seeded direction (for the hard
// cases: low contrast between upper and lower, paper case t; a garment close to skin). The
// result is clamped into the sRGB gamut, which can shorten the distance near its edges.
Eigen::Vector3d colourNear(const Eigen::Vector3d& srgb, double deltaE, std::uint64_t seed);

// === Appearance of a whole outfit

struct AppearanceOptions {
  double shading = 0.06;       // ± amplitude of multiplicative low-frequency shading noise
  double shadingScale = 0.35;  // metres, feature size of the shading noise
  bool gapColours = false;     // gap faces: random blotches of nearby colours (else the inside)
  // Baked light (a scan's texture keeps the studio's light): a key light from the front, above
  // and to the person's left scales the colour by 1 + keyLight·(2·max(0, n·l) − 1), from
  // 1 − keyLight on the far side to 1 + keyLight facing it (clamped to sRGB). 0: none.
  double keyLight = 0;
  std::uint64_t seed = 1;
};

class Appearance {
 public:
  Appearance(const Outfit& outfit, const AppearanceOptions& options);

  // sRGB in [0, 1] at a surface point showing `layer` (index into outfit.garments, −1 = skin)
  // with label `label`, rest-pose point `rest` and unit normal `normal` (posed frame).
  Eigen::Vector3d colour(int layer, Label label, const Eigen::Vector3d& rest,
                         const Eigen::Vector3d& normal) const;
  // Row-wise: layer, label #N; rest, normal #N×3 → #N×3.
  Eigen::MatrixX3d colours(const Eigen::VectorXi& layer, const Eigen::VectorXi& label,
                           const Eigen::MatrixX3d& rest, const Eigen::MatrixX3d& normal) const;

  const Outfit& outfit() const { return outfit_; }
  const AppearanceOptions& options() const { return options_; }

 private:
  Eigen::Vector3d unshaded(int layer, Label label, const Eigen::Vector3d& rest) const;

  Outfit outfit_;
  AppearanceOptions options_;
  std::vector<Eigen::Vector3d> gapPalette_;  // colours the gap blotches mix
  int gapLayer_ = -1;                        // the free-hanging garment, if any
};

}  // namespace s2p
