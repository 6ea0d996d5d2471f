// The frame path's order, timing and extension: every stage timed into the record in order with
// the injected clock, appended stages see the front end's output, timing changes no result.
#include "core/frontend/frame_path.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace ale::frontend {
namespace {

// A checkerboard with some texture: corners on every level.
GrayImage board(int w, int h) {
  GrayImage img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      img.view().at(x, y) = static_cast<std::uint8_t>(((x / 12 + y / 12) % 2) ? 190 + (x * 7 + y * 3) % 40 : 40);
  return img;
}

std::int64_t g_now_ns = 0;
// Each read advances by 1 ms: stage i then takes exactly 1 ms.
std::int64_t fake_clock() { return g_now_ns += 1000000; }

struct CountingStage final : FrameStage {
  const char* name() const override { return "tracking"; }
  Status run(const FrameOutput& frame) override {
    ++runs;
    keypoints = frame.keypoints.size();
    total = frame.stats.total;
    return {};
  }
  int runs = 0;
  std::size_t keypoints = 0;
  int total = 0;
};

TEST(FramePath, TimesEveryStageInOrderWithTheInjectedClock) {
  FramePath path;
  ASSERT_TRUE(path.configure(features::ExtractorConfig{}).ok());
  path.set_clock(fake_clock);
  CountingStage tracking;
  ASSERT_TRUE(path.append_stage(tracking).ok());
  const GrayImage img = board(160, 120);
  std::vector<features::Keypoint> kps;
  std::vector<features::Descriptor> desc;
  ASSERT_TRUE(path.extract(img.view(), kps, desc).ok());
  const FrameTimings& t = path.timings();
  ASSERT_EQ(t.count, FramePath::kFrontEndStages.size() + 1);
  for (std::size_t i = 0; i < FramePath::kFrontEndStages.size(); ++i) {
    EXPECT_STREQ(t.stage[i].name, FramePath::kFrontEndStages[i]);
    EXPECT_EQ(t.stage[i].ns, 1000000);
  }
  EXPECT_STREQ(t.stage[t.count - 1].name, "tracking");
  EXPECT_EQ(t.total_ns(), 7 * 1000000);
  EXPECT_EQ(tracking.runs, 1);
  EXPECT_GT(kps.size(), 20u);
  EXPECT_EQ(tracking.keypoints, kps.size());
  EXPECT_EQ(tracking.total, static_cast<int>(kps.size()));
}

TEST(FramePath, TimingDoesNotChangeTheOutput) {
  const GrayImage img = board(200, 150);
  std::vector<features::Keypoint> kps_a, kps_b;
  std::vector<features::Descriptor> desc_a, desc_b;
  FramePath a, b;
  ASSERT_TRUE(a.configure(features::ExtractorConfig{}).ok());
  ASSERT_TRUE(b.configure(features::ExtractorConfig{}).ok());
  b.set_clock(fake_clock);
  ASSERT_TRUE(a.extract(img.view(), kps_a, desc_a).ok());
  ASSERT_TRUE(b.extract(img.view(), kps_b, desc_b).ok());
  ASSERT_EQ(kps_a.size(), kps_b.size());
  ASSERT_EQ(desc_a.size(), desc_b.size());
  for (std::size_t i = 0; i < kps_a.size(); ++i) {
    EXPECT_EQ(kps_a[i].x, kps_b[i].x);
    EXPECT_EQ(kps_a[i].y, kps_b[i].y);
    EXPECT_EQ(kps_a[i].angle_deg, kps_b[i].angle_deg);
    EXPECT_EQ(std::memcmp(&desc_a[i], &desc_b[i], sizeof desc_a[i]), 0) << i;
  }
}

TEST(FramePath, RefusesMoreStagesThanTheRecordHolds) {
  FramePath path;
  ASSERT_TRUE(path.configure(features::ExtractorConfig{}).ok());
  CountingStage stage;
  std::size_t accepted = 0;
  while (path.append_stage(stage).ok()) ++accepted;
  EXPECT_EQ(accepted, kMaxFrameStages - FramePath::kFrontEndStages.size());
  const Status s = path.append_stage(stage);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("tracking"), std::string::npos) << s.message();
}

// New enhancement thresholds take effect on the next frame and keep the held class: a frame mean
// within the hysteresis of the moved threshold stays in the class it held, where configure()
// would grade it afresh.
TEST(FramePath, SetEnhanceAppliesFromTheNextFrameAndKeepsTheHeldClass) {
  features::ExtractorConfig config;
  config.mode = features::ExtractorMode::kAle;
  config.enhance.grading.t_very_low = 50;
  config.enhance.grading.t_low = 70;
  config.enhance.grading.hysteresis = 4;
  FramePath path;
  ASSERT_TRUE(path.configure(config).ok());
  const GrayImage frame(96, 64, 72);  // normal: 72 >= t_low
  std::vector<features::Keypoint> kp;
  std::vector<features::Descriptor> desc;
  ASSERT_TRUE(path.extract(frame.view(), kp, desc).ok());
  EXPECT_EQ(path.stats().brightness, BrightnessClass::kNormal);

  enhance::EnhanceParams moved = config.enhance;
  moved.grading.t_low = 74;  // 72 is below it, but within the hysteresis of the held class
  ASSERT_TRUE(path.set_enhance(moved).ok());
  EXPECT_EQ(path.config().enhance.grading.t_low, 74);
  ASSERT_TRUE(path.extract(frame.view(), kp, desc).ok());
  EXPECT_EQ(path.stats().brightness, BrightnessClass::kNormal) << "the held class stays";

  moved.grading.t_low = 80;  // beyond the hysteresis: dark from the next frame on
  ASSERT_TRUE(path.set_enhance(moved).ok());
  ASSERT_TRUE(path.extract(frame.view(), kp, desc).ok());
  EXPECT_EQ(path.stats().brightness, BrightnessClass::kDark);

  // configure() with the same thresholds forgets the held class: 72 < 74 is dark at once.
  FramePath fresh;
  features::ExtractorConfig c74 = config;
  c74.enhance.grading.t_low = 74;
  ASSERT_TRUE(fresh.configure(c74).ok());
  ASSERT_TRUE(fresh.extract(frame.view(), kp, desc).ok());
  EXPECT_EQ(fresh.stats().brightness, BrightnessClass::kDark);
}

TEST(FramePath, SetEnhanceRefusesBadParametersAndKeepsTheOldOnes) {
  FramePath unconfigured;
  EXPECT_EQ(unconfigured.set_enhance(enhance::EnhanceParams{}).code(), StatusCode::kInvalidArgument);
  FramePath path;
  ASSERT_TRUE(path.configure(features::ExtractorConfig{}).ok());
  const double t_low = path.config().enhance.grading.t_low;
  enhance::EnhanceParams bad = path.config().enhance;
  bad.grading.t_low = bad.grading.t_very_low - 1;  // below t_very_low
  const Status s = path.set_enhance(bad);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("enhance.grading.t_low"), std::string::npos) << s.message();
  EXPECT_EQ(path.config().enhance.grading.t_low, t_low);
}

}  // namespace
}  // namespace ale::frontend
