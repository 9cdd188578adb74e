#include "core/colour.h"

#include <gtest/gtest.h>

#include <random>

#include "core/error.h"

namespace s2p {
namespace {

void expectNear(const Eigen::Vector3d& got, const Eigen::Vector3d& want, double tol) {
  EXPECT_LE((got - want).cwiseAbs().maxCoeff(), tol)
      << "got " << got.transpose() << ", want " << want.transpose();
}

TEST(Colour, SrgbTransferFunctionReferenceValues) {
  EXPECT_DOUBLE_EQ(srgbToLinear(0.0), 0.0);
  EXPECT_NEAR(srgbToLinear(1.0), 1.0, 1e-15);
  EXPECT_NEAR(srgbToLinear(0.5), 0.214041140, 1e-9);     // ((0.555/1.055)^2.4)
  EXPECT_NEAR(srgbToLinear(0.02), 0.02 / 12.92, 1e-15);  // linear toe
  EXPECT_NEAR(linearToSrgb(0.18), 0.461356129, 1e-9);    // 18 % grey
}

TEST(Colour, D65WhiteAndPrimariesMatchPublishedMatrix) {
  // IEC 61966-2-1: the matrix's row sums are D65 white (x, y) = (0.3127, 0.3290), i.e.
  // (0.9505, 1, 1.0891); its columns are the primaries.
  expectNear(whitePointD65(), {0.95046, 1.0, 1.08906}, 1e-5);
  expectNear(linearRgbToXyz(Eigen::Vector3d(1, 0, 0)), {0.4124, 0.2126, 0.0193}, 1e-4);
  expectNear(linearRgbToXyz(Eigen::Vector3d(0, 1, 0)), {0.3576, 0.7152, 0.1192}, 1e-4);
  expectNear(linearRgbToXyz(Eigen::Vector3d(0, 0, 1)), {0.1805, 0.0722, 0.9505}, 1e-4);
}

TEST(Colour, SrgbToLabReferenceValues) {
  expectNear(srgbToLab(Eigen::Vector3d(1, 1, 1)), {100, 0, 0}, 1e-9);
  expectNear(srgbToLab(Eigen::Vector3d(0, 0, 0)), {0, 0, 0}, 1e-12);
  expectNear(srgbToLab(Eigen::Vector3d(1, 0, 0)), {53.2408, 80.0925, 67.2032}, 0.01);
  expectNear(srgbToLab(Eigen::Vector3d(0, 1, 0)), {87.7347, -86.1827, 83.1793}, 0.01);
  expectNear(srgbToLab(Eigen::Vector3d(0, 0, 1)), {32.2970, 79.1875, -107.8602}, 0.01);
  // Greys are neutral; sRGB 0.5 has L* = 53.389.
  const Eigen::Vector3d grey = srgbToLab(Eigen::Vector3d(0.5, 0.5, 0.5));
  EXPECT_NEAR(grey.x(), 53.389, 0.01);
  EXPECT_NEAR(grey.y(), 0.0, 1e-9);
  EXPECT_NEAR(grey.z(), 0.0, 1e-9);
}

TEST(Colour, RoundTripsToMachinePrecision) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0), dark(0.0, 0.05);
  for (int i = 0; i < 2000; ++i) {
    // Half the samples in the dark range exercise the linear toes of sRGB and L*.
    const Eigen::Vector3d srgb = i % 2 ? Eigen::Vector3d(unit(rng), unit(rng), unit(rng))
                                       : Eigen::Vector3d(dark(rng), dark(rng), dark(rng));
    expectNear(linearToSrgb(srgbToLinear(srgb)), srgb, 1e-9);
    expectNear(labToSrgb(srgbToLab(srgb)), srgb, 1e-9);
    const Eigen::Vector3d xyz = linearRgbToXyz(srgbToLinear(srgb));
    expectNear(xyzToLinearRgb(xyz), srgbToLinear(srgb), 1e-12);
    expectNear(labToXyz(xyzToLab(xyz)), xyz, 1e-12);
  }
}

TEST(Colour, RowWiseVersionsMatchSingleColours) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::MatrixX3d srgb(50, 3);
  for (int i = 0; i < srgb.rows(); ++i) srgb.row(i) << unit(rng), unit(rng), unit(rng);
  const Eigen::MatrixX3d lab = srgbToLab(srgb);
  const Eigen::MatrixX3d back = labToSrgb(lab);
  const Eigen::MatrixX3d lin = srgbToLinear(srgb);
  for (int i = 0; i < srgb.rows(); ++i) {
    const Eigen::Vector3d c = srgb.row(i).transpose();
    expectNear(lab.row(i).transpose(), srgbToLab(c), 1e-12);
    expectNear(lin.row(i).transpose(), srgbToLinear(c), 0.0);
    expectNear(back.row(i).transpose(), c, 1e-9);
  }
  EXPECT_EQ(srgbToLab(Eigen::MatrixX3d(0, 3)).rows(), 0);
}

