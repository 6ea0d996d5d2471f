// A GoogleTest fixture holding the real EuRoC keyframe pairs (euroc_keyframes.h: load, extract,
// select_pairs with the default PairSelection); skips (fails in CI) when the data is missing.
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "tests/host/core/geometry/euroc_keyframes.h"
#include "tests/host/support/test_data.h"

namespace ale::test {

class KeyframePairsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ALE_REQUIRE_DATA(dir, kEurocKeyframesDir);
    ALE_REQUIRE_DATA(yaml, kEurocCam0Yaml);
    const Status load = load_keyframe_pairs(dir, yaml, selection, &kf, &features, &pairs, &counts);
    ASSERT_TRUE(load.ok()) << load.to_string();
    ASSERT_FALSE(pairs.empty());
  }

  EurocKeyframes kf;
  PairSelection selection;
  PairCounts counts;
  std::vector<FrameFeatures> features;  // per keyframe
  std::vector<KeyframePair> pairs;
};

}  // namespace ale::test
