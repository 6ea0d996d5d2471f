// Whole frames: determinism per seed, the ordering of the five light levels, their grading by
// the enhancement module, and the auto-exposure's caps and lag.
#include <gtest/gtest.h>

#include <vector>

#include "core/enhance/grading.h"
#include "app/tools/lib/render/renderer.h"
#include "render_fixture.h"

namespace ale::render {
namespace {

using test::small_scene;

SequenceConfig small_config(LightProfile light, std::uint64_t seed, int frames) {
  SequenceConfig c;
  c.camera = PinholeCamera::wide(160, 120);
  c.light = light;
  c.seed = seed;
  c.frames = frames;
  c.supersample = 1;
  return c;
}

// Renders `frames` frames of the default loop and returns the last one (and its record).
GrayImage render_last(LightProfile light, std::uint64_t seed, int frames, FrameRecord* last = nullptr,
                      std::vector<FrameRecord>* all = nullptr) {
  const SequenceConfig config = small_config(light, seed, frames);
  const Trajectory traj = make_loop(small_scene(), DriveOptions{}, (frames - 1) / config.fps + 0.1);
  Result<SequenceRenderer> seq = SequenceRenderer::create(small_scene(), traj, sweeper_rig(12.0), config);
  EXPECT_TRUE(seq.ok()) << seq.status().to_string();
  GrayImage img(config.camera.width, config.camera.height);
  if (!seq.ok()) return img;
  FrameRecord rec;
  for (int k = 0; k < frames; ++k) {
    const Status s = seq->render_next(img.view(), rec);
    EXPECT_TRUE(s.ok()) << s.to_string();
    if (all != nullptr) all->push_back(rec);
  }
  EXPECT_EQ(seq->render_next(img.view(), rec).code(), StatusCode::kEndOfStream);
  if (last != nullptr) *last = rec;
  return img;
}

double mean_of(const GrayImage& img) {
  double s = 0;
  for (std::uint8_t p : img.pixels) s += p;
  return s / static_cast<double>(img.pixels.size());
}

TEST(RenderSequence, SameSeedSameFrameOtherSeedOtherNoise) {
  const GrayImage a = render_last(LightProfile::kNormal, 7, 3);
  const GrayImage b = render_last(LightProfile::kNormal, 7, 3);
  const GrayImage c = render_last(LightProfile::kNormal, 8, 3);
  EXPECT_EQ(a.pixels, b.pixels);
  ASSERT_EQ(a.pixels.size(), c.pixels.size());
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.pixels.size(); ++i) differ += a.pixels[i] != c.pixels[i];
  // Noise changes most pixels by a grey level or so, not the picture.
  EXPECT_GT(differ, a.pixels.size() / 4);
  EXPECT_NEAR(mean_of(a), mean_of(c), 1.0);
}

TEST(RenderSequence, FrameIsNotFlat) {
  // A textured room, not a uniform grey: a feature detector needs contrast.
  const GrayImage a = render_last(LightProfile::kNormal, 1, 1);
  double m = mean_of(a), var = 0;
  for (std::uint8_t p : a.pixels) var += (p - m) * (p - m);
  EXPECT_GT(var / static_cast<double>(a.pixels.size()), 15.0 * 15.0);
}

TEST(RenderSequence, FiveLevelsAreOrderedAndGraded) {
  const LightProfile levels[] = {LightProfile::kDark, LightProfile::kNormalDark, LightProfile::kNormal,
                                 LightProfile::kNormalBright, LightProfile::kBright};
  std::vector<double> means;
  for (LightProfile p : levels) {
    FrameRecord rec;
    const GrayImage img = render_last(p, 1, 2, &rec);
    EXPECT_NEAR(rec.mean_grey, mean_of(img), 1e-9);
    means.push_back(rec.mean_grey);
  }
  for (std::size_t i = 1; i < means.size(); ++i)
    EXPECT_LT(means[i - 1], means[i]) << to_string(levels[i - 1]) << " vs " << to_string(levels[i]);
  // The enhancement module's grading (default thresholds) sees the dark ones as dark.
  const enhance::GradingParams grading;
  const BrightnessClass dark = enhance::classify(means[0], grading);
  const BrightnessClass normal_dark = enhance::classify(means[1], grading);
  EXPECT_TRUE(dark == BrightnessClass::kExtremelyDark || dark == BrightnessClass::kDark) << means[0];
  EXPECT_TRUE(normal_dark == BrightnessClass::kExtremelyDark || normal_dark == BrightnessClass::kDark) << means[1];
  EXPECT_EQ(enhance::classify(means[2], grading), BrightnessClass::kNormal) << means[2];
  EXPECT_EQ(enhance::classify(means[4], grading), BrightnessClass::kBright) << means[4];
}

TEST(RenderSequence, AutoExposureIsCappedAndLags) {
  // off_on over 30 frames: lamps off for frames 9..17, on again from 18.
  std::vector<FrameRecord> recs;
  render_last(LightProfile::kOffOn, 3, 30, nullptr, &recs);
  ASSERT_EQ(recs.size(), 30u);
  const SensorParams sp;
  for (const FrameRecord& r : recs) {
    EXPECT_GE(r.exposure.exposure_us, sp.min_exposure_us);
    EXPECT_LE(r.exposure.exposure_us, sp.max_exposure_us);
    EXPECT_GE(r.exposure.gain, 1.0);
    EXPECT_LE(r.exposure.gain, sp.max_gain);
  }
  EXPECT_TRUE(recs[8].light.lamps_on);
  EXPECT_FALSE(recs[9].light.lamps_on);
  EXPECT_FALSE(recs[17].light.lamps_on);
  EXPECT_TRUE(recs[18].light.lamps_on);
  // Lights off: the frame goes dark at once, the exposure climbs over the following frames.
  EXPECT_LT(recs[9].mean_grey, 0.5 * recs[8].mean_grey);
  EXPECT_GT(recs[17].exposure.product(), 1.5 * recs[9].exposure.product());
  // Lights on again: the first frame is over-exposed, later ones come back towards the target.
  EXPECT_GT(recs[18].mean_grey, recs[8].mean_grey + 30.0);
  EXPECT_LT(recs[29].mean_grey, recs[18].mean_grey - 20.0);
  EXPECT_LT(recs[29].exposure.product(), recs[18].exposure.product());
}

TEST(RenderSequence, SunPatchSaturates) {
  FrameRecord rec;
  const GrayImage img = render_last(LightProfile::kSunlit, 1, 1, &rec);
  std::size_t saturated = 0;
  for (std::uint8_t p : img.pixels) saturated += p == 255;
  // The patch is in view at the start of the loop and clips, while the rest stays exposed.
  EXPECT_GT(saturated, img.pixels.size() / 50);
  EXPECT_LT(saturated, img.pixels.size() / 2);
}

TEST(RenderSequence, RejectsBadConfiguration) {
  const Trajectory traj = make_loop(small_scene(), DriveOptions{}, 1.0);
  SequenceConfig c = small_config(LightProfile::kNormal, 1, 100);  // 3.3 s > 1 s of trajectory
  EXPECT_EQ(SequenceRenderer::create(small_scene(), traj, sweeper_rig(12.0), c).status().code(),
            StatusCode::kInvalidArgument);
  c.frames = 10;
  c.fps = 0.0;
  EXPECT_FALSE(SequenceRenderer::create(small_scene(), traj, sweeper_rig(12.0), c).ok());
  c.fps = 30.0;
  c.supersample = 9;
  EXPECT_FALSE(SequenceRenderer::create(small_scene(), traj, sweeper_rig(12.0), c).ok());
  c.supersample = 1;
  Result<SequenceRenderer> ok = SequenceRenderer::create(small_scene(), traj, sweeper_rig(12.0), c);
  ASSERT_TRUE(ok.ok());
  GrayImage wrong(10, 10);
  FrameRecord rec;
  EXPECT_EQ(ok->render_next(wrong.view(), rec).code(), StatusCode::kInvalidArgument);
}

TEST(RenderLighting, ParsesEveryProfileAndRejectsOthers) {
  for (const char* name : {"bright", "normal_bright", "normal", "normal_dark", "dark", "off_on", "sunlit", "dimming"}) {
    Result<LightProfile> p = parse_light_profile(name);
    ASSERT_TRUE(p.ok()) << name;
    EXPECT_STREQ(to_string(*p), name);
  }
  Result<LightProfile> bad = parse_light_profile("twilight");
  EXPECT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("twilight"), std::string::npos);
  // Dimming falls steadily.
  EXPECT_GT(light_at(LightProfile::kDimming, 0.0).room_lux, light_at(LightProfile::kDimming, 0.5).room_lux);
  EXPECT_GT(light_at(LightProfile::kDimming, 0.5).room_lux, light_at(LightProfile::kDimming, 1.0).room_lux);
}

}  // namespace
}  // namespace ale::render
