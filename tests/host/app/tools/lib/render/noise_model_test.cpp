// The sensor noise models (noise_model.h, `ale-render --noise-model`): the standard model is the
// sensor model as it was before the others existed, every model is deterministic per seed, and
// each one changes the frame the way it says: cos^4 corners, a pattern fixed over the frames,
// row banding, more noise from a smaller pixel, 8x8 block structure from the compression.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "app/tools/lib/render/noise_model.h"
#include "app/tools/lib/render/renderer.h"
#include "render_fixture.h"

namespace ale::render {
namespace {

using test::small_scene;

SensorParams model(const std::string& name) {
  SensorParams p;
  const Status s = apply_noise_model(name, p);
  EXPECT_TRUE(s.ok()) << s.to_string();
  return p;
}

// Model `name` without the standard quadratic vignetting, so that a flat scene gives a flat
// frame.
SensorParams unvignetted(const std::string& name) {
  SensorParams p = model(name);
  p.vignetting_corner = 1.0;
  return p;
}

std::vector<float> flat(const PinholeCamera& c, float radiance) {
  return std::vector<float>(static_cast<std::size_t>(c.width) * static_cast<std::size_t>(c.height), radiance);
}

GrayImage expose(const SensorModel& m, const std::vector<float>& radiance, const ExposureState& e, std::uint64_t seed) {
  GrayImage img(m.width(), m.height());
  m.expose(radiance, e, seed, img.view());
  return img;
}

// Grey level -> electrons before the gain, through the inverse response curve.
double to_electrons(std::uint8_t grey, const SensorParams& p, const ExposureState& e) {
  return SensorModel::inverse_response(grey / 255.0) * p.full_well_e / e.gain;
}

double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
  ma /= static_cast<double>(a.size());
  mb /= static_cast<double>(b.size());
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

// The bytes of the standard model on a textured radiance field, hashed (FNV-1a). The value was
// taken from the sensor model before the noise models were added (commit 7e664f4, its
// SensorModel(params, 64, 48)): a change here changes every rendered sequence without
// --noise-model.
TEST(RenderNoiseModel, StandardIsTheSensorModelAsItWas) {
  const PinholeCamera cam = PinholeCamera::wide(64, 48);
  std::vector<float> radiance(64 * 48);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      radiance[static_cast<std::size_t>(y * 64 + x)] = 2.0f + 1.5f * static_cast<float>((x * 7 + y * 13) % 32);
  // From parameters another model left behind: apply_noise_model resets them all.
  SensorParams p = model("harsh");
  ASSERT_TRUE(apply_noise_model("standard", p).ok());
  const SensorModel m(p, cam, 99);
  std::uint64_t hash = 1469598103934665603ULL;
  const double expected_mean[] = {62.183919, 111.336589, 202.600586};
  for (int k = 0; k < 3; ++k) {
    ExposureState e;
    e.exposure_us = k == 0 ? 20000 : 33000;
    e.gain = k == 2 ? 8.0 : 1.0 + k;
    GrayImage img(64, 48);
    EXPECT_NEAR(m.expose(radiance, e, 1234 + static_cast<std::uint64_t>(k), img.view()), expected_mean[k], 1e-6);
    for (std::uint8_t v : img.pixels) {
      hash ^= v;
      hash *= 1099511628211ULL;
    }
  }
  EXPECT_EQ(hash, 0xad770e8d5ebe94a5ULL);
}

// Every model through the whole renderer: the same seed gives the same bytes, another seed
// other noise; every model but the standard one gives other frames than the standard.
TEST(RenderNoiseModel, SameSeedSameBytesForEveryModel) {
  auto render = [](const std::string& name, std::uint64_t seed) {
    SequenceConfig c;
    c.camera = PinholeCamera::wide(96, 72);
    c.light = LightProfile::kNormalDark;
    c.seed = seed;
    c.frames = 2;
    c.supersample = 1;
    EXPECT_TRUE(apply_noise_model(name, c.sensor).ok());
    const Trajectory traj = make_loop(small_scene(), DriveOptions{}, 1.0);
    Result<SequenceRenderer> seq = SequenceRenderer::create(small_scene(), traj, sweeper_rig(12.0), c);
    EXPECT_TRUE(seq.ok()) << seq.status().to_string();
    GrayImage img(96, 72);
    std::vector<std::uint8_t> bytes;
    FrameRecord rec;
    for (int k = 0; seq.ok() && k < c.frames; ++k) {
      EXPECT_TRUE(seq->render_next(img.view(), rec).ok());
      bytes.insert(bytes.end(), img.pixels.begin(), img.pixels.end());
    }
    return bytes;
  };
  const std::vector<std::uint8_t> standard = render("standard", 3);
  for (const std::string& name : noise_model_names()) {
    const std::vector<std::uint8_t> a = render(name, 3);
    ASSERT_EQ(a.size(), 2u * 96u * 72u) << name;
    EXPECT_EQ(a, render(name, 3)) << name;
    EXPECT_NE(a, render(name, 4)) << name;
    if (name != "standard") {
      EXPECT_NE(a, standard) << name;
    }
  }
}

TEST(RenderNoiseModel, UnknownNameAndOutOfRangeValuesAreRefused) {
  SensorParams p;
  const Status s = apply_noise_model("pink", p);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(s.message().find("'pink' is not one of standard, small-pixel, fpn, vignetting, banding, jpeg, harsh"),
            std::string::npos)
      << s.message();
  EXPECT_TRUE(validate_noise(p).ok());
  p.jpeg_quality = 101;
  EXPECT_NE(validate_noise(p).message().find("JPEG quality"), std::string::npos);
  p = SensorParams{};
  p.row_noise_e = -1.0;
  EXPECT_NE(validate_noise(p).message().find("row noise"), std::string::npos);
  p = SensorParams{};
  p.fpn_gain = 0.9;
  EXPECT_NE(validate_noise(p).message().find("fixed-pattern gain"), std::string::npos);
  // The renderer refuses them too.
  SequenceConfig c;
  c.camera = PinholeCamera::wide(32, 24);
  c.frames = 1;
  c.sensor.vignetting_power = 9.0;
  const Trajectory traj = make_loop(small_scene(), DriveOptions{}, 1.0);
  EXPECT_EQ(SequenceRenderer::create(small_scene(), traj, sweeper_rig(12.0), c).status().code(),
            StatusCode::kInvalidArgument);
}

// On a flat scene the corners are darker than the centre by cos^4 of their angle off axis (the
// standard model's quadratic fall-off gives 0.62 there).
TEST(RenderNoiseModel, VignettingDarkensTheCornersByCosToTheFourth) {
  const PinholeCamera cam = PinholeCamera::wide(160, 120);
  ExposureState e;
  e.exposure_us = 10000;
  e.gain = 1.0;
  // 4800 e- in the centre, 0.6 of the full well: no clipping, shot noise 1.4 %.
  const std::vector<float> radiance = flat(cam, 480.0f);
  for (const std::string& name : {std::string("vignetting"), std::string("standard")}) {
    const SensorParams p = model(name);
    const SensorModel m(p, cam, 1);
    const GrayImage img = expose(m, radiance, e, 5);
    // 8x8 patches in the top-left corner and around the centre; the expected ratio averages the
    // model's law over the same pixels.
    double corner = 0, centre = 0, corner_law = 0, centre_law = 0;
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) {
        corner += to_electrons(img.view().at(x, y), p, e);
        centre += to_electrons(img.view().at(76 + x, 56 + y), p, e);
        for (int c = 0; c < 2; ++c) {
          const double u = c == 0 ? x : 76 + x, v = c == 0 ? y : 56 + y;
          const double tx = (u - cam.cx) / cam.fx, ty = (v - cam.cy) / cam.fy;
          const double r2 = ((u - cam.cx) * (u - cam.cx) + (v - cam.cy) * (v - cam.cy)) / (cam.cx * cam.cx + cam.cy * cam.cy);
          const double law = name == "vignetting" ? std::pow(1.0 + tx * tx + ty * ty, -2.0) : 1.0 - 0.38 * r2;
          (c == 0 ? corner_law : centre_law) += law;
        }
      }
    const double expected = corner_law / centre_law;
    EXPECT_NEAR(corner / centre, expected, 0.03 * expected) << name;
    if (name == "vignetting") {
      EXPECT_LT(corner / centre, 0.2);  // 0.15 at the corner pixel itself
    }
  }
}

// The fixed pattern stays over the frames: the per-pixel means of two sets of frames with other
// noise seeds agree (correlate), and differ for another pattern seed; without it they do not.
TEST(RenderNoiseModel, FixedPatternIsConstantOverTheFrames) {
  const PinholeCamera cam = PinholeCamera::wide(64, 48);
  ExposureState e;
  e.exposure_us = 10000;
  e.gain = 1.0;
  const std::vector<float> radiance = flat(cam, 200.0f);  // 2000 e-, shot noise 45 e-
  auto mean_of_frames = [&](const SensorParams& p, std::uint64_t pattern_seed, std::uint64_t first_seed) {
    const SensorModel m(p, cam, pattern_seed);
    std::vector<double> mean(radiance.size(), 0.0);
    for (std::uint64_t k = 0; k < 32; ++k) {
      const GrayImage img = expose(m, radiance, e, first_seed + k);
      for (std::size_t i = 0; i < mean.size(); ++i) mean[i] += to_electrons(img.pixels[i], p, e) / 32.0;
    }
    return mean;
  };
  const SensorParams fpn = unvignetted("fpn");
  const std::vector<double> a = mean_of_frames(fpn, 7, 100);
  EXPECT_GT(correlation(a, mean_of_frames(fpn, 7, 200)), 0.8);
  EXPECT_LT(std::fabs(correlation(a, mean_of_frames(fpn, 8, 200))), 0.2);
  const SensorParams standard = unvignetted("standard");
  EXPECT_LT(std::fabs(correlation(mean_of_frames(standard, 7, 100), mean_of_frames(standard, 7, 200))), 0.2);
  // The pattern's spread: 1.5 % of 2000 e- and 6 e- rms, 30.6 e- together; the 32-frame means
  // keep 45 / sqrt(32) = 8 e- of shot noise.
  double m = 0, var = 0;
  for (double v : a) m += v;
  m /= static_cast<double>(a.size());
  for (double v : a) var += (v - m) * (v - m);
  const double spread = std::sqrt(var / static_cast<double>(a.size()) - 45.0 * 45.0 / 32.0);
  EXPECT_NEAR(spread, std::hypot(0.015 * 2000.0, 6.0), 4.0);
}

// Row noise: the rows' means scatter by the model's 3 e- beyond what the pixels' own noise
// gives; the columns' do not.
TEST(RenderNoiseModel, BandingOffsetsWholeRows) {
  const PinholeCamera cam = PinholeCamera::wide(160, 120);
  ExposureState e;
  e.exposure_us = 10000;
  e.gain = 8.0;
  const std::vector<float> radiance = flat(cam, 20.0f);  // 200 e-
  auto excess = [&](const std::string& name, bool rows) {
    const SensorParams p = unvignetted(name);
    const SensorModel m(p, cam, 1);
    double total = 0;
    for (std::uint64_t seed = 1; seed <= 4; ++seed) {
      const GrayImage img = expose(m, radiance, e, seed);
      const int lines = rows ? cam.height : cam.width, along = rows ? cam.width : cam.height;
      std::vector<double> means(static_cast<std::size_t>(lines), 0.0);
      double pixel_var = 0, grand = 0;
      std::vector<double> values;
      for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
          const double v = to_electrons(img.view().at(x, y), p, e);
          means[static_cast<std::size_t>(rows ? y : x)] += v / along;
          grand += v;
          values.push_back(v);
        }
      grand /= static_cast<double>(values.size());
      for (double v : values) pixel_var += (v - grand) * (v - grand);
      pixel_var /= static_cast<double>(values.size());
      double line_var = 0;
      for (double v : means) line_var += (v - grand) * (v - grand);
      line_var /= lines;
      // The lines' scatter beyond the pixels' noise averaged along them.
      total += line_var - (pixel_var - line_var) / (along - 1);
    }
    return std::sqrt(std::max(0.0, total / 4.0));
  };
  EXPECT_NEAR(excess("banding", true), 3.0, 0.6);
  EXPECT_LT(excess("banding", false), 1.0);
  EXPECT_LT(excess("standard", true), 1.0);
}

