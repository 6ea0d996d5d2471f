#include "hal/replay/replay_camera.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "hal/clock.h"
#include "core/io/image_io.h"
#include "tests/host/hal/replay/replay_fixtures.h"
#include "tests/host/support/test_data.h"

namespace ale::replay {
namespace {

// (timestamp, file name) rows of a EuRoC data.csv, parsed with the simplest code that works.
std::vector<std::pair<std::int64_t, std::string>> read_csv_rows(const std::string& csv) {
  std::vector<std::pair<std::int64_t, std::string>> rows;
  std::ifstream in(csv);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (line.back() == '\r') line.pop_back();
    const std::size_t comma = line.find(',');
    rows.emplace_back(std::stoll(line.substr(0, comma)), line.substr(comma + 1));
  }
  return rows;
}

std::unique_ptr<ReplayCamera> open_or_fail(const std::string& path, const ReplayOptions& options = {}) {
  Result<std::unique_ptr<ReplayCamera>> cam = open_replay(path, options);
  EXPECT_TRUE(cam.ok()) << cam.status().to_string();
  if (!cam.ok()) return nullptr;
  EXPECT_TRUE((*cam)->start().ok());
  return std::move(*cam);
}

std::string fixture_frame(const std::string& cam0, int index) {
  return cam0 + "/data/" + std::to_string(test::fixture_timestamp_ns(index)) + ".png";
}

// ---- real data ------------------------------------------------------------------------------

TEST(ReplayCameraTest, EurocMicroAllFramesWithTheirTimestamps) {
  ALE_REQUIRE_DATA(root, "euroc_v101_micro");
  const std::vector<std::pair<std::int64_t, std::string>> rows = read_csv_rows(root + "/mav0/cam0/data.csv");
  ASSERT_EQ(rows.size(), 95u);
  hal::ManualClock clock;
  ReplayOptions options;
  options.clock = &clock;
  const std::unique_ptr<ReplayCamera> cam = open_or_fail(root, options);
  ASSERT_NE(cam, nullptr);
  EXPECT_EQ(cam->frame_count(), 95u);

  GrayImage reference;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    hal::Frame frame;
    const Status st = cam->acquire(frame, 0);
    ASSERT_TRUE(st.ok()) << i << ": " << st.to_string();
    EXPECT_EQ(frame.timestamp_ns, rows[i].first) << i;
    EXPECT_EQ(frame.sequence, i);
    EXPECT_EQ(clock.now_ns(), rows[i].first);
    ASSERT_EQ(frame.image.width, 752);
    ASSERT_EQ(frame.image.height, 480);
    // Spot-check pixels against a separate decode of the file the CSV names.
    if (i % 30 == 0) {
      ASSERT_TRUE(io::read_gray(root + "/mav0/cam0/data/" + rows[i].second, reference).ok());
      EXPECT_EQ(test::mean_abs_diff(frame.image, reference.view()), 0.0) << i;
    }
    ASSERT_TRUE(cam->release(frame).ok());
  }
  hal::Frame frame;
  EXPECT_EQ(cam->acquire(frame, 0).code(), StatusCode::kEndOfStream);
  EXPECT_EQ(cam->stats().delivered, 95u);
  EXPECT_EQ(cam->stats().errors, 0u);

  const Result<hal::CameraCalibration> calib = cam->calibration();
  ASSERT_TRUE(calib.ok());
  EXPECT_EQ(calib->fx, 458.654);
  EXPECT_EQ(calib->cy, 248.375);
  EXPECT_EQ(calib->distortion[3], 1.76187114e-05);
}

