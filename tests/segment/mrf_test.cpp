#include "segment/mrf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/error.h"
#include "core/shapes.h"

namespace s2p {
namespace {

// Open cylinder around the y axis, radius 0.1 m, y in [−0.5, 0.5]: 82 rings of 64 vertices
// (ring spacing 1/81 m ≈ 1.2 cm, 1 cm around: about a 50k-vertex person's spacing; no ring at
// y = 0, so every vertex has a side).
TriMesh centredCylinder() {
  TriMesh m = makeCylinder(81, 64, 0.1, 1.0);
  m.V.col(1).array() -= 0.5;
  return m;
}
constexpr double kRing = 1.0 / 81;

// Region points at the vertices with y in [lo, hi], leaving out those marked in `skip`.
std::vector<SurfacePoint> pointsBetween(const TriMesh& m, double lo, double hi,
                                        const std::vector<bool>& skip = {}) {
  std::vector<SurfacePoint> p;
  for (int v = 0; v < m.numVertices(); ++v)
    if (m.V(v, 1) >= lo && m.V(v, 1) <= hi && (skip.empty() || !skip[v]))
      p.push_back(SurfacePoint::atVertex(m.F, v));
  return p;
}

// Per-vertex sRGB from a band index, with a little seeded Gaussian noise.
Eigen::MatrixX3d paint(const Eigen::VectorXi& band, const std::vector<Eigen::RowVector3d>& colours,
                       unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0, 0.01);
  Eigen::MatrixX3d rgb(band.size(), 3);
  for (int v = 0; v < band.size(); ++v)
    rgb.row(v) = colours[band[v]] + Eigen::RowVector3d(noise(rng), noise(rng), noise(rng));
  return rgb;
}

const Eigen::RowVector3d kRed(0.8, 0.1, 0.1), kBlue(0.1, 0.2, 0.8), kGreen(0.1, 0.7, 0.2);

// Flips `fraction` of the vertices to another band (seeded); returns which were flipped.
std::vector<bool> saltAndPepper(Eigen::VectorXi& band, int bands, double fraction, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<bool> flipped(band.size(), false);
  for (int v = 0; v < band.size(); ++v)
    if (u(rng) < fraction) {
      band[v] = (band[v] + 1 + static_cast<int>(u(rng) * (bands - 1))) % bands;
      flipped[v] = true;
    }
  return flipped;
}

double fractionEqual(const Eigen::VectorXi& a, const Eigen::VectorXi& b) {
  return static_cast<double>((a.array() == b.array()).count()) / static_cast<double>(a.size());
}

// Brute-force minimum of the Potts energy over all K^#V labellings.
double bruteForceMinimum(const Eigen::MatrixXd& unary, const Eigen::MatrixX2i& edges,
                         const Eigen::VectorXd& w) {
  const int n = static_cast<int>(unary.rows()), k = static_cast<int>(unary.cols());
  Eigen::VectorXi f = Eigen::VectorXi::Zero(n);
  double best = std::numeric_limits<double>::infinity();
  while (true) {
    double e = 0;
    for (int v = 0; v < n; ++v) e += unary(v, f[v]);
    for (int j = 0; j < edges.rows(); ++j)
      if (f[edges(j, 0)] != f[edges(j, 1)]) e += w[j];
    best = std::min(best, e);
    int i = 0;
    while (i < n && ++f[i] == k) f[i++] = 0;
    if (i == n) return best;
  }
}

// === Alpha-expansion on its own

TEST(Potts, TwoLabelsReachTheBruteForceMinimum) {
  // 4×3 grid (12 vertices, 4096 labellings), random unaries and weights: one expansion is a
  // global minimum for two labels.
  const TriMesh grid = makeGrid(3, 2);
  Eigen::MatrixX2i edges(0, 2);
  for (int f = 0; f < grid.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = std::min(grid.F(f, k), grid.F(f, (k + 1) % 3));
      const int b = std::max(grid.F(f, k), grid.F(f, (k + 1) % 3));
      bool dup = false;
      for (int j = 0; j < edges.rows(); ++j) dup = dup || (edges(j, 0) == a && edges(j, 1) == b);
      if (!dup) {
        edges.conservativeResize(edges.rows() + 1, 2);
        edges.row(edges.rows() - 1) << a, b;
      }
    }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::MatrixXd unary(grid.numVertices(), 2);
    for (int i = 0; i < unary.size(); ++i) unary.data()[i] = 3 * u(rng);
    Eigen::VectorXd w(edges.rows());
    for (int j = 0; j < w.size(); ++j) w[j] = 1.5 * u(rng);
    const PottsResult r = minimisePotts(unary, edges, w);
    EXPECT_NEAR(r.energy, bruteForceMinimum(unary, edges, w), 1e-9) << "trial " << trial;
  }
}

