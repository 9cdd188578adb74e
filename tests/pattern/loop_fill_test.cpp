// fillLoop on loops of known answer: a square on a saddle z = k·x·y (a harmonic function, so the
// membrane is the saddle itself), a flat square (its area), and a loop that crosses itself (no
// fill).
#include "pattern/loop_fill.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/mesh_topology.h"
#include "core/tri_mesh.h"

namespace s2p {
namespace {

using Vec3 = Eigen::Vector3d;

// The border of [0, s]² walked counter-clockwise, n points a side, z = height(x, y).
template <typename H>
std::vector<Vec3> squareLoop(double s, int n, H height) {
  std::vector<Vec3> loop;
  const auto add = [&](double x, double y) { loop.push_back({x, y, height(x, y)}); };
  for (int i = 0; i < n; ++i) add(s * i / n, 0);
  for (int i = 0; i < n; ++i) add(s, s * i / n);
  for (int i = 0; i < n; ++i) add(s - s * i / n, s);
  for (int i = 0; i < n; ++i) add(0, s - s * i / n);
  return loop;
}

TEST(LoopFill, AFlatSquareIsFilledWithItsAreaAndKeepsItsBorder) {
  const std::vector<Vec3> loop = squareLoop(0.2, 20, [](double, double) { return 0.0; });
  const auto fill = fillLoop(loop, 0.01);
  ASSERT_TRUE(fill.has_value());
  for (size_t i = 0; i < loop.size(); ++i)
    EXPECT_EQ((fill->V.row(static_cast<int>(i)).transpose() - loop[i]).norm(), 0.0) << i;
  TriMesh m{fill->V, fill->F};
  EXPECT_NEAR(surfaceArea(m), 0.04, 1e-12);
  const MeshTopology t(m.F, m.numVertices());
  ASSERT_EQ(t.boundaryLoops().size(), 1u);
  EXPECT_EQ(t.boundaryLoops()[0].size(), loop.size());  // no point added on the loop
  EXPECT_EQ(t.eulerCharacteristic(), 1);
  EXPECT_GT(m.numVertices(), static_cast<int>(loop.size()) + 100);  // meshed inside at 1 cm
  EXPECT_EQ(fill->bump.head(static_cast<int>(loop.size())).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_DOUBLE_EQ(fill->bump.maxCoeff(), 1.0);
}

TEST(LoopFill, ASaddleBorderIsFilledWithTheSaddle) {
  const double k = 2.0;  // z up to 8 cm over the 20 cm square
  const auto saddle = [k](double x, double y) { return k * (x - 0.1) * (y - 0.1); };
  const auto fill = fillLoop(squareLoop(0.2, 20, saddle), 0.01);
  ASSERT_TRUE(fill.has_value());
  double worst = 0;
  for (int v = 0; v < fill->V.rows(); ++v) {
    const Vec3 p = fill->V.row(v).transpose();
    worst = std::max(worst, std::abs(p.z() - saddle(p.x(), p.y())));
  }
  // The plane of best fit is z = 0 here (the saddle is odd in x − 0.1), so the harmonic height
  // is the saddle up to the discretisation.
  EXPECT_LT(worst, 2e-4);
}

TEST(LoopFill, ALoopThatCrossesItselfIsNotFilled) {
  // A figure of eight in the plane.
  std::vector<Vec3> loop;
  for (int i = 0; i < 40; ++i) {
    const double t = 2 * M_PI * i / 40;
    loop.push_back({0.1 * std::sin(t), 0.05 * std::sin(2 * t), 0});
  }
  std::string why;
  EXPECT_FALSE(fillLoop(loop, 0.01, &why).has_value());
  EXPECT_FALSE(why.empty());
}

}  // namespace
}  // namespace s2p
