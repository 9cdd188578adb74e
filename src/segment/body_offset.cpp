#include "segment/body_offset.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"
#include "core/laplacian.h"
#include "segment/colour_model.h"

namespace s2p {

namespace {

void checkOptions(const GeometricCueOptions& o) {
  if (!(o.noiseLength >= 0) || !(o.stepReach > o.noiseLength) || !(o.stepHeight > 0) ||
      !(o.stepDeadZone >= 0) || !(o.stepDeadZone < 0.5 * o.stepHeight) ||
      !(o.blindDeltaE >= 0) || !(o.clearDeltaE > o.blindDeltaE) || !(o.garmentOffset >= 0))
    throw InputError(
        "geometric cues: noiseLength ≥ 0, stepReach > noiseLength, stepHeight > 0 (metres) and "
        "0 ≤ blindDeltaE < clearDeltaE are required");
}

}  // namespace

Eigen::VectorXd bodyOffset(const TriMesh& scan, const MeshQuery& underBody,
                           const TriMesh& underBodyMesh, Eigen::MatrixX3d* bodyNormal) {
  const std::vector<ClosestHit> hits = underBody.closestPoints(scan.V);
  const Eigen::MatrixX3d N = faceNormals(underBodyMesh);
  Eigen::VectorXd out(scan.numVertices());
  if (bodyNormal) bodyNormal->resize(scan.numVertices(), 3);
  for (int v = 0; v < scan.numVertices(); ++v) {
    const ClosestHit& h = hits[v];
    const Eigen::Vector3d d = scan.V.row(v).transpose() - h.point;
    out[v] = d.dot(N.row(h.face).transpose()) < 0 ? -h.distance : h.distance;
    if (bodyNormal) bodyNormal->row(v) = N.row(h.face);
  }
  return out;
}

std::vector<double> offsetsAt(const TriMesh& scan, const Eigen::VectorXd& offset,
                              const std::vector<SurfacePoint>& points) {
  if (offset.size() != scan.numVertices())
    throw InputError("geometric cues: " + std::to_string(offset.size()) + " offsets for " +
                     std::to_string(scan.numVertices()) + " vertices");
  std::vector<double> out;
  out.reserve(points.size());
  for (const SurfacePoint& p : points) {
    if (p.face < 0 || p.face >= scan.numFaces())
      throw InputError("geometric cues: a region point lies on face " + std::to_string(p.face) +
                       ", outside the scan's " + std::to_string(scan.numFaces()));
    int corner = 0;
    p.bary.maxCoeff(&corner);
    out.push_back(offset[scan.F(p.face, corner)]);
  }
  return out;
}

bool offsetSaysClothed(const std::vector<double>& offsets, const GeometricCueOptions& options) {
  checkOptions(options);
  if (offsets.empty()) return false;
  std::vector<double> o = offsets;
  std::nth_element(o.begin(), o.begin() + o.size() / 2, o.end());
  return o[o.size() / 2] > options.garmentOffset;
}

Eigen::VectorXd stepField(const TriMesh& scan, const Eigen::VectorXd& offset,
                          const GeometricCueOptions& options, Eigen::VectorXd* smoothedOffset) {
  checkOptions(options);
  if (offset.size() != scan.numVertices() || !offset.allFinite())
    throw InputError("geometric cues: " + std::to_string(offset.size()) + " offsets for " +
                     std::to_string(scan.numVertices()) + " vertices, or not finite");
  const Eigen::MatrixXd o = offset;
  const Eigen::MatrixXd fine = smoothOnSurface(scan, o, options.noiseLength);
  const Eigen::MatrixXd broad = smoothOnSurface(scan, o, options.stepReach);
  if (smoothedOffset) *smoothedOffset = fine.col(0);
  return (fine - broad).col(0);
}

Eigen::VectorXd stepDisplacement(const Eigen::VectorXd& step, double highSide,
                                 const GeometricCueOptions& options) {
  checkOptions(options);
  const double s = highSide < 0 ? -1.0 : 1.0;
  const double dead = options.stepDeadZone, full = 0.5 * options.stepHeight;
  Eigen::VectorXd out(step.size());
  for (Eigen::Index v = 0; v < step.size(); ++v) {
    const double a = std::clamp((std::abs(step[v]) - dead) / (full - dead), 0.0, 1.0);
    out[v] = step[v] < 0 ? -s * a : s * a;
  }
  return out;
}

Eigen::VectorXd offsetDisplacement(const Eigen::VectorXd& offset, double skinLevel,
                                   double garmentLevel) {
  if (!(garmentLevel > skinLevel))
    throw InputError("geometric cues: the garment's offset level (" +
                     std::to_string(garmentLevel) + " m) must lie above the skin's (" +
                     std::to_string(skinLevel) + " m)");
  const double mid = 0.5 * (skinLevel + garmentLevel), half = 0.5 * (garmentLevel - skinLevel);
  return ((mid - offset.array()) / half).cwiseMax(-1.0).cwiseMin(1.0).matrix();
}

double geometryWeight(double deltaE, const GeometricCueOptions& options) {
  checkOptions(options);
  return std::clamp((options.clearDeltaE - deltaE) / (options.clearDeltaE - options.blindDeltaE),
                    0.0, 1.0);
}

Eigen::VectorXd combinedDisplacement(const Eigen::VectorXd& colour, const Eigen::VectorXd& step,
                                     double weight) {
  if (colour.size() != step.size())
    throw InputError("geometric cues: " + std::to_string(colour.size()) +
                     " colour displacements for " + std::to_string(step.size()) + " step values");
  const double w = std::clamp(weight, 0.0, 1.0);
  if (w == 0) return colour;
  return (colour + 2 * w * step).cwiseMax(-1.0).cwiseMin(1.0);
}

double stepOrientation(const TriMesh& mesh, const Eigen::VectorXd& offset,
                       const Eigen::VectorXd& step, const Eigen::VectorXd& phi0, double band,
                       const GeometricCueOptions& options) {
  checkOptions(options);
  const int nV = mesh.numVertices();
  if (offset.size() != nV || step.size() != nV || phi0.size() != nV)
    throw InputError("geometric cues: offset, step and φ₀ need one value per vertex");
  const Eigen::SparseMatrix<double> G = gradientOperator(mesh);
  const Eigen::VectorXd go = G * offset, gp = G * phi0;
  const Eigen::VectorXd area = faceAreas(mesh);
  const int nF = mesh.numFaces();
  const double threshold = 0.25 * options.stepHeight;
  double vote = 0, weight = 0;
  for (int f = 0; f < nF; ++f) {
    bool onStep = true, near = true;
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.F(f, k);
      onStep &= std::abs(step[v]) > threshold;
      near &= std::abs(phi0[v]) < band;
    }
    if (!onStep || !near) continue;
    const Eigen::Vector3d a(go[f], go[nF + f], go[2 * nF + f]);
    const Eigen::Vector3d b(gp[f], gp[nF + f], gp[2 * nF + f]);
    vote += area[f] * a.dot(b);
    weight += area[f];
  }
  return weight > 0 ? vote / weight : 0.0;
}

