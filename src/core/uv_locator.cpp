#include "core/uv_locator.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"

namespace s2p {
namespace {

// Barycentric weights of p in triangle abc (2D); false for a degenerate triangle.
bool barycentric2d(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                   const Eigen::Vector2d& c, Eigen::Vector3d& w) {
  const Eigen::Vector2d ab = b - a, ac = c - a, ap = p - a;
  const double det = ab.x() * ac.y() - ab.y() * ac.x();
  if (!(std::abs(det) > 0.0)) return false;
  const double wb = (ap.x() * ac.y() - ap.y() * ac.x()) / det;
  const double wc = (ab.x() * ap.y() - ab.y() * ap.x()) / det;
  w = Eigen::Vector3d(1.0 - wb - wc, wb, wc);
  return true;
}

Eigen::Vector3d lift(const Eigen::Vector2d& p) {
  return Eigen::Vector3d(p.x(), p.y(), 0.0);
}

}  // namespace

UvLocator::UvLocator(const Eigen::MatrixX2d& uv, const Eigen::MatrixX3i& F) : uv_(uv), F_(F) {
  const int nV = static_cast<int>(uv.rows()), nF = static_cast<int>(F.rows());
  if (nF == 0) throw InputError("UvLocator: the mesh has no faces");
  if (!uv.allFinite()) throw InputError("UvLocator: uv has non-finite coordinates");
  if (F.minCoeff() < 0 || F.maxCoeff() >= nV)
    throw InputError(fmt::format("UvLocator: a face index is outside [0, {})", nV));
  lo_ = uv.colwise().minCoeff().transpose();
  const Eigen::Vector2d hi = uv.colwise().maxCoeff().transpose();
  const Eigen::Vector2d extent = (hi - lo_).cwiseMax(1e-300);
  cell_ = std::max(std::sqrt(extent.x() * extent.y() / nF), extent.maxCoeff() / 4096.0);
  nx_ = std::max(1, static_cast<int>(extent.x() / cell_) + 1);
  ny_ = std::max(1, static_cast<int>(extent.y() / cell_) + 1);
  auto cellRange = [&](int f, int& x0, int& x1, int& y0, int& y1) {
    Eigen::Vector2d a = uv.row(F(f, 0)).transpose(), b = a;
    for (int k = 1; k < 3; ++k) {
      a = a.cwiseMin(uv.row(F(f, k)).transpose());
      b = b.cwiseMax(uv.row(F(f, k)).transpose());
    }
    x0 = std::clamp(static_cast<int>((a.x() - lo_.x()) / cell_), 0, nx_ - 1);
    x1 = std::clamp(static_cast<int>((b.x() - lo_.x()) / cell_), 0, nx_ - 1);
    y0 = std::clamp(static_cast<int>((a.y() - lo_.y()) / cell_), 0, ny_ - 1);
    y1 = std::clamp(static_cast<int>((b.y() - lo_.y()) / cell_), 0, ny_ - 1);
  };
  cellStart_.assign(static_cast<size_t>(nx_) * ny_ + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<int> fill;
    if (pass == 1) {
      for (size_t c = 0; c + 1 < cellStart_.size(); ++c) cellStart_[c + 1] += cellStart_[c];
      cellFaces_.resize(cellStart_.back());
      fill.assign(cellStart_.begin(), cellStart_.end() - 1);
    }
    for (int f = 0; f < nF; ++f) {
      Eigen::Vector3d w;
      if (!barycentric2d(Eigen::Vector2d::Zero(), uv.row(F(f, 0)), uv.row(F(f, 1)), uv.row(F(f, 2)),
                         w))
        continue;
      int x0, x1, y0, y1;
      cellRange(f, x0, x1, y0, y1);
      for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
          const size_t c = static_cast<size_t>(y) * nx_ + x;
          if (pass == 0)
            ++cellStart_[c + 1];
          else
            cellFaces_[fill[c]++] = f;
        }
    }
  }
}

