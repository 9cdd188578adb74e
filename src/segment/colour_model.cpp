#include "segment/colour_model.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "core/colour.h"
#include "core/error.h"
#include "core/laplacian.h"
#include "core/spd_solver.h"

namespace s2p {

namespace {

constexpr double kLog2Pi = 1.8378770664093453;
constexpr double kChi2Three95 = 7.815;  // 95 % quantile of χ² with 3 degrees of freedom

// Mahalanobis² of x from component k of g.
double mahalanobis2(const GaussianMixture& g, int k, const Eigen::Vector3d& x) {
  const Eigen::Vector3d d = x - g.means.row(k).transpose();
  return d.dot(g.covariances[k].ldlt().solve(d));
}

// x inside the 95 % ellipsoid of component k of g.
bool insideComponent(const GaussianMixture& g, int k, const Eigen::Vector3d& x) {
  return mahalanobis2(g, k, x) < kChi2Three95;
}

double logSumExp(const Eigen::VectorXd& a) {
  const double m = a.maxCoeff();
  if (!std::isfinite(m)) return m;
  return m + std::log((a.array() - m).exp().sum());
}

// log N(x | μ, Σ) for every row, with Σ = LLᵀ.
Eigen::VectorXd logGaussian(const Eigen::MatrixX3d& X, const Eigen::RowVector3d& mean,
                            const Eigen::Matrix3d& cov) {
  const Eigen::LLT<Eigen::Matrix3d> llt(cov);
  const Eigen::Matrix3d Lm = llt.matrixL();
  const double logDet = 2 * Lm.diagonal().array().log().sum();
  const Eigen::MatrixXd centred = (X.rowwise() - mean).transpose();  // 3×N
  const Eigen::MatrixXd z = Lm.triangularView<Eigen::Lower>().solve(centred);
  return (-0.5 * (z.colwise().squaredNorm().array() + 3 * kLog2Pi + logDet)).transpose();
}

GaussianMixture fitFixedK(const Eigen::MatrixX3d& X, int k, const GmmOptions& o) {
  const int n = static_cast<int>(X.rows());
  std::mt19937_64 rng(o.seed);
  // k-means++ seeding.
  Eigen::MatrixX3d means(k, 3);
  means.row(0) = X.row(std::uniform_int_distribution<int>(0, n - 1)(rng));
  Eigen::VectorXd d2 = (X.rowwise() - means.row(0)).rowwise().squaredNorm();
  for (int c = 1; c < k; ++c) {
    const double total = d2.sum();
    int pick = 0;
    if (total > 0) {
      double r = std::uniform_real_distribution<double>(0, total)(rng);
      for (pick = 0; pick < n - 1 && r >= d2[pick]; ++pick) r -= d2[pick];
    }
    means.row(c) = X.row(pick);
    d2 = d2.cwiseMin((X.rowwise() - means.row(c)).rowwise().squaredNorm());
  }
  const double chroma = o.chromaFloor > 0 ? o.chromaFloor : o.covarianceFloor;
  const Eigen::Matrix3d floor = Eigen::Vector3d(o.covarianceFloor, chroma, chroma).asDiagonal();
  const Eigen::RowVector3d mu = X.colwise().mean();
  const Eigen::MatrixX3d Xc = X.rowwise() - mu;
  const Eigen::Matrix3d globalCov = Xc.transpose() * Xc / std::max(1, n) + floor;

  GaussianMixture g;
  g.weights = Eigen::VectorXd::Constant(k, 1.0 / k);
  g.means = means;
  g.covariances.assign(k, globalCov);
  Eigen::MatrixXd logR(n, k);
  double prev = -std::numeric_limits<double>::infinity();
  for (int it = 0; it < o.maxIterations; ++it) {
    // E step.
    for (int c = 0; c < k; ++c)
      logR.col(c) =
          logGaussian(X, g.means.row(c), g.covariances[c]).array() + std::log(g.weights[c]);
    double ll = 0;
    for (int i = 0; i < n; ++i) {
      const double lse = logSumExp(logR.row(i).transpose());
      logR.row(i).array() -= lse;
      ll += lse;
    }
    g.logLikelihood = ll;
    g.iterations = it + 1;
    if (ll / n - prev / n < o.tolerance && it > 0) break;
    prev = ll;
    // M step.
    const Eigen::MatrixXd R = logR.array().exp();
    for (int c = 0; c < k; ++c) {
      const double nk = R.col(c).sum();
      if (nk < 1e-9) {  // an empty component: restart it on the worst-explained sample
        int worst = 0;
        logR.rowwise().maxCoeff().minCoeff(&worst);
        g.means.row(c) = X.row(worst);
        g.covariances[c] = globalCov;
        g.weights[c] = 1.0 / n;
        continue;
      }
      g.weights[c] = nk / n;
      g.means.row(c) = (R.col(c).transpose() * X) / nk;
      const Eigen::MatrixX3d d = X.rowwise() - g.means.row(c);
      g.covariances[c] = (d.transpose() * R.col(c).asDiagonal() * d) / nk + floor;
    }
    g.weights /= g.weights.sum();
  }
  g.bic = -2 * g.logLikelihood + (10.0 * k - 1) * std::log(static_cast<double>(n));
  return g;
}

}  // namespace

Eigen::VectorXd GaussianMixture::logDensity(const Eigen::MatrixX3d& X) const {
  const int k = components();
  Eigen::MatrixXd l(X.rows(), k);
  for (int c = 0; c < k; ++c)
    l.col(c) = logGaussian(X, means.row(c), covariances[c]).array() + std::log(weights[c]);
  Eigen::VectorXd out(X.rows());
  for (int i = 0; i < X.rows(); ++i) out[i] = logSumExp(l.row(i).transpose());
  return out;
}

GaussianMixture fitGaussianMixture(const Eigen::MatrixX3d& X, const GmmOptions& o) {
  if (X.rows() == 0) throw InputError("colour model: no samples to fit (a region with no points)");
  if (!X.allFinite()) throw InputError("colour model: a sample colour is not finite");
  if (o.components < 0 || o.maxComponents < 1 || !(o.covarianceFloor > 0) ||
      !(o.chromaFloor >= 0) || o.maxIterations < 1)
    throw InputError(
        "colour model: components ≥ 0, maxComponents ≥ 1, maxIterations ≥ 1, "
        "covarianceFloor > 0 and chromaFloor ≥ 0 are required");
  const int n = static_cast<int>(X.rows());
  if (o.components > 0) {
    if (n < o.components)
      throw InputError("colour model: " + std::to_string(n) + " samples for " +
                       std::to_string(o.components) + " mixture components");
    return fitFixedK(X, o.components, o);
  }
  GaussianMixture best = fitFixedK(X, 1, o);
  for (int k = 2; k <= std::min(o.maxComponents, n / 10); ++k) {  // ≥ 10 samples per component
    GaussianMixture g = fitFixedK(X, k, o);
    if (g.bic < best.bic) best = std::move(g);
  }
  return best;
}

Eigen::VectorXd posteriorDisplacement(const std::vector<GaussianMixture>& models,
                                      const std::vector<bool>& positive,
                                      const Eigen::MatrixX3d& lab) {
  if (models.size() != positive.size() || models.empty())
    throw InputError("colour model: " + std::to_string(models.size()) + " label models but " +
                     std::to_string(positive.size()) + " side flags");
  const bool anyPos = std::find(positive.begin(), positive.end(), true) != positive.end();
  const bool anyNeg = std::find(positive.begin(), positive.end(), false) != positive.end();
  if (!anyPos || !anyNeg)
    throw InputError("colour model: labels on both sides of the boundary are needed");
  const int n = static_cast<int>(lab.rows()), m = static_cast<int>(models.size());
  Eigen::MatrixXd l(n, m);
  for (int j = 0; j < m; ++j) l.col(j) = models[j].logDensity(lab);
  Eigen::VectorXd phi(n);
  for (int i = 0; i < n; ++i) {
    const Eigen::VectorXd row = l.row(i).transpose();
    const double all = logSumExp(row);
    double p = 0;
    for (int j = 0; j < m; ++j)
      if (positive[j]) p += std::exp(row[j] - all);
    phi[i] = std::clamp(2 * (p - 0.5), -1.0, 1.0);
  }
  return phi;
}

Eigen::MatrixXd smoothOnSurface(const TriMesh& mesh, const Eigen::MatrixXd& values, double length,
                                int steps) {
  if (values.rows() != mesh.numVertices())
    throw InputError("surface smoothing: " + std::to_string(values.rows()) + " values for " +
                     std::to_string(mesh.numVertices()) + " vertices");
  if (!(length >= 0) || steps < 0)
    throw InputError("surface smoothing: length and steps must be non-negative");
  if (length == 0 || steps == 0) return values;
  const Eigen::SparseMatrix<double> M = massMatrix(mesh);
  SpdSolver solver;
  solver.compute(M + (length * length) * cotanLaplacian(mesh));
  Eigen::MatrixXd x = values;
  for (int s = 0; s < steps; ++s) x = solver.solve(Eigen::MatrixXd(M * x));
  return x;
}

std::vector<bool> sharedColours(const GaussianMixture& a, const GaussianMixture& b,
                                const Eigen::MatrixX3d& lab) {
  // Pairs of one colour: each mean inside the other's ellipsoid (a broad component of blends
  // that merely covers the other garment's colour is no pair).
  std::vector<std::pair<int, int>> pairs;
  for (int i = 0; i < a.components(); ++i)
    for (int j = 0; j < b.components(); ++j)
      if (insideComponent(a, i, b.means.row(j).transpose()) &&
          insideComponent(b, j, a.means.row(i).transpose()))
        pairs.emplace_back(i, j);
  std::vector<bool> out(static_cast<size_t>(lab.rows()), false);
  if (pairs.empty()) return out;
  for (int r = 0; r < lab.rows(); ++r) {
    const Eigen::Vector3d x = lab.row(r).transpose();
    for (const auto& [i, j] : pairs)
      if (insideComponent(a, i, x) && insideComponent(b, j, x)) {
        out[r] = true;
        break;
      }
  }
  return out;
}

GaussianMixture withoutBorrowedComponents(const GaussianMixture& model,
                                          const GaussianMixture& other, double maxShare,
                                          double* droppedWeight) {
  if (droppedWeight) *droppedWeight = 0;
  // Each component's distance (Mahalanobis², in other's nearest component) to other's colours.
  std::vector<std::pair<double, int>> explained;
  for (int k = 0; k < model.components(); ++k) {
    double best = std::numeric_limits<double>::infinity();
    for (int j = 0; j < other.components(); ++j)
      best = std::min(best, mahalanobis2(other, j, model.means.row(k).transpose()));
    if (best < kChi2Three95) explained.emplace_back(best, k);
  }
  // The best explained go first, while together they stay a minority: a broad other (a garment
  // spread over 20 L* by shading) can hold the region's own colour in its ellipsoid too, and
  // the strays are the components nearest its colours, not all it holds.
  std::sort(explained.begin(), explained.end());
  std::vector<bool> drop(model.components(), false);
  double dropped = 0;
  for (const auto& [distance, k] : explained) {
    if (dropped + model.weights[k] >= maxShare) break;
    dropped += model.weights[k];
    drop[k] = true;
  }
  std::vector<int> kept;
  for (int k = 0; k < model.components(); ++k)
    if (!drop[k]) kept.push_back(k);
  if (kept.size() == static_cast<size_t>(model.components())) return model;
  if (droppedWeight) *droppedWeight = dropped;
  GaussianMixture out = model;
  const int n = static_cast<int>(kept.size());
  out.weights.resize(n);
  out.means.resize(n, 3);
  out.covariances.clear();
  for (int i = 0; i < n; ++i) {
    out.weights[i] = model.weights[kept[i]] / (1 - dropped);
    out.means.row(i) = model.means.row(kept[i]);
    out.covariances.push_back(model.covariances[kept[i]]);
  }
  return out;
}

RegionColours fitRegionColours(const TriMesh& mesh, const Eigen::MatrixX3d& srgb,
                               const std::vector<std::vector<SurfacePoint>>& regions,
                               const ColourModelOptions& options) {
  validateMesh(mesh, "colour model mesh");
  if (srgb.rows() != mesh.numVertices() || !srgb.allFinite())
    throw InputError("colour model: the scan needs one finite sRGB colour per vertex (" +
                     std::to_string(srgb.rows()) + " colours for " +
                     std::to_string(mesh.numVertices()) +
                     " vertices); a scan without colour "
                     "cannot be segmented by colour");
  RegionColours out;
  out.lab = srgbToLab(Eigen::MatrixX3d(
      smoothOnSurface(mesh, srgb, options.colourSmoothing, options.smoothingSteps)));
  const Eigen::MatrixXd lab = out.lab;
  for (size_t r = 0; r < regions.size(); ++r) {
    const std::vector<SurfacePoint>& points = regions[r];
    if (points.empty())
      throw InputError("colour model: region " + std::to_string(r) + " has no points left");
    Eigen::MatrixX3d samples(static_cast<int>(points.size()), 3);
    for (size_t i = 0; i < points.size(); ++i) {
      const SurfacePoint& p = points[i];
      if (p.face < 0 || p.face >= mesh.numFaces())
        throw InputError("colour model: point " + std::to_string(i) + " of region " +
                         std::to_string(r) + " is on face " + std::to_string(p.face) +
                         ", outside the mesh");
      int corner = 0;
      p.bary.maxCoeff(&corner);
      samples.row(static_cast<int>(i)) = lab.row(mesh.F(p.face, corner));
    }
    GmmOptions g = options.gmm;
    g.seed = options.gmm.seed + r;
    out.models.push_back(fitGaussianMixture(samples, g));
    out.means.push_back(samples.colwise().mean().transpose());
    out.colours.push_back(std::move(samples));
  }
  return out;
}

double SkinModel::skinLikeFraction(const Eigen::MatrixX3d& lab) const {
  if (lab.rows() == 0) return 0;
  int n = 0;
  for (int i = 0; i < lab.rows(); ++i) n += deltaE2000(lab.row(i).transpose(), mean) < threshold;
  return static_cast<double>(n) / static_cast<double>(lab.rows());
}

Eigen::Vector3d medianColour(const Eigen::MatrixX3d& lab) {
  if (lab.rows() == 0) throw InputError("median colour: no colours");
  Eigen::Vector3d out;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> v(lab.col(c).data(), lab.col(c).data() + lab.rows());
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    out[c] = *mid;
  }
  return out;
}

