#include "synth/baked_light.h"

#include <tbb/parallel_for.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <random>
#include <unordered_map>

#include "core/colour.h"
#include "core/error.h"
#include "core/mesh_query.h"

namespace s2p {

namespace {

// A direction in the hemisphere around n with density cos θ / π (Malley's method).
Eigen::Vector3d cosineSample(const Eigen::Vector3d& n, double u1, double u2) {
  const double r = std::sqrt(u1), phi = 2 * std::numbers::pi * u2;
  const Eigen::Vector3d t =
      (std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY())
          .cross(n)
          .normalized();
  const Eigen::Vector3d b = n.cross(t);
  return (r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0, 1 - u1)) * n)
      .normalized();
}

std::uint64_t mix(std::uint64_t x) {  // splitmix64's finaliser
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

struct CellKey {
  long long x, y, z;
  bool operator==(const CellKey&) const = default;
};
struct CellHash {
  std::size_t operator()(const CellKey& k) const {
    return mix(static_cast<std::uint64_t>(k.x) * 73856093ull ^
               static_cast<std::uint64_t>(k.y) * 19349663ull ^
               static_cast<std::uint64_t>(k.z) * 83492791ull);
  }
};
CellKey cellOf(const Eigen::Vector3d& p, double side, double shift = 0) {
  return {static_cast<long long>(std::floor(p.x() / side + shift)),
          static_cast<long long>(std::floor(p.y() / side + shift)),
          static_cast<long long>(std::floor(p.z() / side + shift))};
}

// ITU-R BT.601 full-range luma and chroma of sRGB (what JPEG stores).
Eigen::Vector3d toYCbCr(const Eigen::Vector3d& c) {
  const double y = 0.299 * c.x() + 0.587 * c.y() + 0.114 * c.z();
  return {y, 0.564 * (c.z() - y), 0.713 * (c.x() - y)};
}
Eigen::Vector3d fromYCbCr(const Eigen::Vector3d& q) {
  const double r = q.x() + q.z() / 0.713, b = q.x() + q.y() / 0.564;
  const double g = (q.x() - 0.299 * r - 0.114 * b) / 0.587;
  return {r, g, b};
}

Eigen::Vector3d clamp01(const Eigen::Vector3d& c) {
  return c.cwiseMax(0.0).cwiseMin(1.0);
}

// What vertex v's hemisphere sees: the fraction of its cosine-weighted rays that reach the sky
// within `reach`, and the mean over all rays of the albedo the others hit (0 for open rays).
struct HemisphereLight {
  double open = 0;
  Eigen::Vector3d bounced = Eigen::Vector3d::Zero();
};
HemisphereLight gatherLight(const MeshQuery& query, const TriMesh& mesh,
                            const Eigen::MatrixX3d& normals, const Eigen::MatrixX3d* albedo, int v,
                            double reach, int rays, std::uint64_t seed) {
  std::mt19937_64 rng(mix(seed ^ mix(static_cast<std::uint64_t>(v))));
  std::uniform_real_distribution<double> u(0, 1);
  const Eigen::Vector3d n = normals.row(v).transpose(), p = mesh.V.row(v).transpose();
  HemisphereLight h;
  for (int r = 0; r < rays; ++r) {
    const auto hit = query.rayCast(p + 1e-4 * n, cosineSample(n, u(rng), u(rng)), 0, reach);
    if (!hit) {
      h.open += 1;
    } else if (albedo) {
      for (int k = 0; k < 3; ++k)
        h.bounced += hit->bary[k] * albedo->row(mesh.F(hit->face, k)).transpose();
    }
  }
  h.open /= rays;
  h.bounced /= rays;
  return h;
}

}  // namespace

nlohmann::json bakedLightOptionsToJson(const BakedLightOptions& o) {
  return {{"occlusion", o.occlusion},
          {"bounce", o.bounce},
          {"reach", o.reach},
          {"rays", o.rays},
          {"chroma_block", o.chromaBlock},
          {"block_noise", o.blockNoise}};
}

BakedLightOptions bakedLightOptionsFromJson(const nlohmann::json& j) {
  BakedLightOptions o;
  if (!j.is_object()) throw InputError("synth options: baked_light must be a JSON object");
  o.occlusion = j.value("occlusion", o.occlusion);
  o.bounce = j.value("bounce", o.bounce);
  o.reach = j.value("reach", o.reach);
  o.rays = j.value("rays", o.rays);
  o.chromaBlock = j.value("chroma_block", o.chromaBlock);
  o.blockNoise = j.value("block_noise", o.blockNoise);
  validateBakedLightOptions(o);
  return o;
}

