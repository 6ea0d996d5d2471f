// The SLAM core's per-frame path allocates nothing once warmed up on frames that only track:
// undistortion, the motion model, the reference keyframe, the local map and the keyframe decision
// reuse their buffers (counted by wrapping malloc and friends, tests/host/core/optim/alloc_counter.h).
// Frames that insert a keyframe or run its deferred local BA still allocate while the local BA's
// buffers grow to the largest window seen so far (SchurSystem::analyse, BundleAdjuster::solve);
// their counts are printed, not asserted.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "core/slam/system.h"
#include "tests/host/core/optim/alloc_counter.h"
#include "tests/host/core/slam/synthetic_sequence.h"

namespace ale::slam {
namespace {

TEST(SlamSystemAllocations, NoneAfterWarmUpOnFramesThatOnlyTrack) {
  const int n = 160, warm_up = 100;
  const test::Sequence seq(3, n);
  std::vector<std::vector<map::KeyframeFeature>> frames;
  for (int f = 0; f < n; ++f) frames.push_back(seq.frame(f, 1));
  Result<std::unique_ptr<SlamSystem>> created = SlamSystem::create(SlamParams{}, seq.cam, 8, 1.2f);
  ASSERT_TRUE(created.ok()) << created.status().to_string();
  SlamSystem& slam = **created;
  auto step = [&](int f) {
    slam.finish_mapping();
    ASSERT_TRUE(slam.track_frame(0.1 * f, static_cast<std::uint64_t>(f), frames[static_cast<std::size_t>(f)]).ok());
    slam.map_frame();
  };
  for (int f = 0; f < warm_up; ++f) step(f);
  int tracking_frames = 0, mapping_frames = 0;
  long mapping_allocations = 0;
  for (int f = warm_up; f < n; ++f) {
    ale::test::AllocationCounter counter;
    step(f);
    const long count = counter.count();
    const SlamReport& r = slam.report();
    ASSERT_TRUE(r.has_pose) << "frame " << f;
    if (r.keyframe_inserted || r.mapping.ba_keyframes > 0) {
      ++mapping_frames;
      mapping_allocations += count;
      continue;
    }
    ++tracking_frames;
    EXPECT_EQ(count, 0) << "frame " << f << " only tracked";
  }
  EXPECT_GE(tracking_frames, 30);
  EXPECT_GE(mapping_frames, 3);
  std::printf("%d tracking frames without allocation; %d keyframe or local-BA frames with %ld allocations\n",
              tracking_frames, mapping_frames, mapping_allocations);
}

}  // namespace
}  // namespace ale::slam
