// Polylines as lists of points (metres): a moving mean over arc length, and the runs of equal
// labels along a curve.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace s2p {

// Each point of the closed polyline `points` replaced by the mean position of the polyline over
// the arc of ±halfWidth around it (a box filter in arc length, exact on the segments, so the
// same at any spacing of the points). A zigzag of wavelength 2·halfWidth is removed; a circle of
// radius R shrinks by R(1 − sinc(halfWidth / R)) ≈ halfWidth² / (6R). A loop no longer than
// 4·halfWidth, or halfWidth ≤ 0, is returned as it is. #N×3.
Eigen::MatrixX3d boxFilterClosedPolyline(const std::vector<Eigen::Vector3d>& points,
                                         double halfWidth);

// Each point's share of the polyline's length: half of the segments either side of it (closed:
// the last point joins the first). Sums to the length. #N.
std::vector<double> arcLengthShares(const std::vector<Eigen::Vector3d>& points, bool closed);

// Relabels, shortest first, every run of equal labels along a curve whose length (the sum of its
// points' `share`) is below minLength with its longer neighbour's label, until one run is left or
// none is that short. closed: the first and last points are neighbours. label and share: #N.
void mergeShortRuns(std::vector<int>& label, const std::vector<double>& share, bool closed,
                    double minLength);

}  // namespace s2p