TEST(Potts, ThreeLabelsWithinTheExpansionBoundAndMonotone) {
  // A 3×2 grid graph (729 labellings) with three labels: the energy is at least
  // the optimum, at most twice it (BVZ Thm. 6.1), and never increases across sweeps.
  const TriMesh grid = makeGrid(2, 1);
  const Eigen::MatrixX2i edges =
      (Eigen::MatrixX2i(7, 2) << 0, 1, 1, 2, 3, 4, 4, 5, 0, 3, 1, 4, 2, 5).finished();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  int optimal = 0;
  for (int trial = 0; trial < 30; ++trial) {
    Eigen::MatrixXd unary(grid.numVertices(), 3);
    for (int i = 0; i < unary.size(); ++i) unary.data()[i] = 3 * u(rng);
    Eigen::VectorXd w(edges.rows());
    for (int j = 0; j < w.size(); ++j) w[j] = 2 * u(rng);
    const PottsResult r = minimisePotts(unary, edges, w, 10);
    const double best = bruteForceMinimum(unary, edges, w);
    EXPECT_GE(r.energy, best - 1e-9);
    EXPECT_LE(r.energy, 2 * best + 1e-9);
    optimal += std::abs(r.energy - best) < 1e-9;
    for (size_t s = 1; s < r.sweepEnergies.size(); ++s)
      EXPECT_LE(r.sweepEnergies[s], r.sweepEnergies[s - 1]);
  }
  EXPECT_GE(optimal, 25);  // expansion moves are near-optimal in practice
}

TEST(Potts, BadInputThrows) {
  const Eigen::MatrixXd unary = Eigen::MatrixXd::Zero(3, 2);
  const Eigen::MatrixX2i edges = (Eigen::MatrixX2i(1, 2) << 0, 3).finished();
  EXPECT_THROW(minimisePotts(unary, edges, Eigen::VectorXd::Ones(1)), InputError);
  const Eigen::MatrixX2i ok = (Eigen::MatrixX2i(1, 2) << 0, 2).finished();
  EXPECT_THROW(minimisePotts(unary, ok, Eigen::VectorXd::Ones(2)), InputError);
  EXPECT_THROW(minimisePotts(unary, ok, -Eigen::VectorXd::Ones(1)), InputError);
  Eigen::MatrixXd nan = unary;
  nan(1, 1) = std::nan("");
  EXPECT_THROW(minimisePotts(nan, ok, Eigen::VectorXd::Ones(1)), InputError);
}

// === The segmentation

