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

TEST(ReloadTest, AnUnchangedFileChangesNothing) {
  DaemonConfig c;
  const ReloadPlan plan = plan_reload(c, c);
  EXPECT_TRUE(plan.applied.empty());
  EXPECT_TRUE(plan.needs_restart.empty());
}

}  // namespace
}  // namespace ale::app
