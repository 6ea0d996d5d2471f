#include "app/config.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

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
  expect_rejected("[slam.matcher]\nratio_projection = 1.5\n",
                  "bad.conf:2: slam.matcher.ratio_projection: 1.5 is out of range [0.01, 1]");
  expect_rejected("[slam.matcher.rotation]\nbins = 0\n", "slam.matcher.rotation.bins: 0 is out of range [1, 360]");
  expect_rejected("[map]\nsave_period_s = 60\n", "map.save_period_s: needs map.save, the file saved to");
  expect_rejected("[map]\nsave = m.alemap\nsave_period_s = -1\n", "map.save_period_s: -1 is out of range");
}

TEST(ConfigTest, KeysAreTheStructPaths) {
  DaemonConfig c;
  Status s = parse_config(
      "[features.enhance.grading]\nt_very_low = 40\nt_low = 60.5\n"
      "[features]\nenhance.gamma.gamma_min = 0.5\ncell_clahe.tile_min = 12\nlevel_enhance = always\n"
      "num_features = 100000\ncell_size_px = 1000\n[daemon]\nmax_frames = 7\n",
      "e.conf", c);
  ASSERT_TRUE(s.ok()) << s.to_string();
  EXPECT_DOUBLE_EQ(c.features.enhance.grading.t_very_low, 40.0);
  EXPECT_DOUBLE_EQ(c.features.enhance.grading.t_low, 60.5);
  EXPECT_DOUBLE_EQ(c.features.enhance.gamma.gamma_min, 0.5);
  EXPECT_EQ(c.features.cell_clahe.tile_min, 12);
  EXPECT_EQ(c.features.level_enhance, enhance::LevelEnhance::kAlways);
  // The parser's ranges are the core's: what one accepts the other does.
  EXPECT_EQ(c.features.num_features, 100000);
  EXPECT_EQ(c.features.cell_size_px, 1000);
  EXPECT_TRUE(features::validate(c.features).ok());
  EXPECT_EQ(c.daemon.max_frames, 7);
  expect_rejected("[features.enhance.grading]\nt_low = dark\n",
                  "bad.conf:2: features.enhance.grading.t_low: 'dark' is not a number");
  expect_rejected("[features]\nenhance.gamma.gamma_min = 2\n",
                  "bad.conf:2: features.enhance.gamma.gamma_min: 2 is out of range [0.05, 1]");
  expect_rejected("[features]\nnum_features = 100001\n", "features.num_features: 100001 is out of range [1, 100000]");
  expect_rejected("[features]\nlevel_enhance = sometimes\n", "is not one of never|non_normal_frames|always");
  // The old flat keys are gone.
  expect_rejected("[enhance]\nt_low = 60\n", "unknown key 'enhance.t_low'");
  // Each value in range, but inconsistent together: the core's validation names the field, with
  // one prefix.
  expect_rejected("[features.enhance.grading]\nt_very_low = 90\nt_low = 60\n",
                  "features.enhance.grading.t_low: 60 must be >= t_very_low (90)");
  expect_rejected("[features]\nt_high = 35\n", "features.t_higher: 30 must be > t_high (35)");
}

// A float member (the matcher's ratios) takes the float nearest the value, prints with a float's
// digits and parses back to the same bits; validation reads it as the file does.
TEST(ConfigTest, FloatKeysParseToTheFloatAndBack) {
  DaemonConfig c;
  ASSERT_TRUE(parse_config("[slam.matcher]\nratio_projection = 0.7\nth_high = 90\n[slam.matcher.rotation]\nenabled = false\n",
                           "in.conf", c)
                  .ok());
  EXPECT_EQ(c.slam.matcher.ratio_projection, 0.7f);
  EXPECT_EQ(c.slam.matcher.th_high, 90);
  EXPECT_FALSE(c.slam.matcher.rotation.enabled);
  const std::string printed = print_config(c);
  EXPECT_NE(printed.find("matcher.ratio_projection = 0.7\n"), std::string::npos) << printed;
  DaemonConfig back;
  ASSERT_TRUE(parse_config(printed, "printed", back).ok());
  EXPECT_EQ(back.slam.matcher.ratio_projection, 0.7f);
  EXPECT_EQ(back.slam.matcher.ratio_initialization, slam::MatcherParams{}.ratio_initialization);
  slam::SlamParams p;
  p.matcher.ratio_triangulation = 1.25f;
  EXPECT_EQ(slam::validate(p).message(), "slam.matcher.ratio_triangulation: 1.25 is out of range [0.01, 1]");
}

TEST(ConfigTest, CoreValidationReadsTheSameRanges) {
  features::ExtractorConfig f;
  f.num_features = 0;
  EXPECT_EQ(features::validate(f).message(), "num_features: 0 is out of range [1, 100000]");
  f = features::ExtractorConfig{};
  f.cell_clahe.clip_max = 0.5;  // below clip_min = 1
  EXPECT_EQ(features::validate(f).message(), "cell_clahe.clip_max: 0.5 must be >= clip_min (1)");
}