TEST(ReplayCameraTest, TumDesk20FramesAsGrey) {
  ALE_REQUIRE_DATA(root, "tum_fr2_desk_20");
  const std::unique_ptr<ReplayCamera> cam = open_or_fail(root);
  ASSERT_NE(cam, nullptr);
  std::int64_t previous = 0;
  for (int i = 0; i < 20; ++i) {
    hal::Frame frame;
    ASSERT_TRUE(cam->acquire(frame, 0).ok()) << i;
    EXPECT_EQ(frame.image.width, 640);
    EXPECT_EQ(frame.image.height, 480);
    EXPECT_GT(frame.timestamp_ns, previous);
    previous = frame.timestamp_ns;
    // A real indoor scene: not flat.
    int lo = 255, hi = 0;
    for (int y = 0; y < frame.image.height; y += 7)
      for (int x = 0; x < frame.image.width; x += 7) {
        lo = std::min<int>(lo, frame.image.at(x, y));
        hi = std::max<int>(hi, frame.image.at(x, y));
      }
    EXPECT_GT(hi - lo, 100) << i;
    ASSERT_TRUE(cam->release(frame).ok());
  }
  hal::Frame frame;
  EXPECT_EQ(cam->acquire(frame, 0).code(), StatusCode::kEndOfStream);
  EXPECT_EQ(previous, 1311868171063438000);
  EXPECT_EQ(cam->calibration().status().code(), StatusCode::kUnsupported);
}

TEST(ReplayCameraTest, TumWithCalibrationFromOptions) {
  ALE_REQUIRE_DATA(root, "tum_fr2_desk_20");
  ReplayOptions options;
  hal::CameraCalibration c;
  c.fx = 520.9;
  c.fy = 521.0;
  c.cx = 325.1;
  c.cy = 249.7;
  options.calibration = c;
  const std::unique_ptr<ReplayCamera> cam = open_or_fail(root, options);
  ASSERT_NE(cam, nullptr);
  const Result<hal::CameraCalibration> got = cam->calibration();
  ASSERT_TRUE(got.ok());
  EXPECT_EQ(got->fx, 520.9);
  EXPECT_EQ(got->width, 640);  // filled in from the frames
  EXPECT_EQ(got->height, 480);

  c.width = 320;
  c.height = 240;
  options.calibration = c;
  EXPECT_EQ(open_replay(root, options).status().code(), StatusCode::kInvalidArgument);
}

// ---- pool, order, options -------------------------------------------------------------------

