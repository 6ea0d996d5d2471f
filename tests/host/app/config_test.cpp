#include "app/config.h"

#include <gtest/gtest.h>

#include "tests/host/support/test_data.h"

namespace ale::app {
namespace {

TEST(ConfigTest, DefaultsWhenEmpty) {
  DaemonConfig c;
  ASSERT_TRUE(parse_config("", "empty", c).ok());
  EXPECT_EQ(c.camera.source, "v4l2");
  EXPECT_EQ(c.camera.width, 640);
  EXPECT_EQ(c.camera.fps, 30);
}

TEST(ConfigTest, ReadsSectionsCommentsAndQuotes) {
  DaemonConfig c;
  const char* text =
      "# robot 7\n"
      "[camera]\n"
      "source = replay   # recorded\n"
      "replay_path = \"/data/run 1\"\n"
      "fps=15\n"
      "[gpio]\n"
      "chip = gpiochip1\n"
      "status_led = 34\n"
      "active_low = true\n";
  Status s = parse_config(text, "robot.conf", c);
  ASSERT_TRUE(s.ok()) << s.to_string();
  EXPECT_EQ(c.camera.source, "replay");
  EXPECT_EQ(c.camera.replay_path, "/data/run 1");
  EXPECT_EQ(c.camera.fps, 15);
  EXPECT_EQ(c.gpio.status_led, 34);
  EXPECT_TRUE(c.gpio.active_low);
}

void expect_rejected(const std::string& text, const std::string& needle) {
  DaemonConfig c;
  c.camera.fps = 29;
  Status s = parse_config(text, "bad.conf", c);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << text;
  EXPECT_NE(s.message().find(needle), std::string::npos) << s.message();
  EXPECT_EQ(c.camera.fps, 29) << "a rejected file must not change the config";
}

TEST(ConfigTest, RejectsBadFilesNamingKeyAndLine) {
  expect_rejected("[camera]\nfps = 30\nfsp = 30\n", "bad.conf:3: unknown key 'camera.fsp'");
  expect_rejected("[camera]\nfps = 500\n", "camera.fps: 500 is out of range");
  expect_rejected("[camera]\nfps = 3o\n", "bad.conf:2: camera.fps: '3o' is not an integer");
  expect_rejected("[camera]\nsource = usb\n", "is not one of v4l2|replay");
  expect_rejected("[camera\n", "bad.conf:1: malformed section header");
  expect_rejected("[camera]\nfps\n", "expected 'key = value'");
  expect_rejected("[camera]\nsource = replay\n", "camera.replay_path: required");
  expect_rejected("[gpio]\nstatus_led = 3\n", "gpio.chip: required");
  expect_rejected("[gpio]\nactive_low = maybe\n", "not a boolean");
}

TEST(ConfigTest, EnhancementKeysReachTheCoreParameters) {
  DaemonConfig c;
  Status s = parse_config("[enhance]\nt_very_low = 40\nt_low = 60.5\ngamma_min = 0.5\n", "e.conf", c);
  ASSERT_TRUE(s.ok()) << s.to_string();
  EXPECT_DOUBLE_EQ(c.features.enhance.grading.t_very_low, 40.0);
  EXPECT_DOUBLE_EQ(c.features.enhance.grading.t_low, 60.5);
  EXPECT_DOUBLE_EQ(c.features.enhance.gamma.gamma_min, 0.5);
  expect_rejected("[enhance]\nt_low = dark\n", "bad.conf:2: enhance.t_low: 'dark' is not a number");
  expect_rejected("[enhance]\ngamma_min = 2\n", "enhance.gamma_min: 2 is out of range");
  // each value in range, but inconsistent together: the core's validation names the field
  expect_rejected("[enhance]\nt_very_low = 90\nt_low = 60\n", "t_low");
}

TEST(ConfigTest, MissingFileIsNotFound) {
  DaemonConfig c;
  Status s = load_config("/nonexistent/ale.conf", c);
  EXPECT_EQ(s.code(), StatusCode::kNotFound);
  EXPECT_NE(s.message().find("/nonexistent/ale.conf"), std::string::npos);
}

TEST(ConfigTest, ShippedBoardConfigIsValid) {
  DaemonConfig c;
  Status s = load_config(ALE_SOURCE_DIR "/board/mr133/ale-slamd.conf", c);
  EXPECT_TRUE(s.ok()) << s.to_string();
}

}  // namespace
}  // namespace ale::app
