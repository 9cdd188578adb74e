#include "core/polyline.h"

#include <algorithm>
#include <cstddef>

#include "core/error.h"

namespace s2p {

Eigen::MatrixX3d boxFilterClosedPolyline(const std::vector<Eigen::Vector3d>& points,
                                         double halfWidth) {
  const int n = static_cast<int>(points.size());
  Eigen::MatrixX3d out(n, 3);
  std::vector<double> s(n + 1, 0.0), edge(n);
  for (int i = 0; i < n; ++i) {
    edge[i] = (points[(i + 1) % n] - points[i]).norm();
    s[i + 1] = s[i] + edge[i];
  }
  const double length = s[n];
  if (!(halfWidth > 0) || !(length > 4 * halfWidth)) {
    for (int i = 0; i < n; ++i) out.row(i) = points[i].transpose();
    return out;
  }
  // The integral of the position over [a, b] of arc length, the loop unrolled three times
  // (a, b in [0, 3L)).
  const auto integral = [&](double a, double b) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3 * n; ++k) {
      const int i = k % n;
      const double s0 = s[i] + (k / n) * length, s1 = s0 + edge[i];
      const double lo = std::max(a, s0), hi = std::min(b, s1);
      if (hi <= lo || edge[i] <= 0) continue;
      const double mid = 0.5 * (lo + hi);
      sum += (hi - lo) * (points[i] + (mid - s0) / edge[i] * (points[(i + 1) % n] - points[i]));
    }
    return sum;
  };
  for (int i = 0; i < n; ++i) {
    const double a = s[i] - halfWidth + length;  // in the second turn
    out.row(i) = (integral(a, a + 2 * halfWidth) / (2 * halfWidth)).transpose();
  }
  return out;
}

std::vector<double> arcLengthShares(const std::vector<Eigen::Vector3d>& points, bool closed) {
  const size_t n = points.size();
  std::vector<double> share(n, 0.0);
  if (n < 2) return share;
  for (size_t i = 0; i < (closed ? n : n - 1); ++i) {
    const double d = (points[(i + 1) % n] - points[i]).norm();
    share[i] += 0.5 * d;
    share[(i + 1) % n] += 0.5 * d;
  }
  return share;
}

void mergeShortRuns(std::vector<int>& label, const std::vector<double>& share, bool closed,
                    double minLength) {
  const size_t n = label.size();
  if (share.size() != n)
    throw InputError("label runs: " + std::to_string(share.size()) + " lengths for " +
                     std::to_string(n) + " labels");
  struct Run {
    size_t first, count;
    double length;
  };
  while (true) {
    std::vector<Run> runs;
    for (size_t i = 0; i < n; ++i) {
      if (i == 0 || label[i] != label[i - 1]) runs.push_back({i, 0, 0.0});
      ++runs.back().count;
      runs.back().length += share[i];
    }
    if (closed && runs.size() > 1 && label[0] == label[n - 1]) {  // the run across the seam
      runs.front().length += runs.back().length;
      runs.front().count += runs.back().count;
      runs.front().first = runs.back().first;
      runs.pop_back();
    }
    if (runs.size() < 2) return;
    size_t shortest = 0;
    for (size_t r = 1; r < runs.size(); ++r)
      if (runs[r].length < runs[shortest].length) shortest = r;
    if (runs[shortest].length >= minLength) return;
    const size_t m = runs.size();
    const Run* prev = closed || shortest > 0 ? &runs[(shortest + m - 1) % m] : nullptr;
    const Run* next = closed || shortest + 1 < m ? &runs[(shortest + 1) % m] : nullptr;
    const Run* into = !prev ? next : !next ? prev : (prev->length >= next->length ? prev : next);
    const int to = label[into->first];
    for (size_t k = 0; k < runs[shortest].count; ++k) label[(runs[shortest].first + k) % n] = to;
  }
}

}  // namespace s2p