TEST(ReplayCameraTest, AllBuffersLentIsOutOfMemoryUntilOneIsReleased) {
  const std::string dir = ale::test::make_temp_dir("replay");
  test::write_euroc(dir, 6, 24, 10);
  ReplayOptions options;
  options.buffers = 3;
  const std::unique_ptr<ReplayCamera> cam = open_or_fail(dir, options);
  ASSERT_NE(cam, nullptr);
  hal::Frame lent[3];
  for (int i = 0; i < 3; ++i) ASSERT_TRUE(cam->acquire(lent[i], 0).ok()) << i;
  hal::Frame extra;
  EXPECT_EQ(cam->acquire(extra, 0).code(), StatusCode::kOutOfMemory);
  EXPECT_EQ(cam->acquire(extra, 0).code(), StatusCode::kOutOfMemory);
  EXPECT_EQ(cam->pool()->stats().in_use, 3u);

  // The frames lent out keep their pixels while others are decoded.
  ASSERT_TRUE(cam->release(lent[1]).ok());
  ASSERT_TRUE(cam->acquire(extra, 0).ok());
  EXPECT_EQ(extra.sequence, 3u);  // the refused attempts used up no frame
  EXPECT_EQ(extra.timestamp_ns, test::fixture_timestamp_ns(3));
  EXPECT_EQ(test::mean_abs_diff(extra.image, test::pattern_frame(24, 10, 3).view()), 0.0);
  EXPECT_EQ(test::mean_abs_diff(lent[0].image, test::pattern_frame(24, 10, 0).view()), 0.0);
  EXPECT_EQ(test::mean_abs_diff(lent[2].image, test::pattern_frame(24, 10, 2).view()), 0.0);

  // Releasing twice, or a stale copy of a frame whose buffer was lent again, is refused.
  EXPECT_EQ(cam->release(lent[1]).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(cam->pool()->stats().capacity, 3u);
  ASSERT_TRUE(cam->release(extra).ok());
  ASSERT_TRUE(cam->release(lent[0]).ok());
  ASSERT_TRUE(cam->release(lent[2]).ok());
  EXPECT_EQ(cam->pool()->stats().in_use, 0u);
  EXPECT_EQ(cam->stats().errors, 0u);
}

TEST(ReplayCameraTest, EndOfStreamAfterTheLastFrameAndStaysThere) {
  const std::string dir = ale::test::make_temp_dir("replay");
  test::write_euroc(dir, 2, 8, 4);
  const std::unique_ptr<ReplayCamera> cam = open_or_fail(dir);
  ASSERT_NE(cam, nullptr);
  for (int i = 0; i < 2; ++i) {
    hal::Frame f;
    ASSERT_TRUE(cam->acquire(f, 0).ok());
    ASSERT_TRUE(cam->release(f).ok());
  }
  for (int i = 0; i < 3; ++i) {
    hal::Frame f;
    EXPECT_EQ(cam->acquire(f, 0).code(), StatusCode::kEndOfStream);
  }
  EXPECT_EQ(cam->remaining(), 0u);
}

TEST(ReplayCameraTest, StartIndexAndMaxFrames) {
  const std::string dir = ale::test::make_temp_dir("replay");
  test::write_euroc(dir, 6, 8, 4);
  ReplayOptions options;
  options.start_index = 2;
  options.max_frames = 3;
  const std::unique_ptr<ReplayCamera> cam = open_or_fail(dir, options);
  ASSERT_NE(cam, nullptr);
  EXPECT_EQ(cam->frame_count(), 3u);
  for (int i = 0; i < 3; ++i) {
    hal::Frame f;
    ASSERT_TRUE(cam->acquire(f, 0).ok());
    EXPECT_EQ(f.timestamp_ns, test::fixture_timestamp_ns(2 + i));
    EXPECT_EQ(f.sequence, static_cast<std::uint64_t>(i));
    ASSERT_TRUE(cam->release(f).ok());
  }
  hal::Frame f;
  EXPECT_EQ(cam->acquire(f, 0).code(), StatusCode::kEndOfStream);

  options.start_index = 6;
  EXPECT_EQ(open_replay(dir, options).status().code(), StatusCode::kInvalidArgument);
  options.start_index = 0;
  options.buffers = 0;
  EXPECT_EQ(open_replay(dir, options).status().code(), StatusCode::kInvalidArgument);
}

TEST(ReplayCameraTest, AcquireBeforeStartIsRefused) {
  const std::string dir = ale::test::make_temp_dir("replay");
  test::write_euroc(dir, 1, 8, 4);
  Result<std::unique_ptr<ReplayCamera>> cam = open_replay(dir, {});
  ASSERT_TRUE(cam.ok());
  hal::Frame f;
  EXPECT_EQ((*cam)->acquire(f, 0).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ((*cam)->pool(), nullptr);
  EXPECT_NE((*cam)->describe().find("EuRoC"), std::string::npos);
}

// ---- a bad frame in the middle of a replay --------------------------------------------------

// Frames 0..4 where frame 2 is truncated and frame 3 is garbage.
std::string write_damaged(const std::string& dir) {
  const std::string cam0 = test::write_euroc(dir, 5, 16, 8);
  const std::string bytes = ale::test::read_file(fixture_frame(cam0, 2));
  EXPECT_TRUE(ale::test::write_file(fixture_frame(cam0, 2), bytes.substr(0, bytes.size() / 2)));
  EXPECT_TRUE(ale::test::write_file(fixture_frame(cam0, 3), "garbage garbage garbage"));
  return cam0;
}

TEST(ReplayCameraTest, BadFrameIsReportedAndTheReplayGoesOn) {
  const std::string dir = ale::test::make_temp_dir("replay");
  const std::string cam0 = write_damaged(dir);
  ReplayOptions options;
  options.buffers = 2;
  const std::unique_ptr<ReplayCamera> cam = open_or_fail(dir, options);
  ASSERT_NE(cam, nullptr);
  std::vector<std::uint64_t> sequences;
  std::vector<std::string> errors;
  for (;;) {
    hal::Frame f;
    const Status st = cam->acquire(f, 0);
    if (st.code() == StatusCode::kEndOfStream) break;
    if (!st.ok()) {
      EXPECT_EQ(st.code(), StatusCode::kCorruptData) << st.to_string();
      errors.push_back(st.message());
      continue;
    }
    sequences.push_back(f.sequence);
    ASSERT_TRUE(cam->release(f).ok());
  }
  EXPECT_EQ(sequences, (std::vector<std::uint64_t>{0, 1, 4}));
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_NE(errors[0].find(fixture_frame(cam0, 2)), std::string::npos) << errors[0];
  EXPECT_NE(errors[1].find(fixture_frame(cam0, 3)), std::string::npos) << errors[1];
  EXPECT_EQ(cam->stats().errors, 2u);
  EXPECT_EQ(cam->stats().delivered, 3u);
  EXPECT_EQ(cam->pool()->stats().in_use, 0u);  // failed decodes gave their buffers back
}

TEST(ReplayCameraTest, BadFramePoliciesSkipAndStop) {
  const std::string dir = ale::test::make_temp_dir("replay");
  write_damaged(dir);
  ReplayOptions options;
  options.on_bad_frame = BadFramePolicy::kSkip;
  std::unique_ptr<ReplayCamera> cam = open_or_fail(dir, options);
  ASSERT_NE(cam, nullptr);
  std::vector<std::uint64_t> sequences;
  hal::Frame f;
  while (cam->acquire(f, 0).ok()) {
    sequences.push_back(f.sequence);
    ASSERT_TRUE(cam->release(f).ok());
  }
  EXPECT_EQ(sequences, (std::vector<std::uint64_t>{0, 1, 4}));  // the gap shows the loss
  EXPECT_EQ(cam->stats().dropped, 2u);
  EXPECT_EQ(cam->stats().errors, 2u);

  options.on_bad_frame = BadFramePolicy::kStop;
  cam = open_or_fail(dir, options);
  ASSERT_NE(cam, nullptr);
  for (int i = 0; i < 2; ++i) {
    ASSERT_TRUE(cam->acquire(f, 0).ok());
    ASSERT_TRUE(cam->release(f).ok());
  }
  EXPECT_EQ(cam->acquire(f, 0).code(), StatusCode::kCorruptData);
  EXPECT_EQ(cam->acquire(f, 0).code(), StatusCode::kCorruptData);  // and it stays stopped
  EXPECT_EQ(cam->stats().errors, 1u);
}

TEST(ReplayCameraTest, FrameOfAnotherSizeMidReplayIsCorrupt) {
  const std::string dir = ale::test::make_temp_dir("replay");
  const std::string cam0 = test::write_euroc(dir, 3, 16, 8);
  ASSERT_TRUE(io::write_png(fixture_frame(cam0, 1), test::pattern_frame(17, 8, 1).view()).ok());
  const std::unique_ptr<ReplayCamera> cam = open_or_fail(dir);
  ASSERT_NE(cam, nullptr);
  hal::Frame f;
  ASSERT_TRUE(cam->acquire(f, 0).ok());
  ASSERT_TRUE(cam->release(f).ok());
  const Status st = cam->acquire(f, 0);
  EXPECT_EQ(st.code(), StatusCode::kCorruptData);
  EXPECT_NE(st.message().find(fixture_frame(cam0, 1)), std::string::npos) << st.message();
  ASSERT_TRUE(cam->acquire(f, 0).ok());
  EXPECT_EQ(f.sequence, 2u);
}

TEST(ReplayCameraTest, ClockFollowsRecordedTime) {
  const std::string dir = ale::test::make_temp_dir("replay");
  test::write_euroc(dir, 3, 8, 4);
  hal::ManualClock clock;
  ReplayOptions options;
  options.clock = &clock;
  const std::unique_ptr<ReplayCamera> cam = open_or_fail(dir, options);
  ASSERT_NE(cam, nullptr);
  EXPECT_EQ(clock.now_ns(), 0);
  for (int i = 0; i < 3; ++i) {
    hal::Frame f;
    ASSERT_TRUE(cam->acquire(f, 0).ok());
    EXPECT_EQ(clock.now_ns(), test::fixture_timestamp_ns(i));
    ASSERT_TRUE(cam->release(f).ok());
  }
}

}  // namespace
}  // namespace ale::replay
