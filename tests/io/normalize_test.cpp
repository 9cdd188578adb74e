#include "io/normalize.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "io_test_util.h"

namespace s2p {
namespace {

using test::throwsExactly;

Scan scanOf(const TriMesh& mesh) {
  Scan s;
  s.mesh = mesh;
  return s;
}

TEST(NormalizeScan, DetectsUnitsAndScalesToSameHeight) {
  const TriMesh body = makeCylinder(8, 16, 0.2, 1.7);  // 1.7 m tall, +Y
  const std::pair<Units, double> cases[] = {{Units::Metres, 1.0},
                                            {Units::Decimetres, 10.0},
                                            {Units::Centimetres, 100.0},
                                            {Units::Millimetres, 1000.0}};
  for (const auto& [units, factor] : cases) {
    Scan scan = scanOf(body);
    scan.mesh.V *= factor;
    const NormalizeReport r = normalizeScan(scan, {.up = UpAxis::PosY});
    EXPECT_EQ(r.units, units) << toString(units);
    EXPECT_TRUE(r.unitsDetected);
    EXPECT_DOUBLE_EQ(r.scale, 1.0 / factor);
    EXPECT_NEAR(r.heightMetres, 1.7, 1e-12);
    EXPECT_NEAR(scan.mesh.V.col(1).minCoeff(), 0.0, 1e-12);
    EXPECT_NEAR(scan.mesh.V.col(1).maxCoeff(), 1.7, 1e-12);
  }
}

TEST(NormalizeScan, SymmetricShapeIsAmbiguousAndPrefersPositiveAxis) {
  Scan scan = scanOf(makeCylinder(8, 16, 0.2, 1.7));
  const NormalizeReport r = normalizeScan(scan);
  EXPECT_TRUE(r.upDetected);
  EXPECT_TRUE(r.upAmbiguous);
  EXPECT_EQ(r.up, UpAxis::PosY);
  EXPECT_FALSE(r.warnings.empty());
}

TEST(NormalizeScan, ForcedUnitsAndAxis) {
  Scan scan = scanOf(makeCylinder(2, 8, 0.2, 1.7));
  scan.mesh.V *= 200.0;
  Scan tooSmall = scan;
  const NormalizeReport r = normalizeScan(scan, {.units = Units::Millimetres, .up = UpAxis::NegY});
  EXPECT_FALSE(r.unitsDetected);
  EXPECT_FALSE(r.upDetected);
  EXPECT_EQ(r.up, UpAxis::NegY);
  EXPECT_NEAR(r.heightMetres, 0.34, 1e-12);
  EXPECT_FALSE(r.warnings.empty());  // 0.34 m is no standing person: accepted with a warning
  // Forced units do not make a 17 cm object a person.
  tooSmall.mesh.V *= 0.5;
  EXPECT_THROW(normalizeScan(tooSmall, {.units = Units::Millimetres, .up = UpAxis::NegY}),
               InputError);
}

TEST(NormalizeScan, DetectsUpAxisOfPersonInFourOrientations) {
  const TriMesh person = test::makePerson();
  // Normalised: feet on y = 0, x/z centred on the lowest 5 % (x ∈ [−0.2, 0.2], z ∈ [−0.05, 0.2]).
  Eigen::MatrixX3d expected = person.V;
  expected.col(2).array() -= 0.075;
  const Eigen::RowVector3d offset(120.0, -45.0, 33.0);
  for (const UpAxis up : {UpAxis::PosY, UpAxis::NegY, UpAxis::PosZ, UpAxis::NegZ}) {
    // The file holds the person in millimetres with `up` as its up direction.
    Scan scan = scanOf(person);
    scan.mesh.V = (person.V * upRotation(up)) * 1000.0;  // rows: (Rᵀ p)ᵀ = pᵀ R
    scan.mesh.V.rowwise() += offset;
    const Eigen::MatrixX3d input = scan.mesh.V;
    const NormalizeReport r = normalizeScan(scan);
    EXPECT_EQ(r.up, up) << toString(up) << ": " << r.upCues;
    EXPECT_FALSE(r.upAmbiguous) << toString(up);
    EXPECT_GE(r.upScore * ((up == UpAxis::PosY || up == UpAxis::PosZ) ? 1 : -1), 3) << r.upCues;
    EXPECT_EQ(r.units, Units::Millimetres);
    EXPECT_NEAR(r.heightMetres, 1.69, 1e-9);
    EXPECT_LT((scan.mesh.V - expected).cwiseAbs().maxCoeff(), 1e-9) << toString(up);
    // Back to the file's frame.
    const Eigen::MatrixX3d back =
        ((scan.toInputFrame.linear() * scan.mesh.V.transpose()).colwise() +
         scan.toInputFrame.translation())
            .transpose();
    EXPECT_LT((back - input).cwiseAbs().maxCoeff(), 1e-9) << toString(up);
  }
}

TEST(NormalizeScan, UpRotationsAreProperAndDistinct) {
  for (const UpAxis up : {UpAxis::PosY, UpAxis::NegY, UpAxis::PosZ, UpAxis::NegZ}) {
    const Eigen::Matrix3d R = upRotation(up);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-15);
    EXPECT_TRUE((R * R.transpose()).isIdentity(1e-15));
  }
  EXPECT_EQ(upRotation(UpAxis::PosZ) * Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(upRotation(UpAxis::NegZ) * Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(0, 1, 0));
  EXPECT_EQ(upRotation(UpAxis::NegY) * Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(0, 1, 0));
}

TEST(NormalizeScan, AbsurdSizeIsNotAPerson) {
  for (const double height : {0.01, 300.0, 4.0, 0.3}) {
    Scan scan = scanOf(makeCylinder(2, 8, 0.1 * height, height));
    try {
      normalizeScan(scan);
      ADD_FAILURE() << "height " << height << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("not a person"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("--units"), std::string::npos) << e.what();
    }
  }
  Scan nan = scanOf(makeGrid(1, 1));
  nan.mesh.V(0, 0) = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(throwsExactly<InputError>([&] { normalizeScan(nan); }));
}

TEST(NormalizeScan, ParsesAndPrintsCliStrings) {
  for (const Units u :
       {Units::Auto, Units::Millimetres, Units::Centimetres, Units::Decimetres, Units::Metres})
    EXPECT_EQ(parseUnits(toString(u)), u);
  for (const UpAxis a : {UpAxis::Auto, UpAxis::PosY, UpAxis::NegY, UpAxis::PosZ, UpAxis::NegZ})
    EXPECT_EQ(parseUpAxis(toString(a)), a);
  EXPECT_EQ(parseUnits("Millimeters"), Units::Millimetres);
  EXPECT_EQ(parseUpAxis("Z"), UpAxis::PosZ);
  EXPECT_FALSE(parseUnits("inch").has_value());
  EXPECT_FALSE(parseUpAxis("x").has_value());
}

}  // namespace
}  // namespace s2p
