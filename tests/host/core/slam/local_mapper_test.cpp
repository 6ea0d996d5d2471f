// The local mapper on maps built by hand (exact projections of a field of points, every keypoint
// at level 0): a duplicate landmark is fused into the better-observed one, recent landmarks that
// are rarely found or seen by too few keyframes are culled, and keyframes whose landmarks are
// mostly seen by three others are culled, a keyframe with landmarks of its own kept.
#include "core/slam/keyframe_policy.h"
#include "core/slam/local_mapper.h"
#include "core/slam/map_ba.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "tests/host/core/slam/synthetic_scene.h"

namespace ale::slam {
namespace {

using map::KeyframeId;
using map::LandmarkId;
using test::SE3;
using test::SO3;
using test::Vec3;

// Points seen by every keyframe of the tests (cameras 0 to 0.6 m along x, looking down z).
struct World {
  geometry::Camera cam = test::pinhole();
  ScalePyramid pyr = ScalePyramid::make(8, 1.2f);
  ImageBounds bounds{0.0f, 0.0f, 752.0f, 480.0f};
  map::MapStore map{map::MapCapacity{}};
  std::vector<Vec3> points;
  std::vector<features::Descriptor> truth;
  std::vector<LandmarkId> landmark_of;  // per point

  explicit World(std::uint64_t seed, int n = 200) {
    SplitMix64 g(seed);
    for (int i = 0; i < n; ++i) {
      points.emplace_back(g.uniform_double() * 3.0 - 1.5, g.uniform_double() * 2.0 - 1.0, 4.0 + 2.0 * g.uniform_double());
      truth.push_back(test::random_descriptor(g));
    }
    landmark_of.resize(points.size());
  }

  static SE3 at(double x) { return SE3(SO3(), Vec3(-x, 0.0, 0.0)); }

  // Points hidden from the cameras added from now on: something else is seen where they project
  // (a keypoint with an unrelated descriptor).
  std::vector<bool> hidden;

  // The features of a camera at x: keypoint i is point i (exact projection), then `extra`.
  std::vector<map::KeyframeFeature> view(const SE3& T_cw, const std::vector<Vec3>& extra = {}) const {
    std::vector<map::KeyframeFeature> f;
    SplitMix64 occluder(static_cast<std::uint64_t>(1000.0 * T_cw.translation().norm()) + 17);
    auto add = [&](const Vec3& p, const features::Descriptor& d) {
      geometry::Vec2 uv;
      EXPECT_TRUE(cam.project(T_cw * p, &uv));
      EXPECT_TRUE(bounds.contains(static_cast<float>(uv.x()), static_cast<float>(uv.y())));
      map::KeyframeFeature k;
      k.u = static_cast<float>(uv.x());
      k.v = static_cast<float>(uv.y());
      k.descriptor = d;
      f.push_back(k);
    };
    for (std::size_t i = 0; i < points.size(); ++i)
      add(points[i], i < hidden.size() && hidden[i] ? test::random_descriptor(occluder) : truth[i]);
    SplitMix64 g(99);
    for (const Vec3& p : extra) add(p, test::random_descriptor(g));
    return f;
  }

  KeyframeId add_keyframe(double x, const std::vector<Vec3>& extra = {}) {
    const std::vector<map::KeyframeFeature> f = view(at(x), extra);
    Result<KeyframeId> kf = map.add_keyframe(x, static_cast<std::uint64_t>(x * 100), at(x), f.data(), static_cast<int>(f.size()));
    EXPECT_TRUE(kf.ok());
    return *kf;
  }

  // A landmark at p observed at keypoint `keypoint` of each keyframe.
  LandmarkId add_landmark(const Vec3& p, const features::Descriptor& d, const std::vector<KeyframeId>& seen_by, int keypoint) {
    Result<LandmarkId> lm = map.add_landmark(p, d, seen_by.front());
    EXPECT_TRUE(lm.ok());
    for (KeyframeId k : seen_by) EXPECT_TRUE(map.add_observation(*lm, k, keypoint).ok());
    map.update_descriptor(*lm);
    map.update_normal_and_depth(*lm, pyr.scale, pyr.levels);
    return *lm;
  }

