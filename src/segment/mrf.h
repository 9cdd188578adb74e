// Per-vertex Markov random field segmentation: the baseline the paper compares its boundary
// optimisation with (§7, Fig. 14; the ClothCap procedure of Pons-Moll et al. 2017). Every
// vertex gets one of the regions' labels by minimising
//   E(f) = Σ_u (A_u / s²) [D_u(f_u) + P_u(f_u)] + Σ_{uv ∈ edges} λ (|uv| / s) c_uv [f_u ≠ f_v]
// with the boundary optimiser's colour model (§5.1.4, Eq. 2) as data term D, the projected
// labelled regions as prior P and a contrast-sensitive Potts smoothness term,
// c_uv = exp(−ΔE_uv²/(2σ²)). A_u is the vertex's (barycentric) area and s a fixed reference
// spacing in metres, so E approximates (1/s²)(∫ D + P dA + λ s · κ · boundary length) (κ a
// constant of the mesh's edge directions): the same λ means the same thing at every
// resolution, and at spacing s every vertex weighs about 1. Minimised by alpha-expansion
// (Boykov, Veksler and Zabih 2001), each expansion move an exact min cut (libmaxflow).
//
// With the scan's offset from the body under the clothes (issue 18's geometric cues,
// segment/body_offset.h) the data term is the posterior of colour and offset together, bare skin
// lying on the body and what covers it off the body by its ease, and an edge across a hem's
// riser is cheap to cut (c_uv also falls with the offset's slope along the edge).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/surface_point.h"
#include "core/tri_mesh.h"
#include "segment/colour_model.h"