TEST(Colour, DeltaE76IsEuclidean) {
  EXPECT_DOUBLE_EQ(deltaE76(Eigen::Vector3d(50, 3, 4), Eigen::Vector3d(50, 0, 0)), 5.0);
  Eigen::MatrixX3d a(2, 3), b(2, 3);
  a << 50, 3, 4, 10, 0, 0;
  b << 50, 0, 0, 22, 0, 0;
  const Eigen::VectorXd d = deltaE76(a, b);
  EXPECT_DOUBLE_EQ(d(0), 5.0);
  EXPECT_DOUBLE_EQ(d(1), 12.0);
  EXPECT_THROW(deltaE76(a, Eigen::MatrixX3d(3, 3)), InputError);
  EXPECT_THROW(deltaE2000(a, Eigen::MatrixX3d(1, 3)), InputError);
}

// Table 1 of Sharma, Wu & Dalal 2005: L1 a1 b1 L2 a2 b2 ΔE00.
constexpr double kSharma[34][7] = {
    {50.0000, 2.6772, -79.7751, 50.0000, 0.0000, -82.7485, 2.0425},
    {50.0000, 3.1571, -77.2803, 50.0000, 0.0000, -82.7485, 2.8615},
    {50.0000, 2.8361, -74.0200, 50.0000, 0.0000, -82.7485, 3.4412},
    {50.0000, -1.3802, -84.2814, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, -1.1848, -84.8006, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, -0.9009, -85.5211, 50.0000, 0.0000, -82.7485, 1.0000},
    {50.0000, 0.0000, 0.0000, 50.0000, -1.0000, 2.0000, 2.3669},
    {50.0000, -1.0000, 2.0000, 50.0000, 0.0000, 0.0000, 2.3669},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0009, 7.1792},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0010, 7.1792},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0011, 7.2195},
    {50.0000, 2.4900, -0.0010, 50.0000, -2.4900, 0.0012, 7.2195},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0009, -2.4900, 4.8045},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0010, -2.4900, 4.8045},
    {50.0000, -0.0010, 2.4900, 50.0000, 0.0011, -2.4900, 4.7461},
    {50.0000, 2.5000, 0.0000, 50.0000, 0.0000, -2.5000, 4.3065},
    {50.0000, 2.5000, 0.0000, 73.0000, 25.0000, -18.0000, 27.1492},
    {50.0000, 2.5000, 0.0000, 61.0000, -5.0000, 29.0000, 22.8977},
    {50.0000, 2.5000, 0.0000, 56.0000, -27.0000, -3.0000, 31.9030},
    {50.0000, 2.5000, 0.0000, 58.0000, 24.0000, 15.0000, 19.4535},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.1736, 0.5854, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.2972, 0.0000, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 1.8634, 0.5757, 1.0000},
    {50.0000, 2.5000, 0.0000, 50.0000, 3.2592, 0.3350, 1.0000},
    {60.2574, -34.0099, 36.2677, 60.4626, -34.1751, 39.4387, 1.2644},
    {63.0109, -31.0961, -5.8663, 62.8187, -29.7946, -4.0864, 1.2630},
    {61.2901, 3.7196, -5.3901, 61.4292, 2.2480, -4.9620, 1.8731},
    {35.0831, -44.1164, 3.7933, 35.0232, -40.0716, 1.5901, 1.8645},
    {22.7233, 20.0904, -46.6940, 23.0331, 14.9730, -42.5619, 2.0373},
    {36.4612, 47.8580, 18.3852, 36.2715, 50.5065, 21.2231, 1.4146},
    {90.8027, -2.0831, 1.4410, 91.1528, -1.6435, 0.0447, 1.4441},
    {90.9257, -0.5406, -0.9208, 88.6381, -0.8985, -0.7239, 1.5381},
    {6.7747, -0.2908, -2.4247, 5.8714, -0.0985, -2.2286, 0.6377},
    {2.0776, 0.0795, -1.1350, 0.9033, -0.0636, -0.5514, 0.9082},
};

TEST(Colour, DeltaE2000MatchesSharmaTable) {
  Eigen::MatrixX3d lab1(34, 3), lab2(34, 3);
  for (int i = 0; i < 34; ++i) {
    const Eigen::Vector3d a(kSharma[i][0], kSharma[i][1], kSharma[i][2]);
    const Eigen::Vector3d b(kSharma[i][3], kSharma[i][4], kSharma[i][5]);
    // The table rounds to 4 decimals, hence 5e-5 plus rounding of the inputs.
    EXPECT_NEAR(deltaE2000(a, b), kSharma[i][6], 1e-4) << "pair " << i + 1;
    EXPECT_NEAR(deltaE2000(b, a), deltaE2000(a, b), 1e-12) << "pair " << i + 1;
    lab1.row(i) = a.transpose();
    lab2.row(i) = b.transpose();
  }
  const Eigen::VectorXd d = deltaE2000(lab1, lab2);
  for (int i = 0; i < 34; ++i) EXPECT_NEAR(d(i), kSharma[i][6], 1e-4);
  EXPECT_DOUBLE_EQ(deltaE2000(Eigen::Vector3d(40, 10, -3), Eigen::Vector3d(40, 10, -3)), 0.0);
}

}  // namespace
}  // namespace s2p
