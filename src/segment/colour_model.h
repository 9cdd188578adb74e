// The colour displacement function of §5.1.4, Eq. (2): one Gaussian mixture per labelled region
// in CIELAB, fitted by EM on the region points' colours, and the posterior probability of the
// "positive" labels mapped to φ_d = 2(P − ½) ∈ [−1, 1], slightly smoothed on the surface.
// Two labels for B(U|S) and B(U|L); three for B(L|S) (foot or skin vs lower).
//
// Where the paper smooths the RGB colours slightly, we smooth the displacement instead (the RGB
// smoothing is kept as an option, off by default). Smoothed colours blend across a colour edge,
// and a blend of a tight colour (plain skin) with a broad one (a shaded or printed garment) lies
// in the broad mixture's tail long before it is half-way: the zero of φ_d moved onto the tight
// side by most of the smoothing radius (the dress neckline came out 7.5 mm up the neck with 5 mm
// of RGB smoothing). A blend of posteriors crosses zero half-way whatever the spreads, and it
// averages colour noise just as well.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "core/surface_point.h"
#include "core/tri_mesh.h"

namespace s2p {

// === Smoothing

// Implicit (backward Euler) diffusion of per-vertex values (colours, a displacement): `steps`
// solves of (M + s L) x' = M x with s = length² (m²), so the smoothing radius is `length` metres
// whatever the mesh resolution. values: #V×k. length = 0 or steps = 0 returns them unchanged.
Eigen::MatrixXd smoothOnSurface(const TriMesh& mesh, const Eigen::MatrixXd& values, double length,
                                int steps = 1);

// === Gaussian mixture in CIELAB

struct GmmOptions {
  int components = 0;  // fixed k ≥ 1, or 0: k in 1..maxComponents with the lowest BIC
  int maxComponents = 3;
  int maxIterations = 300;
  double tolerance = 1e-7;       // stop when the mean log-likelihood gains less than this
  double covarianceFloor = 1.0;  // added to every covariance's diagonal, (ΔE)²
  // (ΔE)² added to the a* and b* variances instead of covarianceFloor when > 0 (L* keeps
  // covarianceFloor): an anisotropic floor, for light that moves lightness more than chroma.
  double chromaFloor = 0;
  std::uint64_t seed = 1;        // k-means++ initialisation
};

struct GaussianMixture {
  Eigen::VectorXd weights;                   // k, sum 1
  Eigen::MatrixX3d means;                    // k×3
  std::vector<Eigen::Matrix3d> covariances;  // k, SPD (floored)
  double logLikelihood = 0;                  // of the fitted samples
  double bic = 0;                            // −2 log L + (10k − 1) ln N
  int iterations = 0;

