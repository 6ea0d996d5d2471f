#include "core/slam/refined_trajectory.h"

#include <gtest/gtest.h>

#include <vector>

namespace ale::slam {
namespace {

using geometry::SE3;
using geometry::SO3;
using geometry::Vec3;

SE3 pose_at(double x, double yaw = 0.0) { return SE3(SO3::exp(Vec3(0.0, yaw, 0.0)), Vec3(-x, 0.0, 0.0)); }

// Three keyframes in a spanning-tree chain k0 <- k1 <- k2 (each sharing landmarks with the next).
struct ChainMap {
  map::MapStore m{map::MapCapacity{8, 100, 64}};
  map::KeyframeId k[3];
  ChainMap() {
    std::vector<map::KeyframeFeature> f(40);
    for (int i = 0; i < 3; ++i) k[i] = *m.add_keyframe(0.1 * i, static_cast<std::uint64_t>(i), pose_at(0.1 * i, 0.05 * i), f.data(), 40);
    for (int i = 0; i < 2; ++i) {
      for (int kp = 0; kp < 20; ++kp) {
        const map::LandmarkId l = *m.add_landmark(Vec3(0.0, 0.0, 2.0), features::Descriptor{}, k[i]);
        EXPECT_TRUE(m.add_observation(l, k[i], 20 * i + kp).ok());
        EXPECT_TRUE(m.add_observation(l, k[i + 1], kp).ok());
      }
    }
    for (map::KeyframeId id : k) m.update_connections(id);
  }
};

double distance(const SE3& a, const SE3& b) { return (a.inverse() * b).log().norm(); }

TEST(RefinedTrajectory, FramesFollowTheirKeyframesFinalPoses) {
  ChainMap c;
  ASSERT_EQ(c.m.keyframe(c.k[2])->parent, c.k[1]);
  RefinedTrajectory t;
  const SE3 T_cw = pose_at(0.25, 0.1);
  t.add(1.0, 7, c.k[2], T_cw, c.m);
  const SE3 T_cr = T_cw * c.m.keyframe(c.k[2])->T_cw.inverse();
  // a later bundle adjustment moves the keyframe: the frame moves with it
  c.m.keyframe(c.k[2])->T_cw = pose_at(0.3, 0.12);
  t.resolve(c.m);
  ASSERT_EQ(t.poses().size(), 1u);
  EXPECT_TRUE(t.poses()[0].refined);
  EXPECT_EQ(t.poses()[0].sequence, 7u);
  EXPECT_LT(distance(t.poses()[0].T_cw, T_cr * c.m.keyframe(c.k[2])->T_cw), 1e-12);
}

TEST(RefinedTrajectory, ACulledKeyframeIsReplacedByItsParentThroughTheirRelativePose) {
  ChainMap c;
  RefinedTrajectory t;
  const SE3 T_cw = pose_at(0.22, 0.07);
  t.add(1.0, 1, c.k[2], T_cw, c.m);
  const SE3 T_21 = c.m.keyframe(c.k[2])->T_cw * c.m.keyframe(c.k[1])->T_cw.inverse();
  std::vector<map::ErasedKeyframe> erased;
  c.m.erase_keyframe(c.k[2]);
  c.m.take_erased(erased);
  ASSERT_EQ(erased.size(), 1u);
  EXPECT_EQ(erased[0].id, c.k[2]);
  EXPECT_EQ(erased[0].parent, c.k[1]);
  t.keyframes_erased(erased);
  c.m.keyframe(c.k[1])->T_cw = pose_at(0.11, 0.06);  // moved after the cull
  t.resolve(c.m);
  const SE3 T_c2 = T_cw * pose_at(0.2, 0.1).inverse();
  EXPECT_TRUE(t.poses()[0].refined);
  EXPECT_LT(distance(t.poses()[0].T_cw, T_c2 * T_21 * c.m.keyframe(c.k[1])->T_cw), 1e-12);
}

TEST(RefinedTrajectory, AFrameWithoutAKeyframeChainKeepsItsOnlinePose) {
  ChainMap c;
  RefinedTrajectory t;
  const SE3 T_cw = pose_at(0.4);
  t.add(1.0, 1, map::KeyframeId{}, T_cw, c.m);  // no reference keyframe
  t.add(2.0, 2, c.k[0], T_cw, c.m);
  std::vector<map::ErasedKeyframe> erased;
  c.m.take_erased(erased);
  c.m.reset();  // the map is gone before resolve: nothing to compose with
  t.resolve(c.m);
  ASSERT_EQ(t.poses().size(), 2u);
  for (const TrajectoryPose& p : t.poses()) {
    EXPECT_FALSE(p.refined);
    EXPECT_LT(distance(p.T_cw, T_cw), 1e-15);
  }
}

}  // namespace
}  // namespace ale::slam
