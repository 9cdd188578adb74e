// The body sources the body tests run on: the built-in mannequin; the MPFB2 body when
// ../shared/bodymodels/mpfb2 (or $S2P_MPFB2_DIR) is present; and an SMPL-format model made
// from the mannequin's arrays and read back through the SMPL loader (real SMPL files are
// licensed and never shipped), so the SMPL path's joint names, canonical map and landmark
// rules are exercised on a body-shaped mesh.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "body/body_model.h"

namespace s2p::test {

struct BodySource {
  std::string name;
  std::shared_ptr<const BodyModel> model;
};

// Built once per test program (the mannequin at 8k vertices for speed).
const std::vector<BodySource>& bodySources();

}  // namespace s2p::test