SurfacePoint UvLocator::locate(const Eigen::Vector2d& p, double* distance) const {
  const int cx = std::clamp(static_cast<int>(std::floor((p.x() - lo_.x()) / cell_)), 0, nx_ - 1);
  const int cy = std::clamp(static_cast<int>(std::floor((p.y() - lo_.y()) / cell_)), 0, ny_ - 1);
  auto corner = [&](int f, int k) { return Eigen::Vector2d(uv_.row(F_(f, k)).transpose()); };
  // Inside test in p's cell: the face whose smallest weight is largest.
  SurfacePoint best;
  double bestInside = -std::numeric_limits<double>::infinity();
  const size_t c = static_cast<size_t>(cy) * nx_ + cx;
  for (int i = cellStart_[c]; i < cellStart_[c + 1]; ++i) {
    const int f = cellFaces_[i];
    Eigen::Vector3d w;
    if (!barycentric2d(p, corner(f, 0), corner(f, 1), corner(f, 2), w)) continue;
    if (w.minCoeff() > bestInside) bestInside = w.minCoeff(), best = SurfacePoint{f, w};
  }
  if (bestInside >= -1e-12) {
    if (distance) *distance = 0.0;
    return best;
  }
  // Outside every face: the closest point, searching rings of cells outwards until no unseen
  // cell can be nearer ((r − 1)·cell is a lower bound on the distance to ring r).
  double bestD = std::numeric_limits<double>::infinity();
  best = SurfacePoint{};
  const int maxRing = std::max(nx_, ny_);
  for (int r = 0; r <= maxRing; ++r) {
    if ((r - 1) * cell_ > bestD) break;
    for (int y = cy - r; y <= cy + r; ++y) {
      if (y < 0 || y >= ny_) continue;
      for (int x = cx - r; x <= cx + r; ++x) {
        if (x < 0 || x >= nx_) continue;
        if (std::max(std::abs(x - cx), std::abs(y - cy)) != r) continue;  // ring only
        const size_t cc = static_cast<size_t>(y) * nx_ + x;
        for (int i = cellStart_[cc]; i < cellStart_[cc + 1]; ++i) {
          const int f = cellFaces_[i];
          const Eigen::Vector3d a = lift(corner(f, 0)), b = lift(corner(f, 1)),
                                cv = lift(corner(f, 2));
          const Eigen::Vector3d w = closestPointBarycentric(lift(p), a, b, cv);
          const double d = (w(0) * a + w(1) * b + w(2) * cv - lift(p)).norm();
          if (d < bestD) bestD = d, best = SurfacePoint{f, w};
        }
      }
    }
  }
  if (distance) *distance = bestD;
  return best;
}

std::vector<SurfacePoint> UvLocator::locate(const Eigen::MatrixX2d& P,
                                            Eigen::VectorXd* distances) const {
  std::vector<SurfacePoint> out(P.rows());
  if (distances) distances->resize(P.rows());
  tbb::parallel_for(0, static_cast<int>(P.rows()), [&](int i) {
    double d = 0.0;
    out[i] = locate(P.row(i).transpose(), &d);
    if (distances) (*distances)(i) = d;
  });
  return out;
}

Eigen::MatrixXd interpolateAt(const std::vector<SurfacePoint>& locations, const Eigen::MatrixX3i& F,
                              const Eigen::MatrixXd& field) {
  Eigen::MatrixXd out(static_cast<int>(locations.size()), field.cols());
  for (size_t i = 0; i < locations.size(); ++i) {
    const SurfacePoint& s = locations[i];
    if (s.face < 0 || s.face >= F.rows())
      throw InputError(fmt::format("interpolateAt: location {} has face {} outside [0, {})", i,
                                   s.face, F.rows()));
    out.row(static_cast<int>(i)) = s.bary(0) * field.row(F(s.face, 0)) +
                                   s.bary(1) * field.row(F(s.face, 1)) +
                                   s.bary(2) * field.row(F(s.face, 2));
  }
  return out;
}

}  // namespace s2p
