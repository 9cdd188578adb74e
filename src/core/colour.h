// Colour spaces for scan colours: sRGB (gamma-encoded, [0, 1]) ↔ linear RGB ↔ CIE XYZ (D65,
// 2° observer, Y of white = 1) ↔ CIELAB, and colour differences ΔE*ab (CIE76) and ΔE00
// (CIEDE2000). The paper's colour model (§5.1.4) is a GMM in CIELAB. Every conversion comes as
// a single-colour version (Eigen::Vector3d) and a row-wise one (#N×3); pass concrete types
// (an Eigen expression matches both overloads). Values outside the gamut pass through the
// formulas unclamped, so conversions stay invertible.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace s2p {

// === Reference data
// D65 white in XYZ (Y = 1), consistent with the sRGB matrices below (sRGB white → a = b = 0).
Eigen::Vector3d whitePointD65();
// Linear sRGB → XYZ, derived from the IEC 61966-2-1 primaries and the D65 chromaticity.
const Eigen::Matrix3d& linearRgbToXyzMatrix();

// === Single colours
double srgbToLinear(double c);  // IEC 61966-2-1 transfer function, decoding
double linearToSrgb(double c);  // its exact inverse, encoding
Eigen::Vector3d srgbToLinear(const Eigen::Vector3d& srgb);
Eigen::Vector3d linearToSrgb(const Eigen::Vector3d& rgb);
Eigen::Vector3d linearRgbToXyz(const Eigen::Vector3d& rgb);
Eigen::Vector3d xyzToLinearRgb(const Eigen::Vector3d& xyz);
Eigen::Vector3d xyzToLab(const Eigen::Vector3d& xyz);  // L in [0, 100] for Y in [0, 1]
Eigen::Vector3d labToXyz(const Eigen::Vector3d& lab);
Eigen::Vector3d srgbToLab(const Eigen::Vector3d& srgb);
Eigen::Vector3d labToSrgb(const Eigen::Vector3d& lab);

// === Row-wise versions: #N×3 in, #N×3 out
Eigen::MatrixX3d srgbToLinear(const Eigen::MatrixX3d& srgb);
Eigen::MatrixX3d linearToSrgb(const Eigen::MatrixX3d& rgb);
Eigen::MatrixX3d linearRgbToXyz(const Eigen::MatrixX3d& rgb);
Eigen::MatrixX3d xyzToLinearRgb(const Eigen::MatrixX3d& xyz);
Eigen::MatrixX3d xyzToLab(const Eigen::MatrixX3d& xyz);
Eigen::MatrixX3d labToXyz(const Eigen::MatrixX3d& lab);
Eigen::MatrixX3d srgbToLab(const Eigen::MatrixX3d& srgb);
Eigen::MatrixX3d labToSrgb(const Eigen::MatrixX3d& lab);

// === Colour differences of CIELAB colours
// ΔE*ab (CIE76): Euclidean distance in CIELAB.
double deltaE76(const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2);
// ΔE00 (CIEDE2000) as implemented and tested by Sharma, Wu & Dalal 2005; kL, kC, kH are the
// parametric weights (1 for reference conditions). Symmetric in its arguments.
double deltaE2000(const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2, double kL = 1.0,
                  double kC = 1.0, double kH = 1.0);
// Row-wise: #N (rows of lab1 and lab2 must match; InputError otherwise).
Eigen::VectorXd deltaE76(const Eigen::MatrixX3d& lab1, const Eigen::MatrixX3d& lab2);
Eigen::VectorXd deltaE2000(const Eigen::MatrixX3d& lab1, const Eigen::MatrixX3d& lab2);
// Per-channel median of the rows `rows` of `colours` (#N×3, any colour space); InputError when
// `rows` is empty.
Eigen::Vector3d medianColour(const Eigen::MatrixX3d& colours, const std::vector<int>& rows);

}  // namespace s2p
