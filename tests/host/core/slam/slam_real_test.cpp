// The SLAM core on real recorded frames: our front end, then SlamSystem, then the evaluator.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

#include "app/tools/lib/eval/associate.h"
#include "app/tools/lib/eval/metrics.h"
#include "app/tools/lib/eval/trajectory.h"
#include "core/features/orb.h"
#include "core/slam/slam_pipeline.h"
#include "hal/replay/dataset.h"
#include "core/io/image_io.h"
#include "tests/host/support/test_data.h"

namespace ale::slam {
namespace {

struct ReplayResult {
  int frames = 0;
  int first_tracked = -1;
  int tracked_after_init = 0;
  std::size_t keyframes = 0;
  int resets = 0;
  eval::Trajectory trajectory;  // camera in the map frame
};

ReplayResult replay(const replay::Dataset& ds, const geometry::Camera& cam, features::ExtractorMode mode) {
  ReplayResult out;
  features::ExtractorConfig ec;
  ec.mode = mode;
  auto pipeline = SlamPipeline::create(ec, SlamParams{}, cam);
  EXPECT_TRUE(pipeline.ok()) << pipeline.status().to_string();
  if (!pipeline.ok()) return out;
  GrayImage img;
  for (const replay::FrameEntry& f : ds.frames) {
    EXPECT_TRUE(io::read_gray(f.path, img).ok()) << f.path;
    const Status s = (*pipeline)->process({f.timestamp_ns, static_cast<std::uint64_t>(out.frames)}, img.view());
    EXPECT_TRUE(s.ok()) << s.to_string();
    const SlamReport& r = (*pipeline)->report();
    if (s.ok() && std::getenv("ALE_SLAM_DEBUG")) {
      std::printf("  frame %d: %s features %d matches %d inliers %d kf %zu lm %zu %s\n", out.frames, to_string(r.state),
                  r.features, r.matches, r.inliers, r.keyframes, r.landmarks, r.message.c_str());
    }
    if (s.ok() && r.has_pose) {
      if (out.first_tracked < 0) out.first_tracked = out.frames;
      ++out.tracked_after_init;
      const geometry::SE3 T_wc = r.T_cw.inverse();
      eval::StampedPose p;
      p.t_s = static_cast<double>(f.timestamp_ns) * 1e-9;
      p.R_wb = T_wc.rotation();
      p.p_wb = T_wc.translation();
      out.trajectory.poses.push_back(p);
    }
    if (s.ok()) {
      out.keyframes = r.keyframes;
      out.resets = r.resets;
    }
    ++out.frames;
  }
  return out;
}

TEST(SlamReal, TumFr2DeskInitialisesAndTracksWithinTwoCentimetres) {
  ALE_REQUIRE_DATA(folder, "tum_fr2_desk_20");
  Result<replay::Dataset> ds = replay::open_dataset(folder);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  geometry::CameraIntrinsics k;
  k.fx = 520.9;
  k.fy = 521.0;
  k.cx = 325.1;
  k.cy = 249.7;
  k.width = ds->width;
  k.height = ds->height;
  const geometry::Camera cam = *geometry::Camera::create(k);
  Result<eval::Trajectory> gt = eval::read_trajectory(folder + "/groundtruth.txt");
  ASSERT_TRUE(gt.ok()) << gt.status().to_string();
  for (features::ExtractorMode mode : {features::ExtractorMode::kAle, features::ExtractorMode::kBaseline}) {
    const ReplayResult r = replay(*ds, cam, mode);
    std::printf("tum_fr2_desk_20 mode=%s frames=%d first_tracked=%d tracked=%d keyframes=%zu resets=%d\n",
                features::to_string(mode), r.frames, r.first_tracked, r.tracked_after_init, r.keyframes, r.resets);
    ASSERT_GE(r.first_tracked, 0) << "never initialised";
    // Measured: the first pose on frame 2 and all 18 frames after it tracked, in both modes. At
    // most frame 5 (three frames of margin for a change of the initialiser) keeps 15 of the 20
    // frames for the accuracy check below; every frame after initialisation must have a pose.
    EXPECT_LE(r.first_tracked, 5) << "initialised late";
    EXPECT_EQ(r.tracked_after_init, r.frames - r.first_tracked) << "a frame after initialisation has no pose";
    EXPECT_GE(r.tracked_after_init, 15);
    ASSERT_GE(r.trajectory.poses.size(), 3u);
    Result<eval::PosePairs> pairs = eval::associate(*gt, r.trajectory, 0.02);
    ASSERT_TRUE(pairs.ok()) << pairs.status().to_string();
    ASSERT_TRUE(eval::align_estimate(eval::Alignment::kSim3, &*pairs).ok());
    Result<eval::AteResult> ate = eval::compute_ate(*pairs);
    ASSERT_TRUE(ate.ok());
    std::printf("tum_fr2_desk_20 mode=%s ate_rmse_m=%.4f ate_max_m=%.4f pairs=%zu\n", features::to_string(mode),
                ate->trans_m.rmse, ate->trans_m.max, ate->trans_m.count);
    EXPECT_LE(ate->trans_m.rmse, 0.02);
  }
}

TEST(SlamReal, EurocStaticVehicleMakesNoFalseMap) {
  ALE_REQUIRE_DATA(folder, "euroc_v101_micro");
  Result<replay::Dataset> ds = replay::open_dataset(folder);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  ASSERT_TRUE(ds->calibration.has_value());
  const hal::CameraCalibration& c = *ds->calibration;
  geometry::CameraIntrinsics k;
  k.fx = c.fx;
  k.fy = c.fy;
  k.cx = c.cx;
  k.cy = c.cy;
  k.width = c.width;
  k.height = c.height;
  k.distortion = {c.distortion[0], c.distortion[1], c.distortion[2], c.distortion[3], 0.0};
  const geometry::Camera cam = *geometry::Camera::create(k);
  const ReplayResult r = replay(*ds, cam, features::ExtractorMode::kAle);
  double travel = 0.0;
  for (const eval::StampedPose& p : r.trajectory.poses) {
    travel = std::max(travel, (p.p_wb - r.trajectory.poses.front().p_wb).norm());
  }
  std::printf("euroc_v101_micro frames=%d tracked=%d keyframes=%zu travel=%.4f (map units)\n", r.frames,
              r.tracked_after_init, r.keyframes, travel);
  // A map built from a still camera has no metric scale to compare against: any initialisation is
  // false. Where one happened, the camera must at least not seem to move by more than 1 cm worth
  // (the map is scaled to a median depth of 1, about 3 m in this room).
  if (r.first_tracked >= 0) {
    EXPECT_LT(travel * 3.0, 0.01) << "a still camera produced a moving trajectory";
  }
}

}  // namespace
}  // namespace ale::slam
