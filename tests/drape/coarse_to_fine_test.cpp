#include "drape/coarse_to_fine.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "core/error.h"
#include "drape/cloth_shapes.h"

namespace s2p {
namespace {

using Eigen::Vector3d;

// A w × h rectangle gridded at about `edge`, flat at z = 0.
ClothPanel rectangle(double w, double h, double edge) {
  const int nx = static_cast<int>(std::lround(w / edge)),
            ny = static_cast<int>(std::lround(h / edge));
  return makeGridPanel("rect", nx, ny, w, h, Vector3d::Zero(), Vector3d::UnitX(), Vector3d::UnitY(),
                       false)
      .panel;
}

// Carrying interpolates linearly in the coarse triangles, so a coarse drape that is an affine
// map of the flat pattern is carried exactly, whatever the two triangulations (a carrier that
// took the nearest coarse vertex would be off by up to half a coarse edge).
TEST(CoarseToFine, AnAffineCoarseDrapeIsCarriedExactly) {
  DrapeInput coarse, fine;
  coarse.panels.push_back(rectangle(0.4, 0.3, 0.05));
  fine.panels.push_back(rectangle(0.4, 0.3, 0.0125));
  Eigen::Matrix<double, 3, 2> A;
  A << 0.8, 0.3, -0.2, 0.9, 0.5, -0.4;
  const Vector3d b(0.1, 1.2, -0.3);
  auto affine = [&](const Eigen::MatrixX2d& P) {
    Eigen::MatrixX3d out = (P * A.transpose()).rowwise() + b.transpose();
    return out;
  };
  double outside = -1;
  const std::vector<Eigen::MatrixX3d> carried =
      carryDrape(coarse, {affine(coarse.panels[0].rest2d)}, fine, &outside);
  ASSERT_EQ(carried.size(), 1u);
  EXPECT_LT((carried[0] - affine(fine.panels[0].rest2d)).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(outside, 1e-12);  // the fine grid lies inside the coarse rectangle
}

TEST(CoarseToFine, PanelsThatDoNotCorrespondAreAnInputError) {
  DrapeInput coarse, fine;
  coarse.panels.push_back(rectangle(0.4, 0.3, 0.05));
  fine.panels.push_back(rectangle(0.4, 0.3, 0.0125));
  fine.panels.push_back(rectangle(0.4, 0.3, 0.0125));
  EXPECT_THROW(carryDrape(coarse, {coarse.panels[0].start}, fine), InputError);
  fine.panels.pop_back();
  EXPECT_THROW(carryDrape(coarse, {Eigen::MatrixX3d(2, 3)}, fine), InputError);
}

// The tube of drape_test's known answer, sewn at 30 mm and carried onto 10 mm: the fine mesh
// starts sewn (its stitched partners land on the welded coarse seam), needs almost no sewing,
// and ends a tube of the rectangles' width, as the tube sewn at 10 mm alone does.
TEST(CoarseToFine, ATubeSewnCoarseAndCarriedOntoTheFineMeshKeepsItsCircumference_Slow) {
  const double width = 0.3, height = 0.2;
  const DrapeInput fine = makeTubeGarment(width, height, 0.01, 0.12, 0.06);
  const DrapeInput coarse = makeTubeGarment(width, height, 0.03, 0.12, 0.06);
  DrapeOptions o;
  o.gravity.setZero();
  const CoarseToFineDrape r = runDrapeCoarseToFine(fine, coarse, o);
  ASSERT_EQ(r.coarse.status, DrapeStatus::Settled) << r.coarse.failure;
  ASSERT_TRUE(r.carried);
  EXPECT_LT(r.carriedGap, 1e-3);
  const DrapeResult& f = r.fine;
  ASSERT_NE(f.status, DrapeStatus::Failed) << f.failure;
  EXPECT_TRUE(f.seamsClosed);
  EXPECT_EQ(f.maxStitchGap, 0.0);
  EXPECT_LE(f.sewSteps, 2);
  // Circumference of every row of the fine front and back panels (nx cells across each).
  const int nx = static_cast<int>(std::lround(width / 0.01));
  double worst = 0;
  for (int j = 0; j <= 20; ++j) {
    const int row = j * (nx + 1);
    double length = 0;
    for (int i = 0; i < nx; ++i)
      length += (f.panels[0].row(row + i + 1) - f.panels[0].row(row + i)).norm() +
                (f.panels[1].row(row + i + 1) - f.panels[1].row(row + i)).norm();
    worst = std::max(worst, std::abs(length / (2 * width) - 1));
  }
  EXPECT_LT(worst, 0.01);
  EXPECT_EQ(f.bodyPenetrations, 0);
  EXPECT_EQ(f.selfIntersections, 0);
  std::cout << "tube 30 → 10 mm: coarse " << r.coarse.sewSteps << " + " << r.coarse.drapeSteps
            << " steps (" << r.coarse.seconds << " s), fine " << f.sewSteps << " + " << f.drapeSteps
            << " steps (" << f.seconds << " s), circumference error " << 100 * worst << " %\n";
}

}  // namespace
}  // namespace s2p
