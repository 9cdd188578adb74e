#include "core/colour.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "core/error.h"

namespace s2p {
namespace {

// CIE constants as exact rationals (CIE 15:2004 note): ε = (6/29)³, κ = (29/3)³.
constexpr double kEpsilon = 216.0 / 24389.0;
constexpr double kKappa = 24389.0 / 27.0;
// Decoding threshold of IEC 61966-2-1; encoding uses its image 0.04045/12.92 so that the two
// piecewise functions are exact inverses of each other.
constexpr double kSrgbThreshold = 0.04045;
constexpr double kLinearThreshold = kSrgbThreshold / 12.92;

struct Matrices {
  Eigen::Matrix3d toXyz;
  Eigen::Matrix3d fromXyz;
  Eigen::Vector3d white;
};

// M = [P · diag(S)] with P the primaries' xyz columns and S solving P S = white (Y = 1).
const Matrices& matrices() {
  static const Matrices m = [] {
    auto xyz = [](double x, double y) { return Eigen::Vector3d(x / y, 1.0, (1 - x - y) / y); };
    Eigen::Matrix3d P;
    P.col(0) = xyz(0.64, 0.33);
    P.col(1) = xyz(0.30, 0.60);
    P.col(2) = xyz(0.15, 0.06);
    const Eigen::Vector3d white = xyz(0.3127, 0.3290);
    const Eigen::Vector3d S = P.lu().solve(white);
    Matrices out;
    out.toXyz = P * S.asDiagonal();
    out.fromXyz = out.toXyz.inverse();
    out.white = out.toXyz * Eigen::Vector3d::Ones();
    return out;
  }();
  return m;
}

double labF(double t) {
  return t > kEpsilon ? std::cbrt(t) : (kKappa * t + 16.0) / 116.0;
}

double labFInverse(double f) {
  const double f3 = f * f * f;
  return f3 > kEpsilon ? f3 : (116.0 * f - 16.0) / kKappa;
}

double degrees(double radians) {
  return radians * 180.0 / std::numbers::pi;
}
double radians(double degrees) {
  return degrees * std::numbers::pi / 180.0;
}

template <typename Fn>
Eigen::MatrixX3d rowWise(const Eigen::MatrixX3d& in, Fn fn) {
  Eigen::MatrixX3d out(in.rows(), 3);
  for (Eigen::Index i = 0; i < in.rows(); ++i)
    out.row(i) = fn(Eigen::Vector3d(in.row(i).transpose())).transpose();
  return out;
}

void requireSameRows(const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b, const char* fn) {
  if (a.rows() != b.rows())
    throw InputError(std::string(fn) + ": the two colour lists have " + std::to_string(a.rows()) +
                     " and " + std::to_string(b.rows()) + " rows; pass lists of equal length");
}

}  // namespace

Eigen::Vector3d whitePointD65() {
  return matrices().white;
}
const Eigen::Matrix3d& linearRgbToXyzMatrix() {
  return matrices().toXyz;
}

double srgbToLinear(double c) {
  return c <= kSrgbThreshold ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

double linearToSrgb(double c) {
  return c <= kLinearThreshold ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

Eigen::Vector3d srgbToLinear(const Eigen::Vector3d& srgb) {
  return {srgbToLinear(srgb.x()), srgbToLinear(srgb.y()), srgbToLinear(srgb.z())};
}

Eigen::Vector3d linearToSrgb(const Eigen::Vector3d& rgb) {
  return {linearToSrgb(rgb.x()), linearToSrgb(rgb.y()), linearToSrgb(rgb.z())};
}

Eigen::Vector3d linearRgbToXyz(const Eigen::Vector3d& rgb) {
  return matrices().toXyz * rgb;
}
Eigen::Vector3d xyzToLinearRgb(const Eigen::Vector3d& xyz) {
  return matrices().fromXyz * xyz;
}

Eigen::Vector3d xyzToLab(const Eigen::Vector3d& xyz) {
  const Eigen::Vector3d& w = matrices().white;
  const double fx = labF(xyz.x() / w.x()), fy = labF(xyz.y() / w.y()), fz = labF(xyz.z() / w.z());
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

Eigen::Vector3d labToXyz(const Eigen::Vector3d& lab) {
  const Eigen::Vector3d& w = matrices().white;
  const double fy = (lab.x() + 16.0) / 116.0;
  const double fx = fy + lab.y() / 500.0, fz = fy - lab.z() / 200.0;
  // Y from L directly (L > κε ⇔ fy³ > ε) keeps the dark branch exactly linear.
  const double yr = lab.x() > kKappa * kEpsilon ? fy * fy * fy : lab.x() / kKappa;
  return {w.x() * labFInverse(fx), w.y() * yr, w.z() * labFInverse(fz)};
}

Eigen::Vector3d srgbToLab(const Eigen::Vector3d& srgb) {
  return xyzToLab(linearRgbToXyz(srgbToLinear(srgb)));
}

Eigen::Vector3d labToSrgb(const Eigen::Vector3d& lab) {
  return linearToSrgb(xyzToLinearRgb(labToXyz(lab)));
}

Eigen::MatrixX3d srgbToLinear(const Eigen::MatrixX3d& srgb) {
  return srgb.unaryExpr([](double c) { return srgbToLinear(c); });
}

Eigen::MatrixX3d linearToSrgb(const Eigen::MatrixX3d& rgb) {
  return rgb.unaryExpr([](double c) { return linearToSrgb(c); });
}

Eigen::MatrixX3d linearRgbToXyz(const Eigen::MatrixX3d& rgb) {
  return rgb * matrices().toXyz.transpose();
}

Eigen::MatrixX3d xyzToLinearRgb(const Eigen::MatrixX3d& xyz) {
  return xyz * matrices().fromXyz.transpose();
}

Eigen::MatrixX3d xyzToLab(const Eigen::MatrixX3d& xyz) {
  return rowWise(xyz, [](const Eigen::Vector3d& c) { return xyzToLab(c); });
}

Eigen::MatrixX3d labToXyz(const Eigen::MatrixX3d& lab) {
  return rowWise(lab, [](const Eigen::Vector3d& c) { return labToXyz(c); });
}

Eigen::MatrixX3d srgbToLab(const Eigen::MatrixX3d& srgb) {
  return xyzToLab(linearRgbToXyz(srgbToLinear(srgb)));
}

Eigen::MatrixX3d labToSrgb(const Eigen::MatrixX3d& lab) {
  return linearToSrgb(xyzToLinearRgb(labToXyz(lab)));
}

double deltaE76(const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2) {
  return (lab1 - lab2).norm();
}

// Sharma, Wu & Dalal 2005, Eqs. (1)-(22); hues in degrees.
double deltaE2000(const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2, double kL, double kC,
                  double kH) {
  const double L1 = lab1.x(), a1 = lab1.y(), b1 = lab1.z();
  const double L2 = lab2.x(), a2 = lab2.y(), b2 = lab2.z();
  const double pow25_7 = 6103515625.0;  // 25^7
  const double C1 = std::hypot(a1, b1), C2 = std::hypot(a2, b2);
  const double Cbar = 0.5 * (C1 + C2);
  const double Cbar7 = std::pow(Cbar, 7);
  const double G = 0.5 * (1.0 - std::sqrt(Cbar7 / (Cbar7 + pow25_7)));
  const double a1p = (1.0 + G) * a1, a2p = (1.0 + G) * a2;
  const double C1p = std::hypot(a1p, b1), C2p = std::hypot(a2p, b2);
  auto hue = [](double b, double ap) {
    if (b == 0 && ap == 0) return 0.0;
    const double h = degrees(std::atan2(b, ap));
    return h < 0 ? h + 360.0 : h;
  };
  const double h1p = hue(b1, a1p), h2p = hue(b2, a2p);

  const double dLp = L2 - L1;
  const double dCp = C2p - C1p;
  const double CpProd = C1p * C2p;
  double dhp = 0;
  if (CpProd != 0) {
    dhp = h2p - h1p;
    if (dhp > 180.0)
      dhp -= 360.0;
    else if (dhp < -180.0)
      dhp += 360.0;
  }
  const double dHp = 2.0 * std::sqrt(CpProd) * std::sin(radians(0.5 * dhp));

  const double Lbarp = 0.5 * (L1 + L2);
  const double Cbarp = 0.5 * (C1p + C2p);
  double hbarp = h1p + h2p;
  if (CpProd != 0) {
    if (std::abs(h1p - h2p) <= 180.0)
      hbarp = 0.5 * (h1p + h2p);
    else if (h1p + h2p < 360.0)
      hbarp = 0.5 * (h1p + h2p + 360.0);
    else
      hbarp = 0.5 * (h1p + h2p - 360.0);
  }
  const double T =
      1.0 - 0.17 * std::cos(radians(hbarp - 30.0)) + 0.24 * std::cos(radians(2.0 * hbarp)) +
      0.32 * std::cos(radians(3.0 * hbarp + 6.0)) - 0.20 * std::cos(radians(4.0 * hbarp - 63.0));
  const double dTheta = 30.0 * std::exp(-std::pow((hbarp - 275.0) / 25.0, 2));
  const double Cbarp7 = std::pow(Cbarp, 7);
  const double RC = 2.0 * std::sqrt(Cbarp7 / (Cbarp7 + pow25_7));
  const double Lm50sq = (Lbarp - 50.0) * (Lbarp - 50.0);
  const double SL = 1.0 + 0.015 * Lm50sq / std::sqrt(20.0 + Lm50sq);
  const double SC = 1.0 + 0.045 * Cbarp;
  const double SH = 1.0 + 0.015 * Cbarp * T;
  const double RT = -std::sin(radians(2.0 * dTheta)) * RC;
  const double tL = dLp / (kL * SL), tC = dCp / (kC * SC), tH = dHp / (kH * SH);
  return std::sqrt(tL * tL + tC * tC + tH * tH + RT * tC * tH);
}

Eigen::VectorXd deltaE76(const Eigen::MatrixX3d& lab1, const Eigen::MatrixX3d& lab2) {
  requireSameRows(lab1, lab2, "deltaE76");
  return (lab1 - lab2).rowwise().norm();
}

Eigen::VectorXd deltaE2000(const Eigen::MatrixX3d& lab1, const Eigen::MatrixX3d& lab2) {
  requireSameRows(lab1, lab2, "deltaE2000");
  Eigen::VectorXd out(lab1.rows());
  for (Eigen::Index i = 0; i < lab1.rows(); ++i)
    out(i) = deltaE2000(Eigen::Vector3d(lab1.row(i).transpose()),
                        Eigen::Vector3d(lab2.row(i).transpose()));
  return out;
}

Eigen::Vector3d medianColour(const Eigen::MatrixX3d& colours, const std::vector<int>& rows) {
  if (rows.empty()) throw InputError("medianColour: no rows");
  Eigen::Vector3d out;
  std::vector<double> c(rows.size());
  for (int k = 0; k < 3; ++k) {
    for (size_t i = 0; i < rows.size(); ++i) c[i] = colours(rows[i], k);
    std::nth_element(c.begin(), c.begin() + static_cast<long>(c.size() / 2), c.end());
    out[k] = c[c.size() / 2];
  }
  return out;
}

}  // namespace s2p
