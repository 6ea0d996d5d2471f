// Loop closing through the SLAM system (core/slam/loop_closer.h): a camera driven round a circle
// facing out at a ring of textured points comes back to where it started after one lap; the
// keyframes there see the first keyframes' places again without being joined to them.
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "core/geometry/sim3_solver.h"
#include "core/place/embedded/embedded_vocabulary.h"
#include "core/slam/local_mapper.h"
#include "core/slam/loop_closer.h"
#include "core/slam/system.h"
#include "tests/host/core/slam/synthetic_sequence.h"

namespace ale::slam {
namespace {

using geometry::SE3;
using geometry::SO3;
using geometry::Vec3;
using test::keypoints_seen;

constexpr double kPi = 3.14159265358979323846;

// The camera on a circle of radius 1 m, 4 cm a frame (157 frames a lap), looking out at points
// 3.5-5 m from the centre, 3 m high.
struct CircleSequence {
  geometry::Camera cam = test::pinhole();
  std::vector<Vec3> points;
  std::vector<features::Descriptor> truth;
  std::vector<SE3> T_cw;

  CircleSequence(std::uint64_t seed, int frames) {
    SplitMix64 g(seed);
    for (int i = 0; i < 4000; ++i) {
      const double phi = 2.0 * kPi * g.uniform_double();
      const double r = 3.5 + 1.5 * g.uniform_double();
      points.emplace_back(r * std::cos(phi), r * std::sin(phi), 3.0 * g.uniform_double() - 1.5);
      truth.push_back(test::random_descriptor(g));
    }
    for (int f = 0; f < frames; ++f) {
      const double theta = 0.04 * f;
      const Vec3 out(std::cos(theta), std::sin(theta), 0.0);
      geometry::Mat3 R_wc;
      R_wc.col(0) = Vec3(std::sin(theta), -std::cos(theta), 0.0);  // right
      R_wc.col(1) = Vec3(0.0, 0.0, -1.0);                           // down
      R_wc.col(2) = out;                                            // forward
      T_cw.push_back(SE3(SO3::from_matrix(R_wc), out).inverse());
    }
  }
  std::vector<map::KeyframeFeature> frame(int f, std::uint64_t noise_seed) const {
    SplitMix64 g(noise_seed * 7919 + static_cast<std::uint64_t>(f));
    return keypoints_seen(cam, T_cw[static_cast<std::size_t>(f)], points, truth, g);
  }
};

std::shared_ptr<const place::Vocabulary> builtin_vocabulary() {
  Result<place::Vocabulary> v = place::load_embedded_vocabulary();
  EXPECT_TRUE(v.ok()) << v.status().to_string();
  return v.ok() ? std::make_shared<place::Vocabulary>(std::move(*v)) : nullptr;
}

// RMS position error of the refined trajectory (the frames of map *only when given) after a
// Sim(3) alignment (m); nullopt (a test failure) with fewer than 3 frames or no alignment.
std::optional<double> sim3_ate(const SlamSystem& sys, const CircleSequence& seq, const std::uint32_t* only) {
  std::vector<Vec3> est, gt;
  for (const TrajectoryPose& p : sys.trajectory().poses()) {
    if (only && p.map_id != *only) continue;
    const int f = static_cast<int>(std::lround(p.timestamp_s / 0.1));
    est.push_back(p.T_cw.inverse().translation());
    gt.push_back(seq.T_cw[static_cast<std::size_t>(f)].inverse().translation());
  }
  EXPECT_GE(est.size(), 3u);
  if (est.size() < 3) return std::nullopt;
  Result<geometry::Sim3> S = geometry::umeyama(est, gt, true);
  EXPECT_TRUE(S.ok()) << S.status().to_string();
  if (!S.ok()) return std::nullopt;
  double sum = 0.0;
  for (std::size_t i = 0; i < est.size(); ++i) sum += (*S * est[i] - gt[i]).squaredNorm();
  return std::sqrt(sum / static_cast<double>(est.size()));
}

struct LoopRun {
  int frames = 0;
  int posed_after_init = 0, frames_after_init = 0;
  int resets = 0;
  int loops = 0;
  double loop_time_s = -1.0, loop_at_s = -1.0;
  double ate = 0.0;  // RMS position error of the refined trajectory after a Sim(3) alignment (m)
};

LoopRun run_circle(const CircleSequence& seq, int frames, bool loop_closing) {
  SlamParams params;
  params.loop_closing.enabled = loop_closing;
  auto created = SlamSystem::create(params, seq.cam, 8, 1.2f, builtin_vocabulary());
  EXPECT_TRUE(created.ok()) << created.status().to_string();
  LoopRun run;
  if (!created.ok()) return run;
  SlamSystem& sys = **created;
  sys.record_trajectory(true);
  bool initialised = false;
  for (int f = 0; f < frames; ++f) {
    Result<SlamReport> r = sys.process(0.1 * f, static_cast<std::uint64_t>(f), seq.frame(f, 3));
    EXPECT_TRUE(r.ok()) << r.status().to_string();
    if (!r.ok()) return run;
    initialised = initialised || r->has_pose;
    if (initialised) {
      ++run.frames_after_init;
      run.posed_after_init += r->has_pose ? 1 : 0;
    }
    if (r->loop.closed && run.loops == 0) {
      run.loop_time_s = r->loop.loop_time_s;
      run.loop_at_s = r->loop.time_s;
    }
    run.loops = r->loops_closed;
    run.resets = r->resets;
  }
  sys.resolve_trajectory();
  const std::optional<double> ate = sim3_ate(sys, seq, nullptr);
  if (!ate) return run;
  run.ate = *ate;
  run.frames = frames;
  return run;
}

// A lap and a quarter: the loop to the first keyframes is found and closed once, tracking never
// stops, and the trajectory is at least as good as without loop closing. With loop closing off
// no loop is looked for.
TEST(LoopClosing, ACircleDrivenOnceAndAQuarterClosesItsLoop) {
  const int frames = 200;
  const CircleSequence seq(17, frames);
  const LoopRun on = run_circle(seq, frames, true);
  const LoopRun off = run_circle(seq, frames, false);
  std::printf("loop closed at %.1f s to the place of %.1f s; ATE %.2f cm with loop closing, %.2f cm without\n",
              on.loop_at_s, on.loop_time_s, 100.0 * on.ate, 100.0 * off.ate);
  EXPECT_EQ(on.resets, 0);
  EXPECT_EQ(on.posed_after_init, on.frames_after_init);
  ASSERT_GE(on.loops, 1);
  // closed after the lap (15.7 s) to a keyframe of the lap's first seconds
  EXPECT_GT(on.loop_at_s, 15.0);
  EXPECT_LT(on.loop_time_s, 4.0);
  EXPECT_EQ(off.loops, 0);
  EXPECT_LE(on.ate, off.ate);
}

// Map merging: the camera sees nothing for 4 s two thirds of the way round (frames 100-139),
// longer than the lost timeout, so a new map starts; the light comes back facing points the first
// map never saw. On the second lap the new map's keyframes see the first map's places: the new
// map moves into the first one. The run ends in one map, with the first map's id, and the refined
// trajectory of the whole run (both maps' frames) is one frame: one Sim(3) aligns it. With
// merging off (max_maps 1) the same run ends in the second map and nothing is merged.
struct MergeRun {
  int resets = 0, merges = 0, merges_refused = 0;
  std::uint32_t first_map = 0, last_map = 0;
  std::size_t maps_held = 0;
  double ate = 0.0;
  bool ok = false;
};

MergeRun run_blackout_circle(const CircleSequence& seq, int frames, int max_maps,
                             bool (*dark)(int) = [](int f) { return f >= 100 && f < 140; }) {
  SlamParams params;
  params.loop_closing.max_maps = max_maps;
  auto created = SlamSystem::create(params, seq.cam, 8, 1.2f, builtin_vocabulary());
  EXPECT_TRUE(created.ok()) << created.status().to_string();
  MergeRun run;
  if (!created.ok()) return run;
  SlamSystem& sys = **created;
  sys.record_trajectory(true);
  bool posed = false;
  for (int f = 0; f < frames; ++f) {
    Result<SlamReport> r = sys.process(0.1 * f, static_cast<std::uint64_t>(f),
                                       dark(f) ? std::vector<map::KeyframeFeature>{} : seq.frame(f, 5));
    EXPECT_TRUE(r.ok()) << r.status().to_string();
    if (!r.ok()) return run;
    if (r->has_pose && !posed) run.first_map = r->map_id;
    posed = posed || r->has_pose;
    if (r->has_pose) {
      EXPECT_TRUE(r->T_cw.translation().allFinite()) << "frame " << f;
    }
    run.last_map = r->map_id;
    run.resets = r->resets;
    run.merges = r->merges;
    run.merges_refused = r->merges_refused;
  }
  run.maps_held = sys.map().stats().maps;
  sys.resolve_trajectory();
  const std::optional<double> ate = sim3_ate(sys, seq, &run.last_map);
  if (!ate) return run;
  run.ate = *ate;
  run.ok = true;
  return run;
}

TEST(LoopClosing, AMapStartedAfterABlackoutMergesIntoTheFirstWhenItsPlacesComeBack) {
  const int frames = 300;
  const CircleSequence seq(23, frames);
  const MergeRun on = run_blackout_circle(seq, frames, 3);
  const MergeRun off = run_blackout_circle(seq, frames, 1);
  ASSERT_TRUE(on.ok);
  ASSERT_TRUE(off.ok);
  std::printf("merged: %d merge(s), maps held %zu, ATE %.2f cm; without merging: last map %u, ATE %.2f cm of its part\n",
              on.merges, on.maps_held, 100.0 * on.ate, off.last_map, 100.0 * off.ate);
  EXPECT_EQ(on.resets, 1);
  EXPECT_EQ(on.merges, 1);
  EXPECT_EQ(on.merges_refused, 0);
  EXPECT_EQ(on.last_map, on.first_map);
  EXPECT_EQ(on.maps_held, 1u);
  // one frame for both maps' frames: the whole run within 5 cm of the truth on a 1 m circle
  EXPECT_LT(on.ate, 0.05);
  EXPECT_EQ(off.resets, 1);
  EXPECT_EQ(off.merges, 0);
  EXPECT_NE(off.last_map, off.first_map);
  EXPECT_EQ(off.maps_held, 1u);
}

// A map too small to keep (a few keyframes between two blackouts) is dropped without the kept
// map: the light comes back for 1.5 s between two dark spells, long enough for a small map that
// is lost again, and the first map is still there to merge into on the third lap.
TEST(LoopClosing, ASmallMapLostAgainIsDroppedAndTheKeptMapStays) {
  const int frames = 420;
  const CircleSequence seq(23, frames);
  const MergeRun run = run_blackout_circle(seq, frames, 3, [](int f) { return (f >= 100 && f < 140) || (f >= 155 && f < 190); });
  ASSERT_TRUE(run.ok);
  std::printf("resets %d, merges %d, maps held %zu\n", run.resets, run.merges, run.maps_held);
  EXPECT_GE(run.resets, 2) << "the small map was not started and lost";
  EXPECT_EQ(run.merges, 1);
  EXPECT_EQ(run.last_map, run.first_map);
  EXPECT_LT(run.ate, 0.05);
}

// Bad input: a keyframe the map or the database does not hold, an empty map: nothing is looked
// up, nothing moves, no crash.
TEST(LoopClosing, NothingToLookUpIsNotAnError) {
  const geometry::Camera cam = test::pinhole();
  const ScalePyramid pyramid = ScalePyramid::make(8, 1.2f);
  const ImageBounds bounds{0.0f, 0.0f, 752.0f, 480.0f};
  const map::MapCapacity capacity{16, 1000, 1000};
  map::MapStore map(capacity);
  const std::shared_ptr<const place::Vocabulary> vocabulary = builtin_vocabulary();
  ASSERT_TRUE(vocabulary);
  place::KeyframeDatabase places(*vocabulary, capacity);
  LocalMapper mapper(LocalMapperParams{}, cam, pyramid, bounds);
  LoopCloser closer(LoopCloserParams{}, cam, pyramid, bounds, MatcherParams{}, PoseRefinerParams{}, capacity);
  LoopReport r = closer.step(map::KeyframeId{}, map, places, false, mapper);
  EXPECT_FALSE(r.checked);
  EXPECT_FALSE(closer.moved());
  EXPECT_FALSE(closer.busy());
  // a keyframe in the map that the database has not been given
  std::vector<map::KeyframeFeature> f(10);
  const Result<map::KeyframeId> kf = map.add_keyframe(0.0, 0, SE3(), f.data(), 10);
  ASSERT_TRUE(kf.ok());
  r = closer.step(*kf, map, places, false, mapper);
  EXPECT_FALSE(r.checked);
  EXPECT_FALSE(closer.busy());
  EXPECT_EQ(closer.loops_closed(), 0);
}

}  // namespace
}  // namespace ale::slam
