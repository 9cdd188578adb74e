// Sleeves and trouser legs flattened as for a straight limb (beyond the paper, which flattens
// the scanned shape). A sleeve scanned on a bent arm is a bent tube: no flat panel follows its
// elbow (a bend θ puts ∫K⁺ = 2θ of curvature there, π at 90°: a quarter of a sphere's), and
// bent_arm's forearm came out with warp/weft strain p95 21.8 %. The cloth was cut for a
// straight arm and bends with it, so the pattern is made from the sleeve with the bend taken
// out: every panel vertex is carried by the skinning of the body fitted under the clothes (the
// weights of its closest body point) from the fitted pose to the same pose with the bent
// elbows and knees straight (their rest rotation).
#pragma once

#include <vector>

#include "pattern/flat_pattern.h"
#include "pattern/panels.h"

namespace s2p {

struct PosedFeatures;

struct LimbStraighteningOptions {
  // rad (20°): a joint bent less is left as scanned. An A-pose fit's elbows and knees stay under
  // it, and a bend that small puts ≤ 0.7 rad of curvature into the panel, which the warp/weft
  // refinement absorbs within the strain bound.
  double minBend = 0.35;
};

// One PanelReshape per panel of `panels` (empty V where no straightened joint moves it), or an
// empty vector when no elbow or knee bends more than minBend or the body came without a model.
std::vector<PanelReshape> straightenLimbs(const PanelsResult& panels, const PosedFeatures& body,
                                          const LimbStraighteningOptions& options = {});

}  // namespace s2p
