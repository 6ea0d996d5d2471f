// The SLAM core's per-frame path allocates nothing once warmed up (counted by wrapping malloc and
// friends, tests/host/core/optim/alloc_counter.h):
// - frames that only track: undistortion, the motion model, the reference keyframe, the local map
//   and the keyframe decision reuse their buffers;
// - frames that insert a keyframe or run its deferred local BA: the local mapper's and the local
//   BA's buffers only grow (core/base/grow.h), to the largest problem seen. While a map's local BA
//   window still fills, a larger problem than any before grows them (printed, not asserted); a
//   second pass over the same frames after a reset meets no larger problem, and allocates nothing
//   on any frame.
#include <gtest/gtest.h>

#include <cstdio>
#include <vector>

#include "core/slam/system.h"
#include "tests/host/core/optim/alloc_counter.h"
#include "tests/host/core/slam/synthetic_sequence.h"

namespace ale::slam {
namespace {

constexpr int kFrames = 160;

struct Driver {
  test::Sequence seq{3, kFrames};
  std::vector<std::vector<map::KeyframeFeature>> frames;
  std::unique_ptr<SlamSystem> slam;
  double t_s = 0.0;

  Driver() {
    for (int f = 0; f < kFrames; ++f) frames.push_back(seq.frame(f, 1));
    Result<std::unique_ptr<SlamSystem>> created = SlamSystem::create(SlamParams{}, seq.cam, 8, 1.2f);
    EXPECT_TRUE(created.ok()) << created.status().to_string();
    if (created.ok()) slam = std::move(*created);
  }
  // Frame f of the sequence (timestamps keep increasing over passes).
  void step(int f) {
    t_s += 0.1;
    slam->finish_mapping();
    ASSERT_TRUE(slam->track_frame(t_s, static_cast<std::uint64_t>(f), frames[static_cast<std::size_t>(f)]).ok());
    slam->map_frame();
  }
};

bool maps(const SlamReport& r) { return r.keyframe_inserted || r.mapping.ba_keyframes > 0; }

TEST(SlamSystemAllocations, NoneAfterWarmUpOnFramesThatOnlyTrack) {
  const int n = kFrames, warm_up = 100;
  Driver run;
  ASSERT_TRUE(run.slam);
  SlamSystem& slam = *run.slam;
  auto step = [&](int f) { run.step(f); };
  for (int f = 0; f < warm_up; ++f) step(f);
  int tracking_frames = 0, mapping_frames = 0;
  long mapping_allocations = 0;
  for (int f = warm_up; f < n; ++f) {
    ale::test::AllocationCounter counter;
    step(f);
    const long count = counter.count();
    const SlamReport& r = slam.report();
    ASSERT_TRUE(r.has_pose) << "frame " << f;
    if (maps(r)) {
      ++mapping_frames;
      mapping_allocations += count;
      continue;
    }
    ++tracking_frames;
    EXPECT_EQ(count, 0) << "frame " << f << " only tracked";
  }
  EXPECT_GE(tracking_frames, 30);
  EXPECT_GE(mapping_frames, 3);
  std::printf("%d tracking frames without allocation; %d keyframe or local-BA frames with %ld allocations while the "
              "local BA window fills\n",
              tracking_frames, mapping_frames, mapping_allocations);
}

TEST(SlamSystemAllocations, NoneOnASecondPassAfterAReset) {
  Driver run;
  ASSERT_TRUE(run.slam);
  for (int f = 0; f < kFrames; ++f) run.step(f);
  ASSERT_TRUE(run.slam->report().has_pose);
  run.slam->reset();
  // The initialiser's frames (before the map exists again) are not counted: they are not the
  // tracker's or the local mapper's.
  const SlamReport& r = run.slam->report();
  int initialising = 0, mapping_frames = 0, tracked = 0;
  long init_allocations = 0, allocations = 0;
  for (int f = 0; f < kFrames; ++f) {
    const bool initialised = run.slam->state() == TrackingState::kTracking;
    ale::test::AllocationCounter counter;
    run.step(f);
    const long count = counter.count();
    if (!initialised) {
      ++initialising;
      init_allocations += count;
      continue;
    }
    EXPECT_EQ(count, 0) << "frame " << f << (maps(r) ? " (keyframe or local BA)" : "");
    allocations += count;
    mapping_frames += maps(r) ? 1 : 0;
    tracked += r.has_pose ? 1 : 0;
  }
  EXPECT_LE(initialising, 10);
  EXPECT_GE(mapping_frames, 10);
  EXPECT_GE(tracked, kFrames - 20);
  std::printf("second pass: %ld allocations over the %d frames after initialisation (%d tracked, %d with a keyframe or "
              "local BA); the %d initialisation frames made %ld\n",
              allocations, kFrames - initialising, tracked, mapping_frames, initialising, init_allocations);
}

}  // namespace
}  // namespace ale::slam
