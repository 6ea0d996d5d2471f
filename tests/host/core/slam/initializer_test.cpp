#include "core/slam/initializer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "tests/host/core/slam/synthetic_scene.h"

namespace ale::slam {
namespace {

using test::Scene;

using test::frame_of;

// A sideways step with a little rotation: the general (fundamental-matrix) case.
TEST(Initializer, BuildsTheFirstTwoKeyframesFromASyntheticPair) {
  const geometry::SE3 T2(geometry::SO3::exp(geometry::Vec3(0.0, 0.03, 0.0)), geometry::Vec3(-0.25, 0.02, 0.0));
  Scene s(11, 400, 80, T2);
  map::MapStore map(map::MapCapacity{10, 2000, 1000});
  Initializer init(InitializerParams{}, s.cam, s.pyr);
  map::KeyframeId k1, k2;
  Frame f1 = frame_of(s.f1, 0.0, 0), f2 = frame_of(s.f2, 0.2, 6);
  InitReport r = init.add_frame(f1, map, &k1, &k2);
  EXPECT_EQ(r.state, InitState::kWaiting);
  r = init.add_frame(f2, map, &k1, &k2);
  ASSERT_EQ(r.state, InitState::kInitialized) << r.message;
  EXPECT_EQ(r.model, geometry::TwoViewModel::kFundamental);
  EXPECT_EQ(map.stats().keyframes, 2u);
  EXPECT_GT(r.landmarks, 200);
  EXPECT_EQ(static_cast<int>(map.stats().landmarks), r.landmarks);

  // relative pose: rotation and translation direction of the truth, scale by median depth 1
  const geometry::SE3 T21 = map.keyframe(k2)->T_cw * map.keyframe(k1)->T_cw.inverse();
  const double rot_err = (T21.so3().inverse() * T2.so3()).log().norm() * 180.0 / M_PI;
  EXPECT_LT(rot_err, 0.1);
  const double cos_dir = T21.translation().normalized().dot(T2.translation().normalized());
  EXPECT_GT(cos_dir, std::cos(1.0 * M_PI / 180.0));
  std::vector<double> depths;
  map.for_each_landmark([&](map::LandmarkId, const map::Landmark& lm) { depths.push_back(lm.p_w.z()); });
  std::nth_element(depths.begin(), depths.begin() + static_cast<std::ptrdiff_t>(depths.size() / 2), depths.end());
  EXPECT_NEAR(depths[depths.size() / 2], 1.0, 0.02);
  // the landmarks sit where the truth says, at the map's scale
  const double scale = T21.translation().norm() / T2.translation().norm();
  int checked = 0;
  for (int i = 0; i < f2.size(); ++i) {
    const map::Landmark* lm = map.landmark(f2.landmarks[static_cast<std::size_t>(i)]);
    if (!lm) continue;
    const int p = s.point_of_f2[static_cast<std::size_t>(i)];
    ASSERT_GE(p, 0);
    EXPECT_LT((lm->p_w / scale - s.points[static_cast<std::size_t>(p)]).norm(), 0.05 * s.points[static_cast<std::size_t>(p)].z());
    ++checked;
  }
  EXPECT_EQ(checked, r.landmarks);
  EXPECT_TRUE(f2.has_pose);
  // the keyframes see each other
  EXPECT_EQ(map.keyframe(k2)->parent, k1);
  EXPECT_GE(map.keyframe(k1)->num_covisible, 1);
}

// The quick look declines a pair whose parallax is far too small, which the full run declines
// too; a pair that initialises gives the same map with and without it.
TEST(Initializer, QuickLookDeclinesWhatTheFullRunDeclinesAndChangesNoMap) {
  const auto attempt = [](const geometry::SE3& T2, int probe_samples, map::MapStore& map, InitReport* r) {
    Scene s(21, 400, 80, T2);
    InitializerParams p;
    p.probe_samples = probe_samples;
    Initializer init(p, s.cam, s.pyr);
    map::KeyframeId k1, k2;
    Frame f1 = frame_of(s.f1, 0.0, 0), f2 = frame_of(s.f2, 0.2, 6);
    init.add_frame(f1, map, &k1, &k2);
    *r = init.add_frame(f2, map, &k1, &k2);
    return r->state == InitState::kInitialized ? map.keyframe(k2)->T_cw : geometry::SE3();
  };
  // a 2 cm step at depths of 2-8 m: about 0.3 deg of parallax (the minimum is 1 deg)
  const geometry::SE3 small(geometry::SO3::exp(geometry::Vec3(0.0, 0.01, 0.0)), geometry::Vec3(-0.02, 0.0, 0.0));
  map::MapStore m1(map::MapCapacity{10, 2000, 1000}), m2(map::MapCapacity{10, 2000, 1000});
  InitReport quick, full;
  attempt(small, 50, m1, &quick);
  attempt(small, 0, m2, &full);
  EXPECT_NE(quick.state, InitState::kInitialized);
  EXPECT_NE(quick.message.find("quick look"), std::string::npos) << quick.message;
  EXPECT_EQ(full.failure, geometry::TwoViewFailure::kLowParallax) << full.message;
  EXPECT_EQ(m1.stats().keyframes, 0u);

  const geometry::SE3 wide(geometry::SO3::exp(geometry::Vec3(0.0, 0.03, 0.0)), geometry::Vec3(-0.25, 0.02, 0.0));
  map::MapStore m3(map::MapCapacity{10, 2000, 1000}), m4(map::MapCapacity{10, 2000, 1000});
  const geometry::SE3 a = attempt(wide, 50, m3, &quick);
  const geometry::SE3 b = attempt(wide, 0, m4, &full);
  ASSERT_EQ(quick.state, InitState::kInitialized) << quick.message;
  ASSERT_EQ(full.state, InitState::kInitialized) << full.message;
  EXPECT_EQ(a.translation(), b.translation());
  EXPECT_EQ(a.rotation(), b.rotation());
  EXPECT_EQ(m3.stats().landmarks, m4.stats().landmarks);
}

TEST(Initializer, PureRotationDoesNotInitialise) {
  const geometry::SE3 T2(geometry::SO3::exp(geometry::Vec3(0.0, 0.06, 0.0)), geometry::Vec3::Zero());
  Scene s(12, 400, 80, T2);
  map::MapStore map(map::MapCapacity{10, 2000, 1000});
  Initializer init(InitializerParams{}, s.cam, s.pyr);
  map::KeyframeId k1, k2;
  Frame f1 = frame_of(s.f1, 0.0, 0), f2 = frame_of(s.f2, 0.2, 6);
  init.add_frame(f1, map, &k1, &k2);
  const InitReport r = init.add_frame(f2, map, &k1, &k2);
  EXPECT_NE(r.state, InitState::kInitialized);
  EXPECT_FALSE(r.message.empty());
  EXPECT_EQ(map.stats().keyframes, 0u);
  EXPECT_EQ(map.stats().landmarks, 0u);
}

TEST(Initializer, TooFewKeypointsOrMatchesStartsOver) {
  Scene s(13, 60, 10);
  map::MapStore map(map::MapCapacity{10, 2000, 1000});
  Initializer init(InitializerParams{}, s.cam, s.pyr);
  map::KeyframeId k1, k2;
  Frame f1 = frame_of(s.f1, 0.0, 0);
  EXPECT_EQ(init.add_frame(f1, map, &k1, &k2).state, InitState::kNeedReference);  // 70 keypoints
  Scene t(14, 400, 80);
  Scene u(15, 400, 80);  // unrelated descriptors: no matches
  Frame a = frame_of(t.f1, 1.0, 1), b = frame_of(u.f2, 1.1, 2);
  EXPECT_EQ(init.add_frame(a, map, &k1, &k2).state, InitState::kWaiting);
  const InitReport r = init.add_frame(b, map, &k1, &k2);
  EXPECT_EQ(r.state, InitState::kNeedReference);
  EXPECT_LT(r.matches, 100);
}

}  // namespace
}  // namespace ale::slam