// The smaller pixel holds fewer electrons for the same grey level: at the same linear level its
// frame-to-frame noise is larger by about sqrt(8000 / 3500) = 1.5 (shot noise dominates).
TEST(RenderNoiseModel, SmallPixelIsNoisierAtTheSameGrey) {
  const PinholeCamera cam = PinholeCamera::wide(96, 72);
  auto temporal_noise = [&](const std::string& name) {
    const SensorParams p = unvignetted(name);
    const SensorModel m(p, cam, 1);
    ExposureState e;
    e.gain = 1.0;
    // Linear level 0.3: 0.3 x full well electrons.
    e.exposure_us = 10000;
    const std::vector<float> radiance = flat(cam, static_cast<float>(0.3 * p.full_well_e / (p.sensitivity * 10000)));
    const GrayImage a = expose(m, radiance, e, 1), b = expose(m, radiance, e, 2);
    double mean = 0, var = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) {
      const double d = SensorModel::inverse_response(a.pixels[i] / 255.0) - SensorModel::inverse_response(b.pixels[i] / 255.0);
      mean += SensorModel::inverse_response(a.pixels[i] / 255.0);
      var += d * d;
    }
    EXPECT_NEAR(mean / static_cast<double>(a.pixels.size()), 0.3, 0.01) << name;
    return std::sqrt(var / (2.0 * static_cast<double>(a.pixels.size())));
  };
  const double ratio = temporal_noise("small-pixel") / temporal_noise("standard");
  EXPECT_GT(ratio, 1.35);
  EXPECT_LT(ratio, 1.7);
}

