#include "synth/appearance.h"

#include <algorithm>
#include <cmath>

#include "core/colour.h"
#include "core/error.h"

namespace s2p {
namespace {

std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// Uniform in [0, 1) at an integer lattice node.
double latticeValue(std::int64_t i, std::int64_t j, std::int64_t k, std::uint64_t seed) {
  std::uint64_t h = splitmix(seed ^ splitmix(static_cast<std::uint64_t>(i)));
  h = splitmix(h ^ static_cast<std::uint64_t>(j) * 0x632BE59BD9B4E019ull);
  h = splitmix(h ^ static_cast<std::uint64_t>(k) * 0x85157AF5ull);
  return static_cast<double>(h >> 11) * (1.0 / 9007199254740992.0);
}

double fade(double t) {
  return t * t * t * (t * (t * 6 - 15) + 10);
}

double fract(double x) {
  return x - std::floor(x);
}

Eigen::Vector3d clamp01(const Eigen::Vector3d& c) {
  return c.cwiseMax(0.0).cwiseMin(1.0);
}

}  // namespace

std::uint64_t subSeed(std::uint64_t seed, std::uint64_t stream) {
  return splitmix(splitmix(seed) ^ (stream * 0xD1B54A32D192ED03ull));
}

double valueNoise(const Eigen::Vector3d& p, std::uint64_t seed) {
  const double fx = std::floor(p.x()), fy = std::floor(p.y()), fz = std::floor(p.z());
  const auto i = static_cast<std::int64_t>(fx), j = static_cast<std::int64_t>(fy),
             k = static_cast<std::int64_t>(fz);
  const double u = fade(p.x() - fx), v = fade(p.y() - fy), w = fade(p.z() - fz);
  double c[2][2][2];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int d = 0; d < 2; ++d) c[a][b][d] = latticeValue(i + a, j + b, k + d, seed);
  auto lerp = [](double x, double y, double t) { return x + (y - x) * t; };
  const double x00 = lerp(c[0][0][0], c[1][0][0], u), x10 = lerp(c[0][1][0], c[1][1][0], u);
  const double x01 = lerp(c[0][0][1], c[1][0][1], u), x11 = lerp(c[0][1][1], c[1][1][1], u);
  return lerp(lerp(x00, x10, v), lerp(x01, x11, v), w);
}

double fractalNoise(const Eigen::Vector3d& p, std::uint64_t seed, int octaves) {
  double sum = 0, amp = 1, norm = 0, freq = 1;
  for (int o = 0; o < std::max(octaves, 1); ++o) {
    sum += amp * valueNoise(p * freq, subSeed(seed, static_cast<std::uint64_t>(o)));
    norm += amp;
    amp *= 0.5;
    freq *= 2.0;
  }
  return sum / norm;
}

Eigen::Vector3d patternColour(const Look& look, const Eigen::Vector3d& rest, std::uint64_t seed) {
  const double period = look.period > 1e-6 ? look.period : 0.04;
  switch (look.pattern) {
    case PatternKind::Solid:
      return look.base;
    case PatternKind::Stripes:
      return fract(rest.y() / period) < 0.5 ? look.base : look.second;
    case PatternKind::Checks: {
      const Eigen::Vector3d c = (rest / (period / 2)).array().floor();
      const auto parity = static_cast<std::int64_t>(c.x() + c.y() + c.z());
      return (parity & 1) == 0 ? look.base : look.second;
    }
    case PatternKind::Dots: {
      const Eigen::Vector3d q = rest / period;
      const Eigen::Vector3d d = q - q.array().round().matrix();
      return d.norm() < 0.25 ? look.second : look.base;
    }
    case PatternKind::Noise: {
      const double t = fractalNoise(rest / period, seed, 3);
      const double s = std::clamp((t - 0.5) * 2.5 + 0.5, 0.0, 1.0);  // more contrast
      return (1 - s) * look.base + s * look.second;
    }
  }
  return look.base;
}

const std::vector<Eigen::Vector3d>& skinToneTable() {
  static const std::vector<Eigen::Vector3d> table = {
      {0.96, 0.82, 0.72}, {0.92, 0.74, 0.62}, {0.86, 0.66, 0.53}, {0.78, 0.58, 0.45},
      {0.67, 0.48, 0.35}, {0.55, 0.38, 0.27}, {0.42, 0.28, 0.20}, {0.29, 0.19, 0.13}};
  return table;
}

Eigen::Vector3d skinTone(double t) {
  const auto& table = skinToneTable();
  const double x =
      std::clamp(std::isfinite(t) ? t : 0.0, 0.0, 1.0) * static_cast<double>(table.size() - 1);
  const auto i = std::min(static_cast<std::size_t>(x), table.size() - 2);
  const double f = x - static_cast<double>(i);
  return (1 - f) * table[i] + f * table[i + 1];
}

Eigen::Vector3d colourNear(const Eigen::Vector3d& srgb, double deltaE, std::uint64_t seed) {
  const Eigen::Vector3d lab = srgbToLab(clamp01(srgb));
  const double phi = 2 * M_PI * latticeValue(1, 2, 3, seed);
  // Mostly lightness and a little hue, as two similar fabrics differ.
  Eigen::Vector3d dir(0.8 * (lab.x() > 50 ? -1.0 : 1.0), 0.6 * std::cos(phi), 0.6 * std::sin(phi));
  dir.normalize();
  return clamp01(labToSrgb(Eigen::Vector3d(lab + deltaE * dir)));
}

