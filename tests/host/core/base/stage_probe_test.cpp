#include "core/base/stage_probe.h"

#include <gtest/gtest.h>

#include <set>

namespace ale {
namespace {

// The instruction counter tells the slots apart by address (symbol): a compiler or linker that
// folded the identical empty functions into one would merge the stages.
TEST(StageProbe, EverySlotIsItsOwnFunction) {
  std::set<StageProbe> seen;
  for (std::size_t i = 0; i < kStageProbeSlots; ++i) {
    ASSERT_NE(kStageProbes[i], nullptr) << i;
    EXPECT_TRUE(seen.insert(kStageProbes[i]).second) << "slot " << i << " shares its function";
  }
}

}  // namespace
}  // namespace ale