  int components() const { return static_cast<int>(weights.size()); }
  // log p(x) for every row of X (#N×3) → #N.
  Eigen::VectorXd logDensity(const Eigen::MatrixX3d& X) const;
};

// EM fit on the rows of X (#N×3, CIELAB). Throws InputError when X is empty, not finite, or
// has fewer rows than the requested components.
GaussianMixture fitGaussianMixture(const Eigen::MatrixX3d& X, const GmmOptions& options = {});

// `model` without the components that `other` already explains: of the components whose means
// lie inside the 95 % ellipsoid (Mahalanobis² < 7.81) of one of other's components, the nearest
// go first, as long as the dropped ones together hold less than `maxShare` of the weight; the
// rest are renormalised.
// For a region whose points can stray onto another label's garment (the hip points of the lower
// region land on a top worn untucked): the strays form a minority component the other region's
// mixture already has, and left in they make that garment's colour ambiguous. `dropped`, when
// given, receives the weight removed (0 when the model is returned whole).
GaussianMixture withoutBorrowedComponents(const GaussianMixture& model,
                                          const GaussianMixture& other, double maxShare = 0.5,
                                          double* dropped = nullptr);

// Per row of lab (#N×3, CIELAB): true when the colour lies inside the 95 % ellipsoids
// (Mahalanobis² < 7.81, as withoutBorrowedComponents) of a component of `a` and a component of
// `b` that are one colour (each one's mean inside the other's ellipsoid): a colour both garments
// are made of (a jersey's white stripes over white shorts), which says nothing about which of
// the two a point belongs to.
std::vector<bool> sharedColours(const GaussianMixture& a, const GaussianMixture& b,
                                const Eigen::MatrixX3d& lab);

// φ_d = 2(P(positive | x) − ½) per row of lab (#N×3) with equal label priors: a label's
// region points reflect the feature layout, not its area. models: one mixture per label;
// positive[i] says which side label i pushes to (+1). Throws InputError when the sizes
// differ or one side has no label.
Eigen::VectorXd posteriorDisplacement(const std::vector<GaussianMixture>& models,
                                      const std::vector<bool>& positive,
                                      const Eigen::MatrixX3d& lab);

// === The person's own skin (issue 18)

// This person's skin under this scan's light, from colours where skin is certain (the face and
// hands, by the fitted body): its mean, and how far from it (CIEDE2000) a colour is still this
// skin: spreadFactor × the 90th percentile of the samples' own ΔE from the mean, within
// [minDeltaE, maxDeltaE]. A bare torso is drawn from the same skin and spreads alike; a top of a
// skin-like tone (beige, 8 ΔE off) lies outside this person's spread though inside a population's.
// Robust to samples that are not skin: the mean and the spread are taken over the samples within
// maxDeltaE of their per-channel median (a long sleeve's cuff over the hand held a third of f2's
// samples, ΔE 26–30 off; with them the mean sat 16 ΔE off the skin and the whole head read as
// "not this skin").
struct SkinModel {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();  // CIELAB
  double threshold = 0;                            // ΔE2000
  // Fraction of the colours lab (#N×3, CIELAB) within `threshold` of the mean; 0 for none.
  double skinLikeFraction(const Eigen::MatrixX3d& lab) const;
};
// lab: #N×3 CIELAB samples of skin. Throws InputError when there are none or they are not finite.
SkinModel fitSkinModel(const Eigen::MatrixX3d& lab, double spreadFactor = 2.0,
                       double minDeltaE = 3.0, double maxDeltaE = 10.0);

// The per-channel median of lab (#N×3, N ≥ 1): a colour centre that a minority of strays does not
// move.
Eigen::Vector3d medianColour(const Eigen::MatrixX3d& lab);

// Per row of `skin` (#N×3 CIELAB, the skin region's samples): true for a sample that is a
// garment's colour, not skin: farther than maxDeltaE (CIEDE2000) from the samples' median colour
// and inside the 95 % ellipsoid of a component of one of `garments` (their region points'
// mixtures). A hand's region point that lands on a sleeve's cuff; a fringe of hair, in no
// garment's colour, stays.
std::vector<bool> skinSamplesOfGarments(const Eigen::MatrixX3d& skin,
                                        const std::vector<GaussianMixture>& garments,
                                        double maxDeltaE = 10.0);

// === The whole displacement (§5.1.4)

struct ColourRegion {
  std::vector<SurfacePoint> points;  // projected labelled region points on the mesh
  bool positive = false;             // the side of the boundary the label is on
};

struct ColourModelOptions {
  double colourSmoothing = 0;            // metres of RGB smoothing before CIELAB (the paper's)
  double displacementSmoothing = 0.005;  // metres of smoothing of φ_d (ours; see the top)
  int smoothingSteps = 1;
  GmmOptions gmm;
};

struct ColourDisplacement {
  Eigen::VectorXd phiD;                 // #V, in [−1, 1]
  Eigen::MatrixX3d lab;                 // #V×3, smoothed colours in CIELAB
  std::vector<GaussianMixture> models;  // one per region
};

// CIELAB colours of a mesh (RGB-smoothed when asked) and one mixture per region, fitted on the
// colours at the region's points (the first half of the displacement, shared by every boundary of a
// scan). A point's colour is its nearest vertex's: interpolated across the edge of a print (a dot,
// a stripe) it would be a blend the garment does not have, and the blends formed a component of
// their own between the print and the ground colour.
struct RegionColours {
  Eigen::MatrixX3d lab;                   // #V×3
  std::vector<GaussianMixture> models;    // one per region
  std::vector<Eigen::Vector3d> means;     // mean CIELAB colour of each region's points
  std::vector<Eigen::MatrixX3d> colours;  // per region, #points×3: the colour at each point
};
RegionColours fitRegionColours(const TriMesh& mesh, const Eigen::MatrixX3d& srgb,
                               const std::vector<std::vector<SurfacePoint>>& regions,
                               const ColourModelOptions& options = {});

// The displacement of one boundary on `mesh` (the scan, or what earlier cuts left of it):
// posteriorDisplacement of its colours lab (#V×3), smoothed by options.displacementSmoothing.
// `neutral` (#V, or empty): vertices whose displacement is 0 before the smoothing.
Eigen::VectorXd smoothedDisplacement(const TriMesh& mesh,
                                     const std::vector<GaussianMixture>& models,
                                     const std::vector<bool>& positive, const Eigen::MatrixX3d& lab,
                                     const ColourModelOptions& options,
                                     const std::vector<bool>& neutral = {});

// srgb: #V×3 in [0, 1]. Throws InputError for a colour matrix of the wrong size or non-finite,
// a region without points, a point off the mesh, or no region on one side.
ColourDisplacement colourDisplacement(const TriMesh& mesh, const Eigen::MatrixX3d& srgb,
                                      const std::vector<ColourRegion>& regions,
                                      const ColourModelOptions& options = {});

}  // namespace s2p
