// Light baked into a scan's colours as a photogrammetry texture keeps it (issues 17 and 18's
// realistic family), on top of the appearance's key light:
//   - ambient occlusion: where the surface sees little of the sky (armpits, the crotch, under a
//     hem, the inside of an arm hanging against the torso) the colour is darker;
//   - colour bleeding: the light that does arrive there has bounced off the occluding surface
//     and carries its colour (a red t-shirt reddens the inner arm beside it);
//   - chroma subsampling: a JPEG texture stores colour (Cb, Cr) at half the resolution of
//     lightness and in blocks, so a colour edge is smeared over a block and lightness carries
//     blocky quantisation noise.
// All computed in linear RGB on the posed scan mesh; lengths in metres.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <nlohmann/json.hpp>

#include "core/tri_mesh.h"

namespace s2p {

struct BakedLightOptions {
  // Share of the light that is ambient (from the whole sky): a vertex that sees a fraction V of
  // its hemisphere gets (1 − occlusion) + occlusion·V of the light. 0: no occlusion.
  double occlusion = 0;
  // Albedo of the first bounce: an occluded ray brings occlusion·bounce·(the colour it hits)
  // instead of nothing. 0: no bleeding.
  double bounce = 0;
  double reach = 0.25;  // m: a ray that hits nothing within this sees the sky
  int rays = 32;        // cosine-weighted hemisphere rays per vertex
  // Side of the cubes (in the rest pose, a stand-in for texture space) over which the chroma is
  // averaged, as a JPEG's 16×16-texel chroma blocks are. 0: off.
  double chromaBlock = 0;
  double blockNoise = 0;  // σ of a per-block lightness offset (sRGB units, 0–1): quantisation
  bool any() const { return occlusion > 0 || chromaBlock > 0 || blockNoise > 0; }
};

nlohmann::json bakedLightOptionsToJson(const BakedLightOptions& options);
// Missing entries keep their defaults; bad ones → InputError.
BakedLightOptions bakedLightOptionsFromJson(const nlohmann::json& json);
// Out-of-range values → InputError naming them.
void validateBakedLightOptions(const BakedLightOptions& options);

// Bakes the light into `srgb` (#V×3 in [0, 1], the vertex colours of `mesh`, changed in place).
// rest: #V×3 rest-pose positions (the chroma blocks' space). Deterministic for a given seed.
// Throws InputError for sizes that do not match the mesh.
void bakeLight(const TriMesh& mesh, const Eigen::MatrixX3d& rest, Eigen::MatrixX3d& srgb,
               const BakedLightOptions& options, std::uint64_t seed);

// The visible fraction of each vertex's hemisphere (cosine-weighted, within `reach`): 1 on a
// convex surface, less in creases. #V.
Eigen::VectorXd skyVisibility(const TriMesh& mesh, double reach, int rays, std::uint64_t seed);

}  // namespace s2p