  // Every point a landmark seen by `seen_by`; their covisibility updated.
  void add_landmarks(const std::vector<KeyframeId>& seen_by) {
    for (std::size_t i = 0; i < points.size(); ++i) landmark_of[i] = add_landmark(points[i], truth[i], seen_by, static_cast<int>(i));
    for (KeyframeId k : seen_by) map.update_connections(k);
  }

  // The frame behind a new keyframe at x, its keypoints matched to `matched` (invalid: unmatched).
  Frame frame(double x, const std::vector<LandmarkId>& matched, const std::vector<Vec3>& extra = {}) const {
    Frame f = test::frame_of(view(at(x), extra), x, static_cast<std::uint64_t>(x * 100));
    for (std::size_t i = 0; i < matched.size(); ++i) f.landmarks[i] = matched[i];
    f.T_cw = at(x);
    f.has_pose = true;
    return f;
  }
};

LocalMapperParams params(bool defer_ba, bool cull_keyframes) {
  LocalMapperParams p;
  p.defer_ba = defer_ba;
  p.cull_keyframes = cull_keyframes;
  return p;
}

TEST(LocalMapper, FusesADuplicateIntoTheBetterObservedLandmark) {
  World w(1);
  const KeyframeId k1 = w.add_keyframe(0.0), k2 = w.add_keyframe(0.2);
  w.add_landmarks({k1, k2});
  // The new keyframe also sees 30 points the others do not (keypoints of their own, descriptors
  // unlike any of theirs), each a landmark of its own: nothing to fuse them with.
  std::vector<Vec3> extra;
  SplitMix64 g(5);
  for (int i = 0; i < 30; ++i) extra.emplace_back(g.uniform_double() * 2.0 - 1.0, g.uniform_double() - 0.5, 4.5);
  const KeyframeId k3 = w.add_keyframe(0.4, extra);
  // Tracking matched the new keyframe's keypoints to the map, except that every fifth point was
  // matched to a landmark of its own: a duplicate 1 mm off, a few descriptor bits apart.
  const std::size_t n = w.points.size();
  std::vector<LandmarkId> matched = w.landmark_of, unique;
  std::vector<int> duplicated;
  for (std::size_t i = 0; i < n; i += 5) {
    duplicated.push_back(static_cast<int>(i));
    Result<LandmarkId> d = w.map.add_landmark(w.points[i] + Vec3(0.001, 0.0, 0.0), test::perturbed(w.truth[i], g, 5), k3);
    ASSERT_TRUE(d.ok());
    matched[i] = *d;
  }
  for (std::size_t i = 0; i < extra.size(); ++i) {
    Result<LandmarkId> d = w.map.add_landmark(extra[i], w.map.features(k3)[n + i].descriptor, k3);
    ASSERT_TRUE(d.ok());
    matched.push_back(*d);
    unique.push_back(*d);
  }
  const std::vector<LandmarkId> own = matched;
  LocalMapper mapper(params(true, false), w.cam, w.pyr, w.bounds);
  const MappingReport r = mapper.process(k3, w.frame(0.4, matched, extra), w.map);
  EXPECT_EQ(r.observations_added, static_cast<int>(n + extra.size()));
  EXPECT_EQ(r.landmarks_fused, static_cast<int>(duplicated.size()));
  const LandmarkId* at_k3 = w.map.keypoint_landmarks(k3);
  for (int i : duplicated) {
    EXPECT_EQ(w.map.landmark(own[static_cast<std::size_t>(i)]), nullptr) << "the duplicate of point " << i << " is gone";
    EXPECT_EQ(at_k3[i], w.landmark_of[static_cast<std::size_t>(i)]) << "point " << i;
    EXPECT_EQ(w.map.landmark(w.landmark_of[static_cast<std::size_t>(i)])->num_observations, 3);
  }
  for (std::size_t i = 0; i < unique.size(); ++i) {
    ASSERT_NE(w.map.landmark(unique[i]), nullptr) << "extra point " << i;
    EXPECT_EQ(w.map.landmark(unique[i])->num_observations, 1);
    EXPECT_EQ(at_k3[n + i], unique[i]);
  }
  EXPECT_EQ(w.map.stats().landmarks, n + extra.size());
}

TEST(LocalMapper, CullsRecentLandmarksRarelyFoundOrSeenByTooFewKeyframes) {
  World w(2);
  const KeyframeId k1 = w.add_keyframe(0.0), k2 = w.add_keyframe(0.2);
  w.add_landmarks({k1, k2});
  LocalMapper mapper(params(true, false), w.cam, w.pyr, w.bounds);
  for (LandmarkId l : w.landmark_of) mapper.add_recent(l, k1);  // as after initialisation
  // every fourth point: in view of 20 frames, found in 2 (below min_found_ratio 0.25), and not
  // matched by the next keyframe
  std::vector<LandmarkId> matched = w.landmark_of, rare, unmatched_later;
  for (std::size_t i = 0; i < w.points.size(); ++i) {
    if (i % 4 == 0) {
      map::Landmark* lm = w.map.landmark(w.landmark_of[i]);
      lm->visible = 20;
      lm->found = 2;
      rare.push_back(w.landmark_of[i]);
      matched[i] = LandmarkId{};
    } else if (i % 4 == 1) {
      unmatched_later.push_back(w.landmark_of[i]);
    }
  }
  const KeyframeId k3 = w.add_keyframe(0.4);
  const MappingReport r3 = mapper.process(k3, w.frame(0.4, matched), w.map);
  EXPECT_EQ(r3.landmarks_culled, static_cast<int>(rare.size()));
  for (LandmarkId l : rare) EXPECT_EQ(w.map.landmark(l), nullptr);
  for (LandmarkId l : unmatched_later) EXPECT_NE(w.map.landmark(l), nullptr) << "found often: kept for now";

  // Tracking at k4 misses the second group: they have the three observations of k1, k2 and k3
  // (the fusion may add k4's), more than the two the culling looks for, and stay.
  for (std::size_t i = 1; i < w.points.size(); i += 4) matched[i] = LandmarkId{};
  const KeyframeId k4 = w.add_keyframe(0.6);
  const MappingReport r4 = mapper.process(k4, w.frame(0.6, matched), w.map);
  for (LandmarkId l : unmatched_later) {
    ASSERT_NE(w.map.landmark(l), nullptr);
    EXPECT_GE(w.map.landmark(l)->num_observations, 3);
  }
  EXPECT_EQ(r4.landmarks_culled, 0) << "every recent landmark has three observations or more";
}

TEST(LocalMapper, CullsRecentLandmarksThatStayWithTwoObservations) {
  World w(3);
  const KeyframeId k1 = w.add_keyframe(0.0), k2 = w.add_keyframe(0.2);
  w.add_landmarks({k1, k2});
  LocalMapper mapper(params(true, false), w.cam, w.pyr, w.bounds);
  for (LandmarkId l : w.landmark_of) mapper.add_recent(l, k1);
  // every third point is hidden from the next keyframes: two keyframes later it has only its
  // first two observations
  std::vector<LandmarkId> matched = w.landmark_of, lonely;
  w.hidden.assign(w.points.size(), false);
  for (std::size_t i = 0; i < w.points.size(); i += 3) {
    lonely.push_back(w.landmark_of[i]);
    matched[i] = LandmarkId{};
    w.hidden[i] = true;
  }
  const KeyframeId k3 = w.add_keyframe(0.4);
  const MappingReport r3 = mapper.process(k3, w.frame(0.4, matched), w.map);
  EXPECT_EQ(r3.landmarks_culled, 0) << "one keyframe after: not yet";
  for (LandmarkId l : lonely) ASSERT_NE(w.map.landmark(l), nullptr);
  const KeyframeId k4 = w.add_keyframe(0.6);
  const MappingReport r4 = mapper.process(k4, w.frame(0.6, matched), w.map);
  EXPECT_EQ(r4.landmarks_culled, static_cast<int>(lonely.size()));
  for (LandmarkId l : lonely) EXPECT_EQ(w.map.landmark(l), nullptr);
  for (std::size_t i = 0; i < w.points.size(); ++i) {
    if (i % 3 != 0) {
      EXPECT_NE(w.map.landmark(w.landmark_of[i]), nullptr) << "point " << i << " was matched";
    }
  }
}

// Five keyframes on one field of points: k2 and k4 (after k2 went) have every landmark seen by
// three others at the same level, so they are culled (in id order); k3 has half as many again
// that only the new keyframe sees too and stays; the first keyframe (the root) and the new one
// are never culled.
TEST(LocalMapper, CullsKeyframesWhoseLandmarksOthersSeeAndKeepsTheRest) {
  for (bool cull : {true, false}) {
    World w(4);
    std::vector<Vec3> own;
    SplitMix64 g(8);
    for (int i = 0; i < 100; ++i) own.emplace_back(g.uniform_double() * 2.0 - 1.0, g.uniform_double() - 0.5, 5.0);
    const KeyframeId k1 = w.add_keyframe(0.0), k2 = w.add_keyframe(0.1), k3 = w.add_keyframe(0.2, own),
                     k4 = w.add_keyframe(0.3);
    w.add_landmarks({k1, k2, k3, k4});
    // k3's own points are seen by the new keyframe too (a landmark needs two observations to
    // survive the local BA)
    std::vector<LandmarkId> matched = w.landmark_of;
    for (std::size_t i = 0; i < own.size(); ++i) {
      const int keypoint = static_cast<int>(w.points.size() + i);
      matched.push_back(w.add_landmark(own[i], w.map.features(k3)[keypoint].descriptor, {k3}, keypoint));
    }
    w.map.update_connections(k3);
    const KeyframeId k5 = w.add_keyframe(0.4, own);
    LocalMapper mapper(params(false, cull), w.cam, w.pyr, w.bounds);
    const MappingReport r = mapper.process(k5, w.frame(0.4, matched, own), w.map);
    SCOPED_TRACE(cull ? "culling on" : "culling off");
    EXPECT_GT(r.ba_keyframes, 0) << "the local BA ran before the culling";
    EXPECT_EQ(r.keyframes_culled, cull ? 2 : 0);
    EXPECT_NE(w.map.keyframe(k1), nullptr);
    EXPECT_EQ(w.map.keyframe(k2) == nullptr, cull);
    EXPECT_NE(w.map.keyframe(k3), nullptr);
    EXPECT_EQ(w.map.keyframe(k4) == nullptr, cull);
    EXPECT_NE(w.map.keyframe(k5), nullptr);
    EXPECT_EQ(w.map.stats().keyframes, cull ? 3u : 5u);
  }
}

// With defer_ba the keyframe's local BA and culling wait for finish_pending(), which reports them.
TEST(LocalMapper, DeferredKeyframeCullingRunsInFinishPending) {
  World w(5);
  const KeyframeId k1 = w.add_keyframe(0.0), k2 = w.add_keyframe(0.1), k3 = w.add_keyframe(0.2), k4 = w.add_keyframe(0.3);
  w.add_landmarks({k1, k2, k3, k4});
  const KeyframeId k5 = w.add_keyframe(0.4);
  LocalMapper mapper(params(true, true), w.cam, w.pyr, w.bounds);
  const MappingReport now = mapper.process(k5, w.frame(0.4, w.landmark_of), w.map);
  EXPECT_EQ(now.keyframes_culled, 0);
  EXPECT_EQ(now.ba_keyframes, 0);
  EXPECT_TRUE(mapper.has_pending());
  EXPECT_EQ(w.map.stats().keyframes, 5u);
  const MappingReport later = mapper.finish_pending(w.map);
  EXPECT_FALSE(mapper.has_pending());
  EXPECT_GT(later.ba_keyframes, 0);
  // k2 and k3 go (every landmark seen by four others, then three); k4 keeps k1, k4 and k5's three
  EXPECT_EQ(later.keyframes_culled, 2);
  EXPECT_EQ(w.map.keyframe(k2), nullptr);
  EXPECT_EQ(w.map.keyframe(k3), nullptr);
  EXPECT_NE(w.map.keyframe(k4), nullptr);
}

// The odometry holds a window's scale across a stretch without keyframes (the dark, a bare wall:
// 8 s here, the camera tracking on). Two keyframes 0.6 m apart by the odometry, the map built at
// 0.75 of that scale (every projection the same): the reprojections cannot tell, the prior on the
// second keyframe's centre puts it back at 0.6 m. Beyond keyframe_prior_max_span_s there is no
// prior and the map stays at the scale it had.
TEST(MapBundleAdjustment, TheOdometryHoldsTheScaleAcrossALongStretchWithoutKeyframes) {
  World w(6);
  constexpr double kBaseline = 0.6, kMapScale = 0.75, kGap = 8.0;
  auto solve = [&](const OdometryParams& odometry, int* priors) {
    map::MapStore map{map::MapCapacity{}};
    const std::vector<map::KeyframeFeature> f1 = w.view(World::at(0.0)), f2 = w.view(World::at(kBaseline));
    const KeyframeId k1 = *map.add_keyframe(100.0, 1, World::at(0.0), f1.data(), static_cast<int>(f1.size()));
    const KeyframeId k2 =
        *map.add_keyframe(100.0 + kGap, 2, World::at(kMapScale * kBaseline), f2.data(), static_cast<int>(f2.size()));
    map.keyframe(k1)->has_odometry = true;
    map.keyframe(k2)->has_odometry = true;
    map.keyframe(k2)->odometry_x_m = kBaseline;  // the base drove straight on (x forward)
    for (std::size_t i = 0; i < w.points.size(); ++i) {
      const LandmarkId lm = *map.add_landmark(kMapScale * w.points[i], w.truth[i], k1);
      EXPECT_TRUE(map.add_observation(lm, k1, static_cast<int>(i)).ok());
      EXPECT_TRUE(map.add_observation(lm, k2, static_cast<int>(i)).ok());
    }
    MapBundleAdjustment ba(w.cam, w.pyr);
    ba.reset(map);
    EXPECT_TRUE(ba.add_keyframe(k1, true));
    EXPECT_TRUE(ba.add_keyframe(k2, false));
    for (int j = 0; j < static_cast<int>(w.points.size()); ++j) ba.add_landmark(map.keypoint_landmarks_of(k1)[j]);
    *priors = ba.add_odometry_priors(odometry);
    optim::BaOptions options;
    options.lm.max_iterations = 20;
    EXPECT_TRUE(MapBundleAdjustment::usable(ba.solve(options)));
    ba.write_back(map);
    return map.keyframe(k2)->T_cw.inverse().translation().x();
  };
  OdometryParams odometry;
  odometry.T_bc = SE3();  // the camera's x axis along the base's: it drives along its own x
  int priors = 0;
  const double held = solve(odometry, &priors);
  EXPECT_EQ(priors, 1);
  EXPECT_NEAR(held, kBaseline, 0.005) << "the odometry's 0.6 m";
  odometry.keyframe_prior_max_span_s = kGap - 1.0;
  const double free = solve(odometry, &priors);
  EXPECT_EQ(priors, 0);
  EXPECT_NEAR(free, kMapScale * kBaseline, 0.005) << "nothing else fixes the scale";
}

// The local BA of keyframes that share no landmark with older ones (made in a turn in the dark)
// holds them to the odometry from the keyframe before them, which joins the problem fixed: here the
// two new keyframes and their landmarks sit 0.2 m off where the odometry puts them, consistently
// (nothing in the images says so), and the first is brought back. Without that keyframe nothing is
// fixed and both stay off.
TEST(LocalMapper, KeyframesSharingNothingWithOlderOnesAreHeldByTheOdometryBeforeThem) {
  World w(8);
  constexpr double kOff = 0.2;
  const int n = static_cast<int>(w.points.size());
  auto add = [&](double x, double t, std::uint64_t seq, double off) {
    const std::vector<map::KeyframeFeature> f = w.view(World::at(x));
    const KeyframeId k = *w.map.add_keyframe(t, seq, World::at(x + off), f.data(), n);
    w.map.keyframe(k)->has_odometry = true;
    w.map.keyframe(k)->odometry_x_m = x;  // the base drove straight on (x forward)
    return k;
  };
  const KeyframeId k0 = add(0.0, 100.0, 1, 0.0);
  const KeyframeId k1 = add(0.3, 101.0, 2, kOff);
  const KeyframeId k2 = add(0.6, 102.0, 3, kOff);
  for (std::size_t i = 0; i < w.points.size(); ++i)
    w.landmark_of[i] = w.add_landmark(w.points[i] + Vec3(kOff, 0.0, 0.0), w.truth[i], {k1}, static_cast<int>(i));
  Frame frame = test::frame_of(w.view(World::at(0.6)), 102.0, 3);
  for (std::size_t i = 0; i < w.landmark_of.size(); ++i) frame.landmarks[i] = w.landmark_of[i];
  frame.T_cw = World::at(0.6 + kOff);
  frame.has_pose = true;
  OdometryParams odometry;
  odometry.T_bc = SE3();  // the camera's x axis along the base's: it drives along its own x
  LocalMapper mapper(params(false, false), w.cam, w.pyr, w.bounds);
  mapper.set_odometry(&odometry);
  const MappingReport r = mapper.process(k2, frame, w.map);
  EXPECT_EQ(r.ba_keyframes, 2);
  EXPECT_EQ(r.ba_fixed, 1) << "the keyframe before them";
  EXPECT_EQ(w.map.keyframe(k0)->T_cw.translation(), World::at(0.0).translation()) << "fixed";
  // each prior's target is the earlier keyframe where it stands when the problem is built: k1 is
  // held from k0, k2 from k1 where k1 was (the next BA takes it from k1's new pose)
  EXPECT_NEAR(w.map.keyframe(k1)->T_cw.inverse().translation().x(), 0.3, 0.01);
}

// The keyframe rule of a known place: back on the line of sight of a reference keyframe made more
// than revisit_age_s ago (at most revisit_radius_depths of its median depth, about 5 m here, aside
// of it: 0.25 m), a frame tracking 150 of its 200 landmarks makes no keyframe (the map holds the
// place); the same frame 0.6 m aside (the next cleaning lane) or soon after the reference does
// (ref_ratio 0.9).
TEST(KeyframePolicy, AKnownPlaceIsWhereTheReferenceWasMadeLongAgo) {
  World w(7);
  const KeyframeId k1 = w.add_keyframe(0.0), k2 = w.add_keyframe(0.1), k3 = w.add_keyframe(0.2), k4 = w.add_keyframe(0.3);
  w.add_landmarks({k1, k2, k3, k4});
  KeyframePolicyParams p;
  p.revisit_age_s = 10.0;
  KeyframePolicy policy(p);
  policy.reserve(1000);
  for (int i = 0; i < p.min_frames; ++i) policy.frame_arrived();
  constexpr int kInliers = 150;
  EXPECT_FALSE(policy.needs_keyframe(kInliers, w.map, k1, 20.0, Vec3(0.1, 0.0, 0.0))) << "a known place";
  EXPECT_FALSE(policy.needs_keyframe(kInliers, w.map, k1, 20.0, Vec3(0.1, 0.0, -1.0))) << "1 m behind, on the path";
  EXPECT_TRUE(policy.needs_keyframe(kInliers, w.map, k1, 20.0, Vec3(0.6, 0.0, 0.0))) << "the next lane";
  EXPECT_TRUE(policy.needs_keyframe(kInliers, w.map, k1, 5.0, Vec3(0.1, 0.0, 0.0))) << "not long ago";
  EXPECT_TRUE(policy.needs_keyframe(90, w.map, k1, 20.0, Vec3(0.1, 0.0, 0.0))) << "the view has changed enough";
  p.revisit_radius_depths = 0.2;
  KeyframePolicy wide(p);
  for (int i = 0; i < p.min_frames; ++i) wide.frame_arrived();
  EXPECT_FALSE(wide.needs_keyframe(kInliers, w.map, k1, 20.0, Vec3(0.6, 0.0, 0.0))) << "within 0.2 depths";
}

}  // namespace
}  // namespace ale::slam