// Blockiness: across the 8x8 blocks' borders neighbouring pixels differ more than inside them
// after the compression, not before; and the steps grow with frequency and shrink with quality.
TEST(RenderNoiseModel, CompressionLeavesEightByEightBlocks) {
  EXPECT_EQ(block_step(0, 0, 75), 6);
  EXPECT_EQ(block_step(7, 7, 75), 55);
  EXPECT_EQ(block_step(7, 7, 100), 1);
  EXPECT_GT(block_step(3, 2, 20), block_step(3, 2, 60));
  const PinholeCamera cam = PinholeCamera::wide(160, 120);
  ExposureState e;
  e.exposure_us = 10000;
  e.gain = 2.0;
  // A gentle gradient with noise: smooth inside a block, so the blocks' means step.
  std::vector<float> radiance(static_cast<std::size_t>(cam.width * cam.height));
  for (int y = 0; y < cam.height; ++y)
    for (int x = 0; x < cam.width; ++x) radiance[static_cast<std::size_t>(y * cam.width + x)] = 60.0f + 1.5f * static_cast<float>(x) + 0.5f * static_cast<float>(y);
  auto blockiness = [&](const std::string& name) {
    const SensorModel m(model(name), cam, 1);
    const GrayImage img = expose(m, radiance, e, 9);
    double across = 0, inside = 0;
    int n_across = 0, n_inside = 0;
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x + 1 < cam.width; ++x) {
        const double d = std::fabs(img.view().at(x + 1, y) - img.view().at(x, y));
        if (x % 8 == 7) across += d, ++n_across;
        else inside += d, ++n_inside;
      }
    return (across / n_across) / (inside / n_inside);
  };
  EXPECT_GT(blockiness("jpeg"), 1.5);
  EXPECT_NEAR(blockiness("standard"), 1.0, 0.15);
  // Quality 100 (every step 1) keeps the image within a grey level or two.
  GrayImage img(37, 21);  // partial blocks at the right and bottom edges
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) img.view().at(x, y) = static_cast<std::uint8_t>((x * 29 + y * 47) % 256);
  GrayImage out = img;
  compress_blocks(out.view(), 100);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) ASSERT_LE(std::abs(out.pixels[i] - img.pixels[i]), 2) << i;
}

}  // namespace
}  // namespace ale::render