namespace s2p {

struct MrfRegion {                     // one label
  int label = 0;                       // the caller's label code (e.g. synth Label values)
  std::vector<SurfacePoint> points{};  // projected region points of that label on the mesh
  bool bareSkin = false;  // lies on the body (the offset's skin model); else covers it
};

struct MrfOptions {
  // Potts weight λ: cutting an edge of length s between equally coloured vertices costs λ,
  // as much as λ nats of data term on a vertex of area s². With the data term bounded by
  // −log(posteriorFloor / #labels) (≈ 3.7 for two labels, 4.4 for four), λ = 1 removes specks
  // of about one vertex at spacing s (≈ 1 cm²) whatever their colour, and keeps confidently
  // coloured patches a few centimetres wide: the baseline stays a per-vertex labelling.
  double smoothness = 1.0;
  // Metres, the reference spacing s: 1 cm, the vertex spacing of a 1.75 m person scanned with
  // ≈ 50k vertices.
  double spacing = 0.01;
  // σ of the contrast factor exp(−ΔE²/(2σ²)), ΔE the CIE76 difference of the smoothed colours
  // of an edge's two ends. 10 keeps in-fabric variation (ΔE ≲ 5: factor ≥ 0.88) and makes
  // garment edges (ΔE ≳ 25: factor ≤ 0.04) cheap to cut. 0 turns contrast sensitivity off.
  double contrast = 10.0;
  // Metres: the prior cost of label l at vertex u is priorWeight · (d/priorLength)², d the
  // Euclidean distance from u to l's nearest region point (k-d tree). 0.3 m is about how far a
  // garment may extend beyond its projected region points on a 1.75 m body (a trouser leg or
  // sleeve past its last region point): within it two labels' priors differ by less than
  // priorWeight, well inside the colour term's range, so colour decides at a boundary; at
  // ≳ 3 × priorLength (≥ 9 × priorWeight) the prior overrules colour matches on distant body
  // parts (a red shoe far from a red shirt's points).
  double priorLength = 0.3;
  double priorWeight = 1.0;  // in data-term units (nats)
  // Robust data term: −log(ε/#labels + (1−ε) P(l | c)), so one badly coloured vertex (a
  // specular highlight, a print) costs at most −log(ε/#labels) and can be outvoted by its
  // neighbours. 0 gives the plain −log posterior (clamped at 1e-300).
  double posteriorFloor = 0.05;
  // The geometric cues, when mrfSegmentation is given the offset o from the body under the
  // clothes. The likelihood of o is, for bare skin and for what covers it (every other region's
  // points pooled: between two garments the offset tells nothing, as in the curve method),
  //   p(o) = (1 − η) N(o; μ, σ²) + η / R,
  // μ the median and σ the MAD-estimated spread of the offsets at the regions' points. The
  // outlier share η bounds the log-likelihood ratio the offset adds at
  // log(1 + (1 − η) R / (η σ √(2π))) ≈ 4.5 nats at σ = 2 mm, while colours ΔE00 ≥ 20 apart differ
  // by tens of nats: colour decides where it tells the labels apart (a hand the fit missed by a
  // centimetre stays skin), the offset where it cannot (a skin-coloured sleeve off the arm by its
  // ease; colours ΔE 8 apart differ by ~3 nats).
  // m: σ's floor. The skin's model is fitted on the face and hands, where the fit is closest
  // (|o| 90th percentile 1.3 mm on the suite's fits); bare arms, legs and torsos lie farther
  // (1.5–3.0 mm). At 1 mm the bare arms of a sleeveless top went to the top (MRF IoU 0.968
  // against 0.982 at 2 mm) and a skin-coloured top's bare neck and arms too (0.881 against 0.984).
  double offsetNoise = 0.002;
  double offsetOutliers = 0.1;  // η
  double offsetRange = 0.05;    // m: R, the span of offsets on a scan (−1 … 4 cm)
  // The steps of the offset as contrast: c_uv is also multiplied by exp(−(Δo/|uv|)²/(2τ²)),
  // Δo the difference of the edge's ends' offsets. A hem's riser has slope ~1 (factor < 10⁻³ at
  // τ = 0.25), the ease along a garment ≲ 0.1 (factor ≥ 0.92). 0 turns it off.
  double riserSlope = 0.25;
  int maxSweeps = 5;            // alpha-expansion sweeps over all labels (0: data + prior argmin)
  ColourModelOptions colour{};  // smoothing + GMM, the same as the boundary optimiser's
};

struct OffsetModel {  // the Gaussian part of an offset likelihood, metres
  double mean = 0, sigma = 0;
};

struct MrfResult {
  Eigen::VectorXi vertexLabel;          // #V, caller's label codes
  OffsetModel skinOffset, clothedOffset;  // fitted when the offset was given
  std::vector<GaussianMixture> models;  // one per region, fitted on its points' colours
  double energy = 0;                    // E(f) of vertexLabel
  int sweeps = 0;                       // alpha-expansion sweeps run
  std::vector<double> sweepEnergies;    // E before the first sweep, then after each sweep
};

// srgb: #V×3 in [0, 1]. offset: #V (m, smoothed over the scanner's noise), or empty for colour
// alone; with it, at least one region must be bare skin and one not. Throws InputError for an
// invalid mesh, colours or offsets of the wrong size or non-finite, fewer than two regions, two
// regions with the same label, a region without points, points off the mesh (face out of range
// or non-finite barycentric weights), an offset without both kinds of region, and options out
// of range; SolverError when a min cut cannot allocate its graph.
MrfResult mrfSegmentation(const TriMesh& mesh, const Eigen::MatrixX3d& srgb,
                          const std::vector<MrfRegion>& regions, const MrfOptions& options = {},
                          const Eigen::VectorXd& offset = {});

// === The optimiser on its own

struct PottsResult {
  Eigen::VectorXi label;              // #V, in [0, K)
  double energy = 0;                  // E of label
  int sweeps = 0;                     // sweeps run
  std::vector<double> sweepEnergies;  // E of the start, then after each sweep (non-increasing)
};

// Alpha-expansion for E(f) = Σ_u unary(u, f_u) + Σ_k weight_k [f_a ≠ f_b], edges_k = (a, b):
// unary #V×K finite, edges #E×2 vertex indices, weight #E finite and ≥ 0. Starts from the
// per-vertex argmin of unary and stops after a sweep over all K labels without a strict
// decrease or after maxSweeps sweeps. Exact for K = 2 (one min cut); within a factor 2 of the
// optimum for K > 2 (Boykov, Veksler and Zabih 2001, Thm. 6.1). Throws InputError for sizes or
// values out of range, SolverError when the min-cut graph cannot be allocated.
PottsResult minimisePotts(const Eigen::MatrixXd& unary, const Eigen::MatrixX2i& edges,
                          const Eigen::VectorXd& weight, int maxSweeps = 5);

// Face labels (#F) from vertex labels (#V): the majority of the three corners; when all three
// differ, the label of the corner with the smallest vertex index (so rotating a face's corners
// does not change it). Throws InputError when vertexLabel's size is not #V or an index is out
// of range.
Eigen::VectorXi faceLabelsFromVertices(const TriMesh& mesh, const Eigen::VectorXi& vertexLabel);

}  // namespace s2p
