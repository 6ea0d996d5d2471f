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