TEST(ConfigTest, PrintedConfigParsesBackToItself) {
  DaemonConfig c;
  ASSERT_TRUE(parse_config("[camera]\nsource = replay\nreplay_path = \"/data/run 1\"\n[enhancement]\nmode = off\n"
                           "[features]\nenhance.clahe.clip_base = 1.25\n[gpio]\nactive_low = true\n"
                           "[slam.tracker]\nmin_inliers = 12\n",
                           "in.conf", c)
                  .ok());
  const std::string printed = print_config(c);
  DaemonConfig back;
  const Status s = parse_config(printed, "printed", back);
  ASSERT_TRUE(s.ok()) << s.to_string() << "\n" << printed;
  EXPECT_EQ(print_config(back), printed);
  EXPECT_EQ(back.camera.replay_path, "/data/run 1");
  EXPECT_EQ(back.enhancement.mode, features::ExtractorMode::kBaseline);
  EXPECT_EQ(back.slam.tracker.min_inliers, 12);
  EXPECT_DOUBLE_EQ(back.features.enhance.clahe.clip_base, 1.25);
  EXPECT_NE(printed.find("[features]\n"), std::string::npos) << printed;
}

// docs/configuration.md lists exactly the table's keys, defaults, ranges and help, in its order.
TEST(ConfigTest, DocsListTheTableExactly) {
  const std::string doc = test::read_file(ALE_SOURCE_DIR "/docs/configuration.md");
  ASSERT_FALSE(doc.empty()) << ALE_SOURCE_DIR "/docs/configuration.md";
  const std::string begin = "<!-- keys: begin (ale-slamd --print-config-reference) -->\n";
  const std::string end = "<!-- keys: end -->";
  const std::size_t b = doc.find(begin);
  const std::size_t e = doc.find(end);
  ASSERT_NE(b, std::string::npos);
  ASSERT_NE(e, std::string::npos);
  EXPECT_EQ(doc.substr(b + begin.size(), e - b - begin.size()), config_reference_markdown())
      << "regenerate the table with: ale-slamd --print-config-reference";
}

TEST(ConfigTest, MissingFileIsNotFound) {
  DaemonConfig c;
  Status s = load_config("/nonexistent/ale.conf", c);
  EXPECT_EQ(s.code(), StatusCode::kNotFound);
  EXPECT_NE(s.message().find("/nonexistent/ale.conf"), std::string::npos);
}

TEST(ConfigTest, ADirectoryIsNotAConfigFile) {
  DaemonConfig c;
  c.camera.fps = 20;
  const Status s = load_config(ALE_SOURCE_DIR "/board", c);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("is not a regular file"), std::string::npos) << s.message();
  EXPECT_EQ(c.camera.fps, 20) << "nothing changed";
}

TEST(ConfigTest, ShippedBoardConfigIsValid) {
  DaemonConfig c;
  Status s = load_config(ALE_SOURCE_DIR "/board/mr133/ale-slamd.conf", c);
  EXPECT_TRUE(s.ok()) << s.to_string();
}

TEST(ConfigTest, DaemonKeysOfIssue12AreCheckedToo) {
  DaemonConfig c;
  Status s = parse_config("[camera]\nreconnect_initial_ms = 5000\nreconnect_max_ms = 1000\n", "x.conf", c);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("camera.reconnect_max_ms"), std::string::npos) << s.message();
  s = parse_config("[log]\ntarget = journald\n", "x.conf", c);
  EXPECT_NE(s.message().find("log.target"), std::string::npos) << s.message();
  s = parse_config("[lcm]\nreply_channel = \"\"\n", "x.conf", c);
  EXPECT_NE(s.message().find("reply_channel"), std::string::npos) << s.message();
  s = parse_config("[slam]\nprocess_fps = 500\n", "x.conf", c);
  EXPECT_NE(s.message().find("slam.process_fps"), std::string::npos) << s.message();
  ASSERT_TRUE(parse_config("[lcm]\ncommand_channel = \"\"\n[daemon]\nbody_frame = calibration\n", "x.conf", c).ok());
  EXPECT_TRUE(c.lcm.command_channel.empty()) << "no commands";
}

// The frame-rate key moved from [daemon] to [slam] (issue 12 names it slam.process_fps): the old
// key is refused with the new name, in a file and on the command line's --set form alike.
TEST(ConfigTest, TheOldProcessFpsKeyNamesTheNewOne) {
  DaemonConfig c;
  Status s = parse_config("[daemon]\nprocess_fps = 15\n", "old.conf", c);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("old.conf:2: 'daemon.process_fps' is now 'slam.process_fps'"), std::string::npos)
      << s.message();
  s = parse_config("daemon.process_fps = 15\n", "command line", c);
  EXPECT_NE(s.message().find("'slam.process_fps'"), std::string::npos) << s.message();
  ASSERT_TRUE(parse_config("[slam]\nprocess_fps = 15\n", "new.conf", c).ok());
  EXPECT_EQ(c.slam.process_fps, 15.0);
  // One key in one table: the board's profile sets it, and nothing under [daemon] is left of it.
  DaemonConfig board;
  ASSERT_TRUE(load_config(ALE_SOURCE_DIR "/board/mr133/ale-slamd.conf", board).ok());
  EXPECT_EQ(board.slam.process_fps, 15.0);
  const std::string printed = print_config(board);
  EXPECT_EQ(printed.find("process_fps"), printed.rfind("process_fps")) << printed;
}

}  // namespace
}  // namespace ale::app
