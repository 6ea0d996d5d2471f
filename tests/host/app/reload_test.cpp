#include "app/daemon/reload.h"

#include <gtest/gtest.h>

namespace ale::app {
namespace {

TEST(ReloadTest, SplitsRuntimeKeysFromRestartKeys) {
  DaemonConfig running;
  DaemonConfig loaded;
  ASSERT_TRUE(parse_config("[camera]\ndevice = /dev/video1\nreconnect_max_ms = 8000\n[lcm]\nurl = memq://\n"
                           "status_channel = S\n[features]\nnum_features = 500\n",
                           "new.conf", loaded)
                  .ok());
  const ReloadPlan plan = plan_reload(running, loaded);
  EXPECT_EQ(plan.effective.camera.reconnect_max_ms, 8000);
  EXPECT_EQ(plan.effective.lcm.status_channel, "S");
  EXPECT_EQ(plan.effective.camera.device, "/dev/video0");
  EXPECT_EQ(plan.effective.lcm.url, running.lcm.url);
  EXPECT_EQ(plan.effective.features.num_features, running.features.num_features);
  EXPECT_EQ(plan.applied, (std::vector<std::string>{"camera.reconnect_max_ms = 8000", "lcm.status_channel = S"}));
  EXPECT_EQ(plan.needs_restart,
            (std::vector<std::string>{"camera.device = /dev/video1", "lcm.url = memq://", "features.num_features = 500"}));
}

TEST(ReloadTest, EnhancementParametersAndTheFrameRateChangeAtRunTime) {
  DaemonConfig running;
  DaemonConfig loaded;
  ASSERT_TRUE(parse_config("[features.enhance.grading]\nt_low = 75\n[features.enhance.gamma]\nalpha = 0.6\n"
                           "[features.enhance.clahe]\nclip_max = 3\n[features]\nnoise_gate = 0\n"
                           "[slam]\nprocess_fps = 10\nkeyframe_min_frames = 4\n",
                           "new.conf", loaded)
                  .ok());
  const ReloadPlan plan = plan_reload(running, loaded);
  EXPECT_EQ(plan.effective.features.enhance.grading.t_low, 75.0);
  EXPECT_EQ(plan.effective.features.enhance.gamma.alpha, 0.6);
  EXPECT_EQ(plan.effective.features.enhance.clahe.clip_max, 3.0);
  EXPECT_EQ(plan.effective.slam.process_fps, 10.0);
  EXPECT_EQ(plan.effective.features.noise_gate, running.features.noise_gate);
  EXPECT_EQ(plan.effective.slam.keyframe_min_frames, running.slam.keyframe_min_frames);
  EXPECT_EQ(plan.applied, (std::vector<std::string>{"features.enhance.grading.t_low = 75", "features.enhance.gamma.alpha = 0.6",
                                                    "features.enhance.clahe.clip_max = 3", "slam.process_fps = 10"}));
  ASSERT_EQ(plan.needs_restart.size(), 2u);
  EXPECT_EQ(plan.needs_restart[0].rfind("features.noise_gate = 0", 0), 0u) << plan.needs_restart[0];
  EXPECT_EQ(plan.needs_restart[1], "slam.keyframe_min_frames = 4");
}

TEST(ReloadTest, TheMapSaveKeysChangeAtRunTimeTheLoadNeedsARestart) {
  DaemonConfig running;
  DaemonConfig loaded;
  ASSERT_TRUE(parse_config("[map]\nload = a.alemap\nsave = b.alemap\nsave_period_s = 60\n", "new.conf", loaded).ok());
  const ReloadPlan plan = plan_reload(running, loaded);
  EXPECT_EQ(plan.effective.map.save, "b.alemap");
  EXPECT_EQ(plan.effective.map.save_period_s, 60.0);
  EXPECT_EQ(plan.effective.map.load, "");
  EXPECT_EQ(plan.applied, (std::vector<std::string>{"map.save = b.alemap", "map.save_period_s = 60"}));
  EXPECT_EQ(plan.needs_restart, (std::vector<std::string>{"map.load = a.alemap"}));
}

TEST(ReloadTest, AnUnchangedFileChangesNothing) {
  DaemonConfig c;
  const ReloadPlan plan = plan_reload(c, c);
  EXPECT_TRUE(plan.applied.empty());
  EXPECT_TRUE(plan.needs_restart.empty());
}

}  // namespace
}  // namespace ale::app
