// Canonical-joint error between two body JSONs.
#include "eval/body_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace s2p {
namespace {

TEST(BodyMetrics, KnownOffsetsGiveExactMeanAndMax) {
  nlohmann::json truth, pred;
  truth["canonical"] = {{"pelvis", {0.0, 1.0, 0.0}},
                        {"head", {0.0, 1.6, 0.05}},
                        {"left_wrist", {0.3, 0.9, 0.0}},
                        {"right_ankle", {-0.1, 0.08, 0.0}}};
  pred["canonical"] = {{"pelvis", {0.0, 1.0, 0.0}},        // 0
                       {"head", {0.003, 1.6, 0.054}},      // 3-4-5: 5 mm
                       {"left_wrist", {0.3, 0.912, 0.0}},  // 12 mm
                       {"not_in_truth", {9.0, 9.0, 9.0}}};
  const BodyScore s = compareBodies(truth, pred);
  EXPECT_EQ(s.count, 3);
  EXPECT_NEAR(s.meanError, (0.0 + 0.005 + 0.012) / 3, 1e-12);
  EXPECT_NEAR(s.maxError, 0.012, 1e-12);
  EXPECT_EQ(s.worstJoint, "left_wrist");
  ASSERT_EQ(s.missing.size(), 1u);
  EXPECT_EQ(s.missing[0], "right_ankle");
}

TEST(BodyMetrics, BadBodiesAreInputErrors) {
  nlohmann::json truth, pred;
  truth["canonical"] = {{"pelvis", {0.0, 1.0, 0.0}}};
  EXPECT_THROW(compareBodies(truth, nlohmann::json::object()), InputError);
  pred["canonical"] = {{"head", {0.0, 1.0, 0.0}}};
  EXPECT_THROW(compareBodies(truth, pred), InputError);  // nothing in common
  pred["canonical"] = {{"pelvis", {0.0, 1.0}}};
  EXPECT_THROW(compareBodies(truth, pred), InputError);
  pred["canonical"] = {{"pelvis", "here"}};
  EXPECT_THROW(compareBodies(truth, pred), InputError);
  EXPECT_THROW(compareBodies(nlohmann::json(), truth), InputError);
}

}  // namespace
}  // namespace s2p