void validateBakedLightOptions(const BakedLightOptions& o) {
  auto in = [](double x, double lo, double hi) { return std::isfinite(x) && x >= lo && x <= hi; };
  if (!in(o.occlusion, 0, 1)) throw InputError("synth baked light: occlusion must be in [0, 1]");
  if (!in(o.bounce, 0, 1)) throw InputError("synth baked light: bounce must be in [0, 1]");
  if (!in(o.reach, 0.01, 2)) throw InputError("synth baked light: reach must be in [0.01, 2] m");
  if (o.rays < 1 || o.rays > 1024) throw InputError("synth baked light: rays must be in [1, 1024]");
  if (!in(o.chromaBlock, 0, 0.05))
    throw InputError("synth baked light: chroma_block must be in [0, 0.05] m");
  if (!in(o.blockNoise, 0, 0.1))
    throw InputError("synth baked light: block_noise must be in [0, 0.1]");
}

Eigen::VectorXd skyVisibility(const TriMesh& mesh, double reach, int rays, std::uint64_t seed) {
  const MeshQuery query(mesh);
  const Eigen::MatrixX3d normals = vertexNormals(mesh);
  Eigen::VectorXd visible(mesh.numVertices());
  tbb::parallel_for(0, mesh.numVertices(), [&](int v) {
    visible(v) = gatherLight(query, mesh, normals, nullptr, v, reach, rays, seed).open;
  });
  return visible;
}

void bakeLight(const TriMesh& mesh, const Eigen::MatrixX3d& rest, Eigen::MatrixX3d& srgb,
               const BakedLightOptions& o, std::uint64_t seed) {
  validateBakedLightOptions(o);
  const int nv = mesh.numVertices();
  if (rest.rows() != nv || srgb.rows() != nv)
    throw InputError("baked light: rest positions and colours need one row per vertex");

  // === Occlusion and the first bounce, in linear RGB.
  if (o.occlusion > 0) {
    const MeshQuery query(mesh);
    const Eigen::MatrixX3d normals = vertexNormals(mesh);
    const Eigen::MatrixX3d albedo = srgbToLinear(srgb);
    Eigen::MatrixX3d lit(nv, 3);
    tbb::parallel_for(0, nv, [&](int v) {
      const HemisphereLight h =
          gatherLight(query, mesh, normals, &albedo, v, o.reach, o.rays, seed);
      const Eigen::Vector3d light = Eigen::Vector3d::Constant(h.open) + o.bounce * h.bounced;
      const Eigen::Vector3d factor =
          Eigen::Vector3d::Constant(1 - o.occlusion) + o.occlusion * light;
      lit.row(v) = albedo.row(v).cwiseProduct(factor.transpose());
    });
    srgb = linearToSrgb(lit.cwiseMax(0.0).cwiseMin(1.0).eval());
  }

  // === JPEG: chroma averaged per block, lightness offset per block.
  if (o.chromaBlock > 0 || o.blockNoise > 0) {
    const double side = o.chromaBlock > 0 ? o.chromaBlock : 0.006;
    std::unordered_map<CellKey, Eigen::Vector3d, CellHash> sum;  // Cb, Cr, count
    std::vector<Eigen::Vector3d> ycc(nv);
    for (int v = 0; v < nv; ++v) {
      ycc[v] = toYCbCr(srgb.row(v).transpose());
      auto [it, fresh] =
          sum.try_emplace(cellOf(rest.row(v).transpose(), side), Eigen::Vector3d::Zero());
      it->second += Eigen::Vector3d(ycc[v].y(), ycc[v].z(), 1);
    }
    for (int v = 0; v < nv; ++v) {
      Eigen::Vector3d q = ycc[v];
      if (o.chromaBlock > 0) {
        const Eigen::Vector3d& s = sum.at(cellOf(rest.row(v).transpose(), side));
        q.y() = s.x() / s.z();
        q.z() = s.y() / s.z();
      }
      if (o.blockNoise > 0) {
        // Luma blocks are half the chroma's side and on their own grid.
        const CellKey k = cellOf(rest.row(v).transpose(), side / 2, 0.5);
        std::mt19937_64 rng(mix(seed ^ CellHash{}(k)));
        q.x() += o.blockNoise * std::normal_distribution<double>(0, 1)(rng);
      }
      srgb.row(v) = clamp01(fromYCbCr(q)).transpose();
    }
  }
}

}  // namespace s2p