SkinModel fitSkinModel(const Eigen::MatrixX3d& lab, double spreadFactor, double minDeltaE,
                       double maxDeltaE) {
  if (lab.rows() == 0 || !lab.allFinite())
    throw InputError("skin model: " + std::to_string(lab.rows()) +
                     " skin colour samples, or not finite; it needs at least one");
  // The samples within maxDeltaE of the median colour (all of them if none is).
  const Eigen::Vector3d centre = medianColour(lab);
  std::vector<int> kept;
  for (int i = 0; i < lab.rows(); ++i)
    if (deltaE2000(lab.row(i).transpose(), centre) <= maxDeltaE) kept.push_back(i);
  if (kept.empty())
    for (int i = 0; i < lab.rows(); ++i) kept.push_back(i);
  SkinModel m;
  for (const int i : kept) m.mean += lab.row(i).transpose();
  m.mean /= static_cast<double>(kept.size());
  std::vector<double> d;
  for (const int i : kept) d.push_back(deltaE2000(lab.row(i).transpose(), m.mean));
  const size_t k = std::min(d.size() - 1, static_cast<size_t>(0.9 * static_cast<double>(d.size())));
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(k), d.end());
  m.threshold = std::clamp(spreadFactor * d[k], minDeltaE, maxDeltaE);
  return m;
}