double hemContrast(const TriMesh& mesh, const Eigen::VectorXd& phi, const Eigen::VectorXd& step,
                   double highSide, const GeometricCueOptions& options) {
  checkOptions(options);
  const int nV = mesh.numVertices();
  if (phi.size() != nV || step.size() != nV)
    throw InputError("geometric cues: φ and the step field need one value per vertex");
  // The band of half a step reach either side of the curve (φ is a signed distance): on a hem
  // the step field votes for the positive side on the positive half (s·h > 0) and for the
  // negative side on the other; a step Δ gives votes (Δ/2)·e^(−x/L), median ≈ 0.4Δ, less where
  // the fitted body follows the clothes a little. The boundary of a displacement that follows
  // the steps always ends where the votes turn, so off a hem they are positive too, but small.
  const double band = 0.5 * options.stepReach;
  const double s = highSide < 0 ? -1.0 : 1.0;
  std::vector<double> votes;
  for (int v = 0; v < nV; ++v)
    if (std::abs(phi[v]) < band) votes.push_back((phi[v] >= 0 ? s : -s) * step[v]);
  if (votes.empty()) return 0.0;
  std::nth_element(votes.begin(), votes.begin() + votes.size() / 2, votes.end());
  return votes[votes.size() / 2];
}

}  // namespace s2p
