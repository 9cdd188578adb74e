#include "drape/coarse_to_fine.h"

#include <fmt/format.h>

#include <chrono>

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
                                       const CoarseToFineOptions& c2f) {
  const auto t0 = std::chrono::steady_clock::now();
  CoarseToFineDrape out;
  out.coarse = runDrape(coarse, options);
  auto finish = [&] {
    out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  };
  if (out.coarse.status != DrapeStatus::Settled) {
    out.fine = out.coarse;
    for (std::string& w : out.fine.warnings) w = "coarse " + w;
    return finish();
  }
  DrapeInput start = fine;
  const std::vector<Eigen::MatrixX3d> carried =
      carryDrape(coarse, out.coarse.panels, fine, &out.carriedOutside);
  for (size_t p = 0; p < start.panels.size(); ++p) start.panels[p].start = carried[p];
  for (const ClothStitch& s : fine.stitches)
    out.carriedGap = std::max(out.carriedGap, (carried[s.panelA].row(s.vertexA) -
                                               carried[s.panelB].row(s.vertexB))
                                                  .norm());
  DrapeOptions o = options;
  o.startsDraped = true;
  o.sewMaxSteps = c2f.fineSewSteps;
  o.sewSettleSteps = 0;
  o.drapeMinSteps = c2f.fineMinSteps;
  o.drapeMaxSteps = c2f.fineMaxSteps;
  out.fine = runDrape(start, o);
  out.carried = true;
  return finish();
}

}  // namespace s2p