// === Appearance

Appearance::Appearance(const Outfit& outfit, const AppearanceOptions& options)
    : outfit_(outfit), options_(options) {
  if (!std::isfinite(options.shading) || options.shading < 0 || options.shading > 0.5)
    throw InputError("appearance: shading amplitude must be in [0, 0.5]");
  if (!std::isfinite(options.keyLight) || options.keyLight < 0 || options.keyLight > 0.8)
    throw InputError("appearance: key light strength must be in [0, 0.8]");
  if (!std::isfinite(options.shadingScale) || options.shadingScale <= 0)
    throw InputError("appearance: shading scale must be a positive length in metres");
  for (std::size_t i = 0; i < outfit.garments.size(); ++i) {
    const Look& l = outfit.garments[i].look;
    if (!l.base.allFinite() || !l.second.allFinite() || !std::isfinite(l.period) || l.period <= 0)
      throw InputError("appearance: garment " + std::to_string(i) +
                       " has a non-finite colour or a non-positive pattern period");
    if (gapLayer_ < 0 && isFreeHanging(outfit.garments[i].type)) gapLayer_ = static_cast<int>(i);
  }
  // Nearby colours: every garment's colours and the skin, plus two seeded stray colours.
  for (const auto& g : outfit.garments) {
    gapPalette_.push_back(g.look.base);
    gapPalette_.push_back(g.look.second);
  }
  gapPalette_.push_back(outfit.skin);
  for (std::uint64_t k = 0; k < 2; ++k) {
    const std::uint64_t s = subSeed(options.seed, 100 + k);
    gapPalette_.emplace_back(latticeValue(0, 0, 0, s), latticeValue(1, 0, 0, s),
                             latticeValue(2, 0, 0, s));
  }
}

Eigen::Vector3d Appearance::unshaded(int layer, Label label, const Eigen::Vector3d& rest) const {
  const int n = static_cast<int>(outfit_.garments.size());
  if (label == Label::Gap) {
    if (options_.gapColours) {
      // Blotches ~5 cm across, each mixing two palette colours.
      const auto k = static_cast<double>(gapPalette_.size());
      const std::uint64_t s = subSeed(options_.seed, 7);
      const auto pick = [&](std::uint64_t stream) {
        const double t = fractalNoise(rest / 0.05, subSeed(s, stream), 2);
        const auto i = static_cast<std::size_t>(fract(5 * t) * k);
        return gapPalette_[std::min(i, gapPalette_.size() - 1)];
      };
      const double t = fade(valueNoise(rest / 0.03, subSeed(s, 3)));
      return (1 - t) * pick(1) + t * pick(2);
    }
    const int g = layer >= 0 && layer < n ? layer : gapLayer_;
    const Eigen::Vector3d base = g >= 0 ? outfit_.garments[g].look.base : outfit_.skin;
    return 0.45 * base;  // the garment's inside, in its own shadow
  }
  if (label == Label::Skin || layer < 0 || layer >= n) {
    // Skin: the tone with faint blotchiness.
    const double t = fractalNoise(rest / 0.08, subSeed(options_.seed, 11), 2);
    return outfit_.skin * (0.96 + 0.08 * t);
  }
  const GarmentSpec& g = outfit_.garments[layer];
  if (g.type == GarmentType::Hair) {
    // Strands: fine noise stretched along Y.
    const Eigen::Vector3d q(rest.x() / 0.004, rest.y() / 0.06, rest.z() / 0.004);
    const double t = fractalNoise(q, subSeed(options_.seed, 12), 2);
    return outfit_.hair * (0.8 + 0.4 * t);
  }
  return patternColour(g.look, rest,
                       subSeed(options_.seed, 20 + static_cast<std::uint64_t>(layer)));
}

Eigen::Vector3d Appearance::colour(int layer, Label label, const Eigen::Vector3d& rest,
                                   const Eigen::Vector3d& normal) const {
  const Eigen::Vector3d c = unshaded(layer, label, rest);
  // Multiplicative, low-frequency: uneven lighting and fabric tone; a little darker where the
  // surface faces the floor (studio lights from above).
  const double noise = fractalNoise(rest / options_.shadingScale, subSeed(options_.seed, 5), 2);
  const double down = std::max(0.0, -normal.y());
  double factor = (1 + options_.shading * (2 * noise - 1)) * (1 - 0.08 * down);
  if (options_.keyLight > 0) {
    const Eigen::Vector3d light = Eigen::Vector3d(0.5, 0.7, 0.6).normalized();
    factor *= 1 + options_.keyLight * (2 * std::max(0.0, normal.dot(light)) - 1);
  }
  return clamp01(c * factor);
}

Eigen::MatrixX3d Appearance::colours(const Eigen::VectorXi& layer, const Eigen::VectorXi& label,
                                     const Eigen::MatrixX3d& rest,
                                     const Eigen::MatrixX3d& normal) const {
  const Eigen::Index n = rest.rows();
  if (layer.size() != n || label.size() != n || normal.rows() != n)
    throw InputError("appearance: layer, label, rest and normal need one row per point");
  Eigen::MatrixX3d out(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!isValidLabel(label(i)))
      throw InputError("appearance: point " + std::to_string(i) + " has an invalid label " +
                       std::to_string(label(i)));
    out.row(i) = colour(layer(i), static_cast<Label>(label(i)), rest.row(i).transpose(),
                        normal.row(i).transpose())
                     .transpose();
  }
  return out;
}

}  // namespace s2p
