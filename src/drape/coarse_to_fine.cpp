#include "drape/coarse_to_fine.h"

#include <fmt/format.h>

#include <chrono>
#include <numeric>

#include "core/error.h"
#include "core/uv_locator.h"

namespace s2p {

std::vector<Eigen::MatrixX3d> carryDrape(const DrapeInput& coarse,
                                         const std::vector<Eigen::MatrixX3d>& draped,
                                         const DrapeInput& fine, double* outside) {
  if (coarse.panels.size() != fine.panels.size() || draped.size() != coarse.panels.size())
    throw InputError(fmt::format(
        "drape: {} coarse panels ({} draped) for {} fine ones; the two resolutions must list the "
        "same panels",
        coarse.panels.size(), draped.size(), fine.panels.size()));
  std::vector<Eigen::MatrixX3d> out(fine.panels.size());
  double far = 0;
  for (size_t p = 0; p < fine.panels.size(); ++p) {
    const ClothPanel& c = coarse.panels[p];
    if (draped[p].rows() != c.numVertices())
      throw InputError(fmt::format("drape: coarse panel '{}' has {} vertices but {} draped", c.name,
                                   c.numVertices(), draped[p].rows()));
    const UvLocator locator(c.rest2d, c.F);
    Eigen::VectorXd distance;
    const std::vector<SurfacePoint> at = locator.locate(fine.panels[p].rest2d, &distance);
    Eigen::MatrixX3d& P = out[p];
    P.resize(static_cast<Eigen::Index>(at.size()), 3);
    for (size_t v = 0; v < at.size(); ++v) {
      P.row(static_cast<Eigen::Index>(v)).setZero();
      for (int k = 0; k < 3; ++k)
        P.row(static_cast<Eigen::Index>(v)) += at[v].bary[k] * draped[p].row(c.F(at[v].face, k));
    }
    if (distance.size() > 0) far = std::max(far, distance.maxCoeff());
  }
  if (outside) *outside = far;
  return out;
}

CoarseToFineDrape runDrapeCoarseToFine(const DrapeInput& fine, const DrapeInput& coarse,
                                       const DrapeOptions& options,
                                       const CoarseToFineOptions& c2f, Progress* progress) {
  const auto t0 = std::chrono::steady_clock::now();
  CoarseToFineDrape out;
  out.coarse = runDrape(coarse, options, progress, "coarse drape");
  auto finish = [&] {
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  };
  const bool nearlySewn = out.coarse.status == DrapeStatus::NotSettled && out.coarse.settled &&
                          out.coarse.maxStitchGap <= c2f.maxCarriedGap;
  if (out.coarse.status != DrapeStatus::Settled && !nearlySewn) {
    out.fine = out.coarse;
    for (std::string& w : out.fine.warnings) w = "coarse " + w;
    return finish();
  }
  DrapeInput start = fine;
  const std::vector<Eigen::MatrixX3d> carried =
      carryDrape(coarse, out.coarse.panels, fine, &out.carriedOutside);
  for (const ClothStitch& s : fine.stitches)
    out.carriedGap =
        std::max(out.carriedGap,
                 (carried[s.panelA].row(s.vertexA) - carried[s.panelB].row(s.vertexB)).norm());
  // Partners land on the coarse seam up to how the two outlines were sampled (a millimetre or
  // so): each group of vertices the stitches join (two, or four at a junction) starts at its
  // mean, sewn from the first step.
  std::vector<int> offset(fine.panels.size() + 1, 0);
  for (size_t p = 0; p < fine.panels.size(); ++p)
    offset[p + 1] = offset[p] + fine.panels[p].numVertices();
  std::vector<int> root(offset.back());
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](int v) {
    while (root[v] != v) v = root[v] = root[root[v]];
    return v;
  };
  for (const ClothStitch& s : fine.stitches)
    root[find(offset[s.panelA] + s.vertexA)] = find(offset[s.panelB] + s.vertexB);
  std::vector<Eigen::Vector3d> sum(root.size(), Eigen::Vector3d::Zero());
  std::vector<int> count(root.size(), 0);
  for (size_t p = 0; p < fine.panels.size(); ++p)
    for (int v = 0; v < fine.panels[p].numVertices(); ++v) {
      const int r = find(offset[p] + v);
      sum[r] += carried[p].row(v).transpose();
      ++count[r];
    }
  for (size_t p = 0; p < fine.panels.size(); ++p) {
    start.panels[p].start = carried[p];
    for (int v = 0; v < fine.panels[p].numVertices(); ++v) {
      const int r = find(offset[p] + v);
      if (count[r] > 1) start.panels[p].start.row(v) = (sum[r] / count[r]).transpose();
    }
  }
  DrapeOptions o = options;
  o.startsDraped = true;
  o.sewMaxSteps = c2f.fineSewSteps;
  o.sewSettleSteps = 0;
  o.drapeMinSteps = c2f.fineMinSteps;
  o.drapeMaxSteps = c2f.fineMaxSteps;
  if (c2f.fineSubsteps > 0) o.substeps = c2f.fineSubsteps;
  if (!c2f.fineGravity) o.gravity.setZero();
  if (c2f.fineDamping > 0) o.damping = c2f.fineDamping;
  out.fine = runDrape(start, o, progress, "fine drape");
  out.carried = true;
  return finish();
}

}  // namespace s2p
