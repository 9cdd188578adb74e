// Outlines of flattened panels as chains of cubic Béziers (paper §6.2: "we fit each edge of E
// with a Bezier curve"): each edge between two corners is fitted within a tolerance with as
// few segments as the greedy split allows, G1 inside the edge, corners left sharp.
//
// The fit is Schneider's ("An Algorithm for Automatically Fitting Digitized Curves", Graphics
// Gems 1990): chord-length parameters, least-squares inner control points along fixed end
// tangents, Newton reparametrisation while the error is within some tolerances. Where one
// segment does not fit, Schneider splits at the point of largest error; we instead take the
// longest prefix that fits (binary search on its end point), which needs fewer segments (a full
// circle of 0.3 m at 1 mm: 3 instead of 8) and continue from there. A split point's tangent (the
// central difference of its neighbours) is shared by both segments: G1. Also: a segment is
// accepted only when the polyline is within the tolerance of it and it is within the tolerance
// of the polyline (it cannot bulge between samples), and the end tangents are one-sided
// second-order differences.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>
#include <string>
#include <vector>

namespace s2p {

// One cubic Bézier segment, control points p[0..3] (metres).
struct CubicBezier {
  std::array<Eigen::Vector2d, 4> p;

  Eigen::Vector2d point(double t) const;             // B(t), t ∈ [0, 1]
  Eigen::Vector2d derivative(double t) const;        // B'(t)
  Eigen::Vector2d secondDerivative(double t) const;  // B''(t)
  // Arc length of B on [t0, t1] (Gauss–Legendre, relative error ~1e-12 for fair segments).
  double length(double t0 = 0.0, double t1 = 1.0) const;
};

// A chain of segments, each starting where the previous ends (one edge of an outline).
struct BezierChain {
  std::vector<CubicBezier> segments;

  int size() const { return static_cast<int>(segments.size()); }
  double length() const;  // total arc length (m)
  // The point at chain parameter τ ∈ [0, size()]: segment ⌊τ⌋ at t = τ − ⌊τ⌋.
  Eigen::Vector2d point(double tau) const;
};

struct BezierFitOptions {
  double tolerance = 1e-3;            // m: maximum distance between the chain and the polyline
  int maxReparametrisations = 20;     // Newton passes per segment before giving up on it
  double reparametriseFactor = 20.0;  // reparametrise only below this × tolerance
};

// Fits one open polyline (#P×2, P ≥ 2, from one corner to the next) with a G1 chain of cubic
// Béziers that starts and ends exactly at its end points. Consecutive duplicate points are
// ignored. Throws InputError for fewer than two distinct points, non-finite coordinates or a
// tolerance ≤ 0.
BezierChain fitBezierChain(const Eigen::MatrixX2d& polyline, const BezierFitOptions& options = {});

// Fits every edge of a closed outline: points #P×2 in order (the loop closes from the last point
// to the first), corners the indices of the corner points in increasing order (at least one);
// edge k runs from corners[k] to corners[k + 1], the last edge wraps to corners[0]. Returns
// one chain per edge. Throws InputError for bad corner indices.
std::vector<BezierChain> fitOutline(const Eigen::MatrixX2d& points, const std::vector<int>& corners,
                                    const BezierFitOptions& options = {});

// `count` points (≥ 2) along the chain equally spaced by arc length (to ~1e-10 relative),
// the first and last exactly the chain's end points. #count×2.
Eigen::MatrixX2d resampleChain(const BezierChain& chain, int count);

// Arc-length fractions (0, 1) of the joints between the chain's segments, in order.
std::vector<double> jointFractions(const BezierChain& chain);

// The same curve cut (exactly, by de Casteljau) at arc-length fractions `fractions` (any
// order; those within 1e-4 of a joint, of 0 or 1 or of each other are merged): the chain of
// a seam edge made to share its partner's breaks, so that each piece can be stitched alone.
BezierChain splitChainAt(const BezierChain& chain, std::vector<double> fractions);

// Largest distance between the chain and the polyline, both ways: from every polyline point
// to the chain and from dense samples of the chain to the polyline (a Hausdorff distance).
double maxDeviation(const BezierChain& chain, const Eigen::MatrixX2d& polyline);

// Distance from p to the chain (closest point by sampling and Newton refinement).
double distanceToChain(const BezierChain& chain, const Eigen::Vector2d& p);

// The chain under the affine map that keeps its chord (first to last point) and scales every
// offset from it by s: control points map to control points, so joints stay G1 and the ends stay.
BezierChain scaledAcrossChord(const BezierChain& chain, double s);

// Seam walking: the chain scaled across its chord (above) to `target` arc length, by bisection on
// s ∈ [0, 4] (the length grows with s: |B'|² = a² + s²b² in the chord's frame); nullopt when no
// such s reaches it or a control point would move by more than `limit` (m).
std::optional<BezierChain> walkChainToLength(const BezierChain& chain, double target, double limit);

}  // namespace s2p
