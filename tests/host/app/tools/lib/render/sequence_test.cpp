// Whole frames: determinism per seed, the ordering of the five light levels, their grading by
// the enhancement module, and the auto-exposure's caps and lag.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
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

// Renders every frame of `config` along `traj` in the small room; the records.
std::vector<FrameRecord> render_all(const SequenceConfig& config, const Trajectory& traj,
                                    std::vector<GrayImage>* images = nullptr) {
  std::vector<FrameRecord> recs;
  Result<SequenceRenderer> seq = SequenceRenderer::create(small_scene(), traj, sweeper_rig(12.0), config);
  EXPECT_TRUE(seq.ok()) << seq.status().to_string();
  if (!seq.ok()) return recs;
  GrayImage img(config.camera.width, config.camera.height);
  FrameRecord rec;
  while (seq->render_next(img.view(), rec).ok()) {
    recs.push_back(rec);
    if (images != nullptr) images->push_back(img);
  }
  return recs;
}

TEST(RenderSequence, BlackoutLeavesOnlyNoiseThenTheLightComesBack) {
  // 10 fps, 30 frames; all light off from 1.0 s for 0.8 s (frames 10..17).
  SequenceConfig c = small_config(LightProfile::kNormal, 3, 30);
  c.fps = 10.0;
  c.blackouts.push_back({1.0, 0.8});
  const Trajectory traj = make_loop(small_scene(), DriveOptions{}, 3.0);
  std::vector<GrayImage> images;
  const std::vector<FrameRecord> recs = render_all(c, traj, &images);
  ASSERT_EQ(recs.size(), 30u);
  for (const FrameRecord& r : recs) EXPECT_EQ(r.blackout, r.index >= 10 && r.index <= 17) << r.index;
  EXPECT_FALSE(recs[12].light.lamps_on);
  EXPECT_EQ(recs[12].light.off_lux, 0.0f);
  // In the dark the auto-exposure goes to its limits and the frame holds only noise: no picture,
  // whatever the gain (off_on keeps 2 lux and shows the room).
  EXPECT_GT(recs[17].exposure.product(), 1.5 * recs[10].exposure.product());
  EXPECT_LT(recs[17].mean_grey, 10.0);
  EXPECT_GT(recs[9].mean_grey, 80.0);
  EXPECT_GT(recs[18].mean_grey, recs[9].mean_grey);  // the first frame back is over-exposed
  // Timestamps carry on: a blackout leaves no gap.
  for (const FrameRecord& r : recs) EXPECT_EQ(r.gap_ns, 0);
  // Without the blackout the frames before it are the same, bit for bit.
  SequenceConfig plain = c;
  plain.blackouts.clear();
  std::vector<GrayImage> plain_images;
  render_all(plain, traj, &plain_images);
  ASSERT_EQ(plain_images.size(), 30u);
  EXPECT_EQ(images[9].pixels, plain_images[9].pixels);
  EXPECT_NE(images[12].pixels, plain_images[12].pixels);
}

TEST(RenderSequence, KidnapJumpsBackAlongTheTrajectoryAfterAGap) {
  // 10 fps, 40 frames; at 2.0 s on the trajectory the camera jumps to its pose at 0.5 s and the
  // timestamps go on after 1.5 s without frames; at 2.0 s again (1.5 s later) to 1.0 s, no gap.
  SequenceConfig c = small_config(LightProfile::kNormal, 3, 40);
  c.fps = 10.0;
  c.kidnaps.push_back({2.0, 0.5, 1.5});
  c.kidnaps.push_back({2.0, 1.0, 0.0});
  const Trajectory traj = make_loop(small_scene(), DriveOptions{}, 4.0);
  const std::vector<FrameRecord> recs = render_all(c, traj);
  ASSERT_EQ(recs.size(), 40u);
  EXPECT_NEAR(recs[19].t_s, 1.9, 1e-9);
  EXPECT_EQ(recs[19].gap_ns, 0);
  EXPECT_NEAR(recs[20].t_s, 0.5, 1e-9);
  EXPECT_EQ(recs[20].gap_ns, 1500000000);
  EXPECT_NEAR(recs[34].t_s, 1.9, 1e-9);
  EXPECT_NEAR(recs[35].t_s, 1.0, 1e-9);
  EXPECT_EQ(recs[35].gap_ns, 1500000000);
  // The camera is where the trajectory was at that time: a place already seen.
  EXPECT_LT((recs[20].camera.p_wb - recs[5].camera.p_wb).norm(), 1e-9);
  EXPECT_LT(recs[20].camera.q_wb.angularDistance(recs[5].camera.q_wb), 1e-9);
  // Kidnaps that go forwards, or happen before the previous one's place, are refused.
  const Rig rig = sweeper_rig(12.0);
  SequenceConfig bad = c;
  bad.kidnaps = {{1.0, 2.0, 0.0}};
  EXPECT_EQ(SequenceRenderer::create(small_scene(), traj, rig, bad).status().code(), StatusCode::kInvalidArgument);
  bad.kidnaps = {{2.0, 1.0, 0.0}, {0.8, 0.2, 0.0}};
  EXPECT_FALSE(SequenceRenderer::create(small_scene(), traj, rig, bad).ok());
  bad.kidnaps = {{2.0, 1.0, -1.0}};
  EXPECT_FALSE(SequenceRenderer::create(small_scene(), traj, rig, bad).ok());
  bad.kidnaps.clear();
  bad.blackouts = {{1.0, 0.0}};
  EXPECT_FALSE(SequenceRenderer::create(small_scene(), traj, rig, bad).ok());
}

TEST(RenderSequence, TwinRoomsLookAlike) {
  SceneOptions o;
  o.texel_scale = 3.0f;
  Result<Scene> twin = build_twin_scene(o);
  ASSERT_TRUE(twin.ok()) << twin.status().to_string();
  EXPECT_FLOAT_EQ(twin->size.x(), 12.0f);
  const Renderer r(*twin, PinholeCamera::wide(80, 60), 1);
  // The same place in each room, looking at the south wall, then at the partition from the left
  // room and at the east wall from the right one: the pictures agree (the partition stands 5 cm
  // nearer than the wall it copies).
  const Eigen::Matrix3d R_wc = sweeper_rig(12.0).R_bc;  // looking +x
  const Eigen::Matrix3d turn_right = Eigen::AngleAxisd(-0.5 * 3.14159265358979, Eigen::Vector3d::UnitZ()).matrix();
  LightState light;
  for (const Eigen::Matrix3d& R : {Eigen::Matrix3d(turn_right * R_wc), R_wc}) {
    std::vector<float> left, right;
    r.render(R, Eigen::Vector3d(2.5, 2.0, 0.09), light, left);
    r.render(R, Eigen::Vector3d(8.5, 2.0, 0.09), light, right);
    double diff = 0.0, sum = 0.0;
    for (std::size_t i = 0; i < left.size(); ++i) {
      diff += std::abs(left[i] - right[i]);
      sum += left[i];
    }
    EXPECT_LT(diff, 0.05 * sum);
    // ... and unlike a view from elsewhere in the same room.
    std::vector<float> elsewhere;
    r.render(R, Eigen::Vector3d(4.0, 3.0, 0.09), light, elsewhere);
    double other = 0.0;
    for (std::size_t i = 0; i < left.size(); ++i) other += std::abs(left[i] - elsewhere[i]);
    EXPECT_GT(other, 4.0 * diff);
  }
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
