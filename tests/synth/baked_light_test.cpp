// Baked light: known visibilities of a crease, bleeding towards the occluder's colour, JPEG
// chroma blocks that keep lightness, determinism.
#include "synth/baked_light.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <tuple>

#include "core/error.h"
#include "core/shapes.h"

namespace s2p {
namespace {

// A floor (y = 0, x ∈ [0, 1]) folded up into a wall (x = 0, y ∈ [0, 1]), both z ∈ [−0.5, 0.5],
// facing into the quarter space x > 0, y > 0: a 90° crease along the z axis whose vertices
// have the bisector (1, 1, 0)/√2 as their normal.
TriMesh crease(int n) {
  TriMesh m = makeGrid(2 * n, n, 2.0, 1.0);  // z = 0, normals +z
  for (int v = 0; v < m.numVertices(); ++v) {
    const double a = m.V(v, 0) - 1, b = m.V(v, 1) - 0.5;
    if (a >= 0)
      m.V.row(v) << a, 0, -b;  // floor, normal +y
    else
      m.V.row(v) << 0, -a, -b;  // wall, normal +x
  }
  return m;
}

int vertexAt(const TriMesh& m, const Eigen::Vector3d& p) {
  int best = 0;
  for (int v = 1; v < m.numVertices(); ++v)
    if ((m.V.row(v).transpose() - p).norm() < (m.V.row(best).transpose() - p).norm()) best = v;
  return best;
}

TEST(BakedLight, ACreaseSeesTheCosineWeightedShareOfItsQuarterSpace) {
  // A point on the crease with its normal on the bisector sees directions within 45° of the
  // normal's azimuth: ∫cos = π·sin 45°, of π for the hemisphere, so 0.707. A floor point
  // farther than `reach` from the wall sees the whole sky.
  const TriMesh m = crease(20);
  const Eigen::VectorXd visible = skyVisibility(m, 0.25, 4096, 7);
  const int onCrease = vertexAt(m, {0, 0, 0}), farFloor = vertexAt(m, {0.6, 0, 0});
  EXPECT_NEAR(visible(onCrease), std::sin(M_PI / 4), 0.03);
  EXPECT_DOUBLE_EQ(visible(farFloor), 1.0);
}

TEST(BakedLight, OcclusionDarkensTheCreaseAndTheBounceCarriesTheFloorsColourUpTheWall) {
  const TriMesh m = crease(20);
  const int nv = m.numVertices();
  Eigen::MatrixX3d srgb(nv, 3);
  for (int v = 0; v < nv; ++v)  // a red floor, a grey wall
    srgb.row(v) =
        m.V(v, 1) == 0 ? Eigen::RowVector3d(0.8, 0.1, 0.1) : Eigen::RowVector3d(0.7, 0.7, 0.7);
  const int low = vertexAt(m, {0, 0.05, 0}), high = vertexAt(m, {0, 0.9, 0});

  Eigen::MatrixX3d dark = srgb;
  bakeLight(m, m.V, dark, {.occlusion = 0.8, .bounce = 0, .rays = 256}, 3);
  EXPECT_LT(dark(low, 0), srgb(low, 0) - 0.05);     // occluded by the floor: darker
  EXPECT_NEAR(dark(high, 0), srgb(high, 0), 0.01);  // out of the floor's reach: unchanged
  EXPECT_NEAR(dark(low, 0), dark(low, 1), 1e-9);    // no bounce: still grey

  Eigen::MatrixX3d bled = srgb;
  bakeLight(m, m.V, bled, {.occlusion = 0.8, .bounce = 0.8, .rays = 256}, 3);
  // A third of the low wall's rays hit the floor (dark: 0.70 → 0.61 sRGB); they bring back
  // 0.8 × 0.8 × the floor's linear red 0.60, so red rises to ≈ 0.65 while green barely moves.
  EXPECT_GT(bled(low, 0), bled(low, 1) + 0.03);    // the wall low down turns red
  EXPECT_NEAR(bled(low, 1), dark(low, 1), 0.005);  // the floor has next to no green to give
  EXPECT_GT(bled(low, 0), dark(low, 0));           // and gets more light than without the bounce

  Eigen::MatrixX3d again = srgb;
  bakeLight(m, m.V, again, {.occlusion = 0.8, .bounce = 0.8, .rays = 256}, 3);
  EXPECT_EQ(again, bled);  // deterministic
}

TEST(BakedLight, ChromaBlocksShareOneChromaAndKeepEachVertexsLightness) {
  const TriMesh m = makeGrid(40, 40, 0.2, 0.2);  // 5 mm spacing
  Eigen::MatrixX3d srgb(m.numVertices(), 3);
  for (int v = 0; v < m.numVertices(); ++v)  // a green-blue edge at x = 0.11 plus a lightness ramp
    srgb.row(v) =
        m.V(v, 0) < 0.11 ? Eigen::RowVector3d(0.2, 0.5, 0.3) : Eigen::RowVector3d(0.2, 0.3, 0.6);
  srgb.col(0).array() += 0.1 * m.V.col(1).array();
  Eigen::MatrixX3d blocked = srgb;
  const double side = 0.02;
  bakeLight(m, m.V, blocked, {.chromaBlock = side}, 1);
  auto ycc = [](const Eigen::RowVector3d& c) {
    const double y = 0.299 * c.x() + 0.587 * c.y() + 0.114 * c.z();
    return Eigen::Vector3d(y, 0.564 * (c.z() - y), 0.713 * (c.x() - y));
  };
  std::map<std::tuple<int, int>, Eigen::Vector3d> chroma;
  int edgeBlocksMixed = 0;
  for (int v = 0; v < m.numVertices(); ++v) {
    const Eigen::Vector3d before = ycc(srgb.row(v)), after = ycc(blocked.row(v));
    EXPECT_NEAR(after.x(), before.x(), 1e-9) << v;  // lightness kept
    const auto key = std::make_tuple(static_cast<int>(std::floor(m.V(v, 0) / side)),
                                     static_cast<int>(std::floor(m.V(v, 1) / side)));
    const auto [it, fresh] = chroma.try_emplace(key, after);
    if (!fresh) {
      EXPECT_LT((it->second - after).tail<2>().norm(), 1e-9) << v;
    }
    if ((after - before).tail<2>().norm() > 1e-3) ++edgeBlocksMixed;
  }
  EXPECT_GT(edgeBlocksMixed, 0);  // the block on the colour edge mixed its two chromas
}

TEST(BakedLight, OptionsOutOfRangeAreRefusedByName) {
  EXPECT_THROW(validateBakedLightOptions({.occlusion = 1.5}), InputError);
  EXPECT_THROW(validateBakedLightOptions({.rays = 0}), InputError);
  EXPECT_THROW(bakedLightOptionsFromJson(nlohmann::json{{"chroma_block", 0.5}}), InputError);
  const BakedLightOptions o{.occlusion = 0.5, .bounce = 0.3, .chromaBlock = 0.01};
  EXPECT_EQ(bakedLightOptionsToJson(bakedLightOptionsFromJson(bakedLightOptionsToJson(o))),
            bakedLightOptionsToJson(o));
}

}  // namespace
}  // namespace s2p