std::vector<bool> skinSamplesOfGarments(const Eigen::MatrixX3d& skin,
                                        const std::vector<GaussianMixture>& garments,
                                        double maxDeltaE) {
  std::vector<bool> out(static_cast<size_t>(skin.rows()), false);
  if (skin.rows() == 0) return out;
  const Eigen::Vector3d centre = medianColour(skin);
  for (int i = 0; i < skin.rows(); ++i) {
    const Eigen::Vector3d x = skin.row(i).transpose();
    if (deltaE2000(x, centre) <= maxDeltaE) continue;
    for (const GaussianMixture& g : garments)
      for (int k = 0; k < g.components() && !out[static_cast<size_t>(i)]; ++k)
        out[static_cast<size_t>(i)] = insideComponent(g, k, x);
  }
  return out;
}

Eigen::VectorXd smoothedDisplacement(const TriMesh& mesh,
                                     const std::vector<GaussianMixture>& models,
                                     const std::vector<bool>& positive, const Eigen::MatrixX3d& lab,
                                     const ColourModelOptions& options,
                                     const std::vector<bool>& neutral) {
  Eigen::VectorXd phi = posteriorDisplacement(models, positive, lab);
  if (!neutral.empty()) {
    if (neutral.size() != static_cast<size_t>(phi.size()))
      throw InputError("colour model: " + std::to_string(neutral.size()) + " neutral flags for " +
                       std::to_string(phi.size()) + " vertices");
    for (int v = 0; v < phi.size(); ++v)
      if (neutral[v]) phi[v] = 0;
  }
  // Clamped: the cotan Laplacian of a mesh with obtuse triangles can overshoot by a hair.
  return smoothOnSurface(mesh, phi, options.displacementSmoothing, options.smoothingSteps)
      .col(0)
      .cwiseMax(-1.0)
      .cwiseMin(1.0);
}

ColourDisplacement colourDisplacement(const TriMesh& mesh, const Eigen::MatrixX3d& srgb,
                                      const std::vector<ColourRegion>& regions,
                                      const ColourModelOptions& options) {
  std::vector<std::vector<SurfacePoint>> points;
  std::vector<bool> positive;
  for (const ColourRegion& r : regions) {
    points.push_back(r.points);
    positive.push_back(r.positive);
  }
  RegionColours fit = fitRegionColours(mesh, srgb, points, options);
  ColourDisplacement out;
  out.phiD = smoothedDisplacement(mesh, fit.models, positive, fit.lab, options);
  out.lab = std::move(fit.lab);
  out.models = std::move(fit.models);
  return out;
}

}  // namespace s2p