TEST(Mrf, TwoColourCylinderIsLabelledByColourSide) {
  const TriMesh cyl = centredCylinder();
  Eigen::VectorXi band = (cyl.V.col(1).array() > 0).cast<int>();  // 1 above, 0 below
  const Eigen::MatrixX3d rgb = paint(band, {kBlue, kRed}, 1);
  const std::vector<MrfRegion> regions = {{.label = 7, .points = pointsBetween(cyl, 0.2, 0.5)},
                                          {.label = 3, .points = pointsBetween(cyl, -0.5, -0.2)}};
  const MrfResult r = mrfSegmentation(cyl, rgb, regions);
  ASSERT_EQ(r.vertexLabel.size(), cyl.numVertices());
  ASSERT_EQ(r.models.size(), 2u);
  for (int v = 0; v < cyl.numVertices(); ++v)
    EXPECT_EQ(r.vertexLabel[v], cyl.V(v, 1) > 0 ? 7 : 3) << "vertex " << v << " y " << cyl.V(v, 1);
  // The change sits between the two rings next to y = 0: every edge with differing labels
  // spans y = 0 and is at most one ring long in y.
  for (int f = 0; f < cyl.numFaces(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = cyl.F(f, k), b = cyl.F(f, (k + 1) % 3);
      if (r.vertexLabel[a] != r.vertexLabel[b]) {
        EXPECT_LT(std::abs(cyl.V(a, 1)), kRing);
        EXPECT_LT(std::abs(cyl.V(b, 1)), kRing);
      }
    }
  EXPECT_DOUBLE_EQ(r.energy, r.sweepEnergies.back());
}

TEST(Mrf, SmoothnessRelabelsSaltAndPepperNoise) {
  const TriMesh cyl = centredCylinder();
  const Eigen::VectorXi truth = (cyl.V.col(1).array() > 0).cast<int>();
  Eigen::VectorXi band = truth;
  const std::vector<bool> flipped = saltAndPepper(band, 2, 0.05, 5);
  const Eigen::MatrixX3d rgb = paint(band, {kBlue, kRed}, 2);
  // Region points on clean vertices: a region's colour model describes its garment, the noise
  // is what the labelling has to cope with.
  const std::vector<MrfRegion> regions = {
      {.label = 0, .points = pointsBetween(cyl, -0.5, -0.2, flipped)},
      {.label = 1, .points = pointsBetween(cyl, 0.2, 0.5, flipped)}};
  // Colour and smoothness only: no prior, no contrast sensitivity (which would make the noise's
  // colour edges cheap to cut on purpose).
  MrfOptions o{.contrast = 0, .priorWeight = 0};
  const MrfResult smooth = mrfSegmentation(cyl, rgb, regions, o);
  EXPECT_GE(fractionEqual(smooth.vertexLabel, truth), 0.99);

  o.smoothness = 0;
  const MrfResult raw = mrfSegmentation(cyl, rgb, regions, o);
  int flippedCount = 0, flippedWrong = 0;
  for (int v = 0; v < cyl.numVertices(); ++v)
    if (flipped[v]) {
      ++flippedCount;
      flippedWrong += raw.vertexLabel[v] != truth[v];
    }
  ASSERT_GT(flippedCount, 40);
  EXPECT_GE(flippedWrong, 0.9 * flippedCount);  // λ = 0 labels them by their (wrong) colour
  EXPECT_LE(fractionEqual(raw.vertexLabel, truth), 0.97);
  EXPECT_LT(smooth.energy, smooth.sweepEnergies.front());
}

TEST(Mrf, ThreeBandsAreAllFoundAndEnergyNeverIncreases) {
  const TriMesh cyl = centredCylinder();
  Eigen::VectorXi truth(cyl.numVertices());
  for (int v = 0; v < cyl.numVertices(); ++v) {
    const double y = cyl.V(v, 1);
    truth[v] = y < -1.0 / 6 ? 0 : (y < 1.0 / 6 ? 1 : 2);
  }
  Eigen::VectorXi band = truth;
  const std::vector<bool> flipped = saltAndPepper(band, 3, 0.05, 9);
  const Eigen::MatrixX3d rgb = paint(band, {kBlue, kGreen, kRed}, 3);
  const std::vector<MrfRegion> regions = {
      {.label = 10, .points = pointsBetween(cyl, -0.5, -0.3, flipped)},
      {.label = 20, .points = pointsBetween(cyl, -0.08, 0.08, flipped)},
      {.label = 30, .points = pointsBetween(cyl, 0.3, 0.5, flipped)}};
  const MrfResult r = mrfSegmentation(cyl, rgb, regions, {.contrast = 0, .priorWeight = 0});
  const int codes[3] = {10, 20, 30};
  int correct = 0;
  std::vector<int> count(3, 0);
  for (int v = 0; v < cyl.numVertices(); ++v) {
    correct += r.vertexLabel[v] == codes[truth[v]];
    if (!flipped[v]) {
      EXPECT_EQ(r.vertexLabel[v], codes[truth[v]]) << "clean vertex " << v;
    }
    for (int l = 0; l < 3; ++l) count[l] += r.vertexLabel[v] == codes[l];
  }
  // Isolated specks are relabelled; a few adjacent pairs of flipped vertices next to a band
  // edge are cheaper to keep (λ = 1), so ≥ 98 % rather than the 99 % of the two-colour case.
  EXPECT_GE(correct, 0.98 * cyl.numVertices());
  for (int l = 0; l < 3; ++l) EXPECT_GT(count[l], cyl.numVertices() / 4) << "label " << codes[l];
  ASSERT_GE(r.sweeps, 1);
  ASSERT_EQ(r.sweepEnergies.size(), static_cast<size_t>(r.sweeps) + 1);
  for (size_t s = 1; s < r.sweepEnergies.size(); ++s)
    EXPECT_LE(r.sweepEnergies[s], r.sweepEnergies[s - 1]) << "sweep " << s;
  EXPECT_LT(r.sweepEnergies.back(), r.sweepEnergies.front());
}

TEST(Mrf, SameColourRegionsFollowThePrior) {
  const TriMesh cyl = centredCylinder();
  const Eigen::MatrixX3d rgb =
      paint(Eigen::VectorXi::Zero(cyl.numVertices()), {Eigen::RowVector3d(0.5, 0.5, 0.5)}, 4);
  const std::vector<MrfRegion> regions = {{.label = 1, .points = pointsBetween(cyl, 0.3, 0.5)},
                                          {.label = 2, .points = pointsBetween(cyl, -0.5, -0.3)}};
  const MrfResult r = mrfSegmentation(cyl, rgb, regions);
  for (int v = 0; v < cyl.numVertices(); ++v) {
    const double y = cyl.V(v, 1);
    if (std::abs(y) > 1.5 * kRing) {
      EXPECT_EQ(r.vertexLabel[v], y > 0 ? 1 : 2) << "y " << y;
    }
  }
  // Without the prior the same colour gives no reason to split at y = 0.
  const MrfResult noPrior = mrfSegmentation(cyl, rgb, regions, {.priorWeight = 0});
  EXPECT_LT(fractionEqual(noPrior.vertexLabel, r.vertexLabel), 0.9);
}

TEST(Mrf, BadInputThrowsInputError) {
  const TriMesh cyl = centredCylinder();
  const Eigen::MatrixX3d rgb = paint((cyl.V.col(1).array() > 0).cast<int>(), {kBlue, kRed}, 1);
  const std::vector<SurfacePoint> top = pointsBetween(cyl, 0.2, 0.5);
  const std::vector<SurfacePoint> bottom = pointsBetween(cyl, -0.5, -0.2);
  const std::vector<MrfRegion> good = {{.label = 1, .points = top}, {.label = 2, .points = bottom}};

  EXPECT_THROW(mrfSegmentation(cyl, rgb, {{.label = 1, .points = top}, {.label = 2}}), InputError);
  EXPECT_THROW(mrfSegmentation(cyl, rgb.topRows(10), good), InputError);
  Eigen::MatrixX3d nan = rgb;
  nan(17, 1) = std::nan("");
  EXPECT_THROW(mrfSegmentation(cyl, nan, good), InputError);
  EXPECT_THROW(mrfSegmentation(cyl, rgb, {good[0]}), InputError);
  EXPECT_THROW(mrfSegmentation(cyl, rgb, {good[0], {.label = 1, .points = bottom}}), InputError);
  std::vector<MrfRegion> off = good;
  off[1].points.push_back({.face = cyl.numFaces(), .bary = Eigen::Vector3d(1, 0, 0)});
  EXPECT_THROW(mrfSegmentation(cyl, rgb, off), InputError);
  EXPECT_THROW(mrfSegmentation(cyl, rgb, good, {.priorLength = 0}), InputError);
  EXPECT_THROW(mrfSegmentation(cyl, rgb, good, {.smoothness = -1}), InputError);
  EXPECT_THROW(mrfSegmentation(TriMesh{}, Eigen::MatrixX3d(0, 3), good), InputError);
}

TEST(Mrf, ResolutionDoesNotChangeWhichStripesSurvive) {
  // Colour A above y = 0.1 m with two stripes of colour B: 0.5 cm and 3 cm wide. A stripe is
  // worth keeping when its data gain (∝ width / s²) beats its two boundaries (∝ λ / s): the
  // narrow one goes, the wide one stays, at 0.5 cm and at 0.25 cm vertex spacing alike (with
  // weights relative to the mean edge length instead, the narrow stripe would survive at the
  // finer spacing). Colour, prior and contrast are kept out to isolate that balance.
  for (const double h : {0.005, 0.0025}) {
    const TriMesh cyl = makeCylinder(static_cast<int>(std::lround(0.4 / h)),
                                     static_cast<int>(std::lround(2 * M_PI * 0.04 / h)), 0.04, 0.4);
    Eigen::VectorXi band(cyl.numVertices());
    std::vector<bool> narrow(cyl.numVertices()), wide(cyl.numVertices());
    for (int v = 0; v < cyl.numVertices(); ++v) {
      const double y = cyl.V(v, 1);
      narrow[v] = y > 0.149 && y < 0.1535;
      wide[v] = y > 0.199 && y < 0.2285;
      band[v] = y < 0.1 || narrow[v] || wide[v] ? 1 : 0;
    }
    const Eigen::MatrixX3d rgb = paint(band, {kRed, kBlue}, 6);
    const std::vector<MrfRegion> regions = {{.label = 0, .points = pointsBetween(cyl, 0.3, 0.4)},
                                            {.label = 1, .points = pointsBetween(cyl, 0, 0.08)}};
    MrfOptions o{.contrast = 0, .priorWeight = 0};
    o.colour.displacementSmoothing = 0;
    const MrfResult r = mrfSegmentation(cyl, rgb, regions, o);
    int narrowCount = 0, wideCount = 0;
    for (int v = 0; v < cyl.numVertices(); ++v) {
      if (narrow[v]) {
        ++narrowCount;
        EXPECT_EQ(r.vertexLabel[v], 0) << "narrow stripe, spacing " << h << ", y " << cyl.V(v, 1);
      }
      if (wide[v]) {
        ++wideCount;
        EXPECT_EQ(r.vertexLabel[v], 1) << "wide stripe, spacing " << h << ", y " << cyl.V(v, 1);
      }
    }
    EXPECT_EQ(narrowCount, std::lround(0.005 / h) * std::lround(2 * M_PI * 0.04 / h));
    EXPECT_EQ(wideCount, std::lround(0.03 / h) * std::lround(2 * M_PI * 0.04 / h));
  }
}

// === Face labels

// === The geometric cues (issue 18)

// The known answer for the baseline: a skin-coloured sleeve with 1 cm of ease over a
// bare forearm of the same colour. Colour alone splits where the prior does (y ≈ −0.025); the
// offset from the body puts the split at the sleeve's hem (y = −0.2).
TEST(Mrf, SkinColouredSleeveIsFoundByItsOffset) {
  const TriMesh cyl = centredCylinder();
  const Eigen::RowVector3d skin(0.85, 0.65, 0.55);
  const Eigen::MatrixX3d rgb = paint(Eigen::VectorXi::Zero(cyl.numVertices()), {skin}, 5);
  std::mt19937 rng(6);
  std::normal_distribution<double> noise(0, 0.0005);  // m, the scanner's and the fit's
  Eigen::VectorXd offset(cyl.numVertices());
  for (int v = 0; v < cyl.numVertices(); ++v)
    offset[v] = (cyl.V(v, 1) > -0.2 ? 0.01 : 0.0) + noise(rng);
  const std::vector<MrfRegion> regions = {
      {.label = 0, .points = pointsBetween(cyl, -0.5, -0.35), .bareSkin = true},
      {.label = 1, .points = pointsBetween(cyl, 0.3, 0.5)}};
  const MrfResult r = mrfSegmentation(cyl, rgb, regions, {}, offset);
  const MrfResult blind = mrfSegmentation(cyl, rgb, regions);
  int wrong = 0, blindWrong = 0;
  for (int v = 0; v < cyl.numVertices(); ++v) {
    const double y = cyl.V(v, 1);
    if (std::abs(y + 0.2) < kRing) continue;
    wrong += r.vertexLabel[v] != (y > -0.2 ? 1 : 0);
    blindWrong += blind.vertexLabel[v] != (y > -0.2 ? 1 : 0);
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GT(blindWrong, 10 * 64);  // the 17 cm between the hem and the prior's split
  EXPECT_NEAR(r.skinOffset.mean, 0, 0.0005);
  EXPECT_NEAR(r.clothedOffset.mean, 0.01, 0.0005);
  EXPECT_DOUBLE_EQ(r.skinOffset.sigma, MrfOptions{}.offsetNoise);  // the spread's floor
}

// Where colour tells skin from the garment, a fit error does not override it: a hand the fit
// missed by a centimetre stays skin.
TEST(Mrf, ColourStillDecidesWhereItCanTell) {
  const TriMesh cyl = centredCylinder();
  Eigen::VectorXi band(cyl.numVertices());
  for (int v = 0; v < cyl.numVertices(); ++v) band[v] = cyl.V(v, 1) > 0 ? 1 : 0;
  const Eigen::MatrixX3d rgb = paint(band, {Eigen::RowVector3d(0.85, 0.65, 0.55), kBlue}, 7);
  Eigen::VectorXd offset(cyl.numVertices());
  for (int v = 0; v < cyl.numVertices(); ++v) {
    const double y = cyl.V(v, 1);
    offset[v] = y > 0 ? 0.01 : (y < -0.3 ? 0.01 : 0.0);  // the skin's end off the body too
  }
  const std::vector<MrfRegion> regions = {
      {.label = 0, .points = pointsBetween(cyl, -0.3, -0.1), .bareSkin = true},
      {.label = 1, .points = pointsBetween(cyl, 0.1, 0.5)}};
  const MrfResult r = mrfSegmentation(cyl, rgb, regions, {}, offset);
  for (int v = 0; v < cyl.numVertices(); ++v)
    if (std::abs(cyl.V(v, 1)) > 1.5 * kRing) {
      EXPECT_EQ(r.vertexLabel[v], band[v]) << "y " << cyl.V(v, 1);
    }
}

// Two garments of one colour over a bare ankle of another, a 1 cm hem step between them 3.7 cm
// below where the prior splits them (y = 0): colour alone splits at the prior; the riser's cheap
// edges move the split onto the step.
TEST(Mrf, EqualColoursSplitAtTheHemRiser) {
  const TriMesh cyl = centredCylinder();
  constexpr double kHem = -0.037;  // between two rings
  Eigen::VectorXi band(cyl.numVertices());
  Eigen::VectorXd offset(cyl.numVertices());
  for (int v = 0; v < cyl.numVertices(); ++v) {
    const double y = cyl.V(v, 1);
    band[v] = y < -0.42 ? 1 : 0;
    offset[v] = y < -0.42 ? 0.0 : (y > kHem ? 0.02 : 0.01);
  }
  const Eigen::MatrixX3d rgb = paint(band, {kGreen, Eigen::RowVector3d(0.85, 0.65, 0.55)}, 8);
  const std::vector<MrfRegion> regions = {
      {.label = 0, .points = pointsBetween(cyl, -0.5, -0.45), .bareSkin = true},
      {.label = 1, .points = pointsBetween(cyl, 0.3, 0.5)},
      {.label = 2, .points = pointsBetween(cyl, -0.4, -0.3)}};
  const MrfResult r = mrfSegmentation(cyl, rgb, regions, {}, offset);
  const MrfResult blind = mrfSegmentation(cyl, rgb, regions);
  int wrong = 0, blindWrong = 0;
  for (int v = 0; v < cyl.numVertices(); ++v) {
    const double y = cyl.V(v, 1);
    if (y < -0.4 || y > 0.3) continue;
    wrong += r.vertexLabel[v] != (y > kHem ? 1 : 2);
    blindWrong += blind.vertexLabel[v] != (y > kHem ? 1 : 2);
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_GE(blindWrong, 3 * 64);  // the three rings between the step and y = 0
}

TEST(Mrf, BadOffsetsThrowInputError) {
  const TriMesh cyl = centredCylinder();
  const Eigen::MatrixX3d rgb = paint(Eigen::VectorXi::Zero(cyl.numVertices()), {kRed}, 1);
  const std::vector<MrfRegion> regions = {
      {.label = 0, .points = pointsBetween(cyl, -0.5, -0.3), .bareSkin = true},
      {.label = 1, .points = pointsBetween(cyl, 0.3, 0.5)}};
  const Eigen::VectorXd offset = Eigen::VectorXd::Zero(cyl.numVertices());
  EXPECT_NO_THROW(mrfSegmentation(cyl, rgb, regions, {}, offset));
  EXPECT_THROW(mrfSegmentation(cyl, rgb, regions, {}, offset.head(10)), InputError);
  Eigen::VectorXd nan = offset;
  nan[3] = std::nan("");
  EXPECT_THROW(mrfSegmentation(cyl, rgb, regions, {}, nan), InputError);
  std::vector<MrfRegion> noSkin = regions;
  noSkin[0].bareSkin = false;
  EXPECT_THROW(mrfSegmentation(cyl, rgb, noSkin, {}, offset), InputError);
  EXPECT_THROW(mrfSegmentation(cyl, rgb, regions, {.offsetOutliers = 0}, offset), InputError);
  EXPECT_THROW(mrfSegmentation(cyl, rgb, regions, {.riserSlope = -1}, offset), InputError);
}

TEST(Mrf, FaceLabelsTakeTheCornerMajority) {
  TriMesh m;
  m.V.setZero(6, 3);
  m.F.resize(4, 3);
  m.F << 0, 1, 2,  // 5 5 8 → 5
      1, 2, 3,     // 5 8 8 → 8
      3, 4, 5,     // 8 2 9: all differ → vertex 3's label
      5, 3, 4;     // the same face rotated → the same label
  const Eigen::VectorXi vl = (Eigen::VectorXi(6) << 5, 5, 8, 8, 2, 9).finished();
  const Eigen::VectorXi fl = faceLabelsFromVertices(m, vl);
  EXPECT_EQ(fl, (Eigen::VectorXi(4) << 5, 8, 8, 8).finished());
  EXPECT_THROW(faceLabelsFromVertices(m, vl.head(5)), InputError);
}

}  // namespace
}  // namespace s2p
