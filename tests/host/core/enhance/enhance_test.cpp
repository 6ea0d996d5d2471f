// Grading with hysteresis, CDF gamma, contrast-guided CLAHE settings, and the whole enhancement
// on real frames: classes, FAST-9 corner counts before/after, normal frames unchanged.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/enhance/enhancer.h"
#include "core/enhance/noise.h"
#include "core/io/image_io.h"
#include "tests/host/core/enhance/real_frames.h"
#include "tests/host/support/test_data.h"

namespace ale::enhance {
namespace {

// Test-only FAST-9 (no non-maximum suppression): a pixel is a corner when 9 contiguous pixels of
// the 16 on the radius-3 circle are all brighter than p + t or all darker than p - t.
int count_fast9(GrayView img, int t) {
  static const int kCircle[16][2] = {{0, -3}, {1, -3},  {2, -2},  {3, -1}, {3, 0},  {3, 1},  {2, 2},  {1, 3},
                                     {0, 3},  {-1, 3}, {-2, 2}, {-3, 1}, {-3, 0}, {-3, -1}, {-2, -2}, {-1, -3}};
  int corners = 0;
  for (int y = 3; y < img.height - 3; ++y) {
    for (int x = 3; x < img.width - 3; ++x) {
      const int p = img.at(x, y);
      int state[16];
      for (int i = 0; i < 16; ++i) {
        const int v = img.at(x + kCircle[i][0], y + kCircle[i][1]);
        state[i] = v > p + t ? 1 : (v < p - t ? -1 : 0);
      }
      bool corner = false;
      for (int sign : {1, -1}) {
        int run = 0;
        for (int i = 0; i < 32 && !corner; ++i) {
          run = state[i % 16] == sign ? run + 1 : 0;
          corner = run >= 9;
        }
      }
      corners += corner ? 1 : 0;
    }
  }
  return corners;
}

GrayImage load(const std::string& path) {
  GrayImage img;
  const Status st = io::read_gray(path, img);
  EXPECT_TRUE(st.ok()) << st.to_string();
  return img;
}

GrayImage scaled(const GrayImage& in, double gain) {
  GrayImage out = in;
  for (auto& v : out.pixels) v = static_cast<std::uint8_t>(std::min(255.0, std::round(v * gain)));
  return out;
}

double mean_of(const GrayImage& img) {
  FrameStats s;
  compute_stats(img.view(), s);
  return s.mean;
}

// An image whose mean is exactly `mean` (two grey levels mixed in the right proportion).
GrayImage image_with_mean(double mean) {
  GrayImage img(100, 100);
  const int lo = static_cast<int>(std::floor(mean));
  const auto high_count = static_cast<std::size_t>(std::lround((mean - lo) * 10000.0));
  for (std::size_t i = 0; i < img.pixels.size(); ++i)
    img.pixels[i] = static_cast<std::uint8_t>(i < high_count ? lo + 1 : lo);
  return img;
}

TEST(Gamma, LutIsMonotonicWithFixedEnds) {
  for (double g : {0.2, 0.4, 0.507, 0.75, 1.0}) {
    Lut lut{};
    gamma_lut(g, lut);
    EXPECT_EQ(lut[0], 0);
    EXPECT_EQ(lut[255], 255);
    for (int i = 1; i < 256; ++i) EXPECT_GE(lut[static_cast<std::size_t>(i)], lut[static_cast<std::size_t>(i - 1)]) << g;
    if (g < 1.0) {
      for (int i = 1; i < 255; ++i) EXPECT_GE(lut[static_cast<std::size_t>(i)], i) << "gamma < 1 must not darken";
    }
  }
}

// The mean rule with noise_max: a clean frame gets the full lift to the target, a noisier one
// less (its lifted noise at the mean, sigma * gamma * T' / mean, lands on noise_max), one whose
// own noise reaches noise_max none; the lift never grows with the noise.
TEST(Gamma, NoisierFramesGetLessLift) {
  FrameStats s;
  s.histogram[24] = 100;  // mean 24
  stats_from_histogram(s);
  GammaParams p;
  p.target_mean = 54.0;
  p.noise_max = 4.0;
  const double full = std::log(54.0 / 255.0) / std::log(24.0 / 255.0);
  EXPECT_DOUBLE_EQ(cdf_gamma(s, p, 0.0), full) << "noise unknown: the target alone";
  EXPECT_DOUBLE_EQ(cdf_gamma(s, p, 1.0), full) << "1 * gamma * 54 / 24 = 1.48 <= 4";
  const double partial = cdf_gamma(s, p, 3.0);
  EXPECT_GT(partial, full);
  EXPECT_LT(partial, 1.0);
  const double target = 255.0 * std::pow(24.0 / 255.0, partial);  // what the mean maps to
  EXPECT_NEAR(3.0 * partial * target / 24.0, 4.0, 1e-6);
  EXPECT_DOUBLE_EQ(cdf_gamma(s, p, 4.0), 1.0) << "the frame's own noise reaches noise_max";
  EXPECT_DOUBLE_EQ(cdf_gamma(s, p, 7.0), 1.0);
  double last = 0.0;
  for (double sigma = 0.0; sigma <= 5.0; sigma += 0.25) {
    const double g = cdf_gamma(s, p, sigma);
    EXPECT_GE(g, last) << sigma;
    last = g;
  }
  p.noise_max = 0.0;
  EXPECT_DOUBLE_EQ(cdf_gamma(s, p, 7.0), full) << "noise_max 0: the noise is not looked at";
}

TEST(Gamma, DarkerFrameNeverGetsLargerGamma) {
  ALE_REQUIRE_DATA(dir, "euroc_v101_micro/mav0/cam0/data");
  ALE_REQUIRE_DATA(webcams, "lighting/webcam");
  ALE_REQUIRE_DATA(dark, "lighting/dark_frame/euroc_dark.png");
  std::vector<std::string> files = test::every(test::image_files(dir), 30);
  for (const char* cam : test::kWebcams) {
    const auto w = test::every(test::image_files(webcams + "/" + cam), 10);
    files.insert(files.end(), w.begin(), w.end());
  }
  files.push_back(dark);
  const GammaParams p;
  for (const std::string& f : files) {
    const GrayImage img = load(f);
    double previous = 2.0;
    for (double gain : {1.3, 1.0, 0.8, 0.6, 0.4, 0.2}) {
      FrameStats s;
      compute_stats(scaled(img, gain).view(), s);
      const double g = cdf_gamma(s, p);
      EXPECT_LE(g, previous) << f << " gain " << gain;
      EXPECT_GE(g, p.gamma_min);
      EXPECT_LE(g, 1.0);
      previous = g;
    }
  }
  FrameStats dark_stats;
  compute_stats(load(dark).view(), dark_stats);
  EXPECT_LT(cdf_gamma(dark_stats, p), 0.75) << "the real dark frame must be lifted";
}

TEST(Grading, StatsCountEveryPixelOfTheViewOnce) {
  // Widths around the 8-pixel step, rows padded with a marker value that must not be counted,
  // views starting at odd addresses; dark images put neighbours in the same bin.
  std::uint32_t seed = 7;
  for (int width : {1, 2, 7, 8, 9, 15, 16, 17, 33}) {
    for (int range : {3, 256}) {
      const int height = 5, stride = width + 5, start = 3;
      std::vector<std::uint8_t> buf(static_cast<std::size_t>(start + stride * height), 201);
      std::array<std::uint32_t, 256> want{};
      std::vector<int> values;
      std::uint64_t sum = 0, sum_sq = 0;
      for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
          seed = seed * 1664525u + 1013904223u;
          const int v = static_cast<int>((seed >> 24) % static_cast<std::uint32_t>(range));
          buf[static_cast<std::size_t>(start + y * stride + x)] = static_cast<std::uint8_t>(v);
          ++want[static_cast<std::size_t>(v)];
          values.push_back(v);
          sum += static_cast<std::uint64_t>(v);
          sum_sq += static_cast<std::uint64_t>(v * v);
        }
      }
      FrameStats s;
      compute_stats(GrayView{buf.data() + start, width, height, stride}, s);
      EXPECT_EQ(s.histogram, want) << width << " wide, range " << range;
      EXPECT_EQ(s.pixels, values.size());
      const double n = static_cast<double>(values.size());
      EXPECT_DOUBLE_EQ(s.mean, static_cast<double>(sum) / n);
      EXPECT_NEAR(s.sigma, std::sqrt(static_cast<double>(sum_sq) / n - s.mean * s.mean), 1e-9);
      std::sort(values.begin(), values.end());
      EXPECT_EQ(s.median, values[(values.size() - 1) / 2]) << width << " wide, range " << range;
    }
  }
}

// Grading's cheap path must give exactly compute_stats()'s figures (and the histogram's lowest
// grey): every width around the 16-pixel step, the 2048-pixel row limit of the vector sums,
// padded rows, odd starts, and saturated images (the largest sums).
TEST(Grading, MomentsEqualTheStatsMeanAndSigma) {
  std::uint32_t seed = 11;
  for (int width : {1, 5, 15, 16, 17, 31, 32, 33, 47, 640, 752, 2047, 2048, 2049, 3001}) {
    for (int kind = 0; kind < 3; ++kind) {
      // 640 x 430 takes the vector sums past their 16,000-step fold.
      const int height = width > 1000 ? 3 : (width == 640 ? 430 : 9), stride = width + 3, start = 1;
      std::vector<std::uint8_t> buf(static_cast<std::size_t>(start + stride * height), 77);
      for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
          seed = seed * 1664525u + 1013904223u;
          const int v = kind == 0 ? static_cast<int>(seed >> 24) : (kind == 1 ? 255 : static_cast<int>((seed >> 24) % 4u));
          buf[static_cast<std::size_t>(start + y * stride + x)] = static_cast<std::uint8_t>(v);
        }
      }
      const GrayView view{buf.data() + start, width, height, stride};
      FrameStats s;
      compute_stats(view, s);
      const Moments m = compute_moments(view);
      EXPECT_EQ(m.pixels, s.pixels) << width << " kind " << kind;
      EXPECT_EQ(m.mean, s.mean) << width << " kind " << kind;
      EXPECT_EQ(m.sigma, s.sigma) << width << " kind " << kind;
      int lowest = 0;
      while (s.histogram[static_cast<std::size_t>(lowest)] == 0) ++lowest;
      EXPECT_EQ(m.min, lowest) << width << " kind " << kind;
    }
  }
  const Moments empty = compute_moments(GrayView{nullptr, 0, 0, 0});
  EXPECT_EQ(empty.pixels, 0u);
  EXPECT_EQ(empty.mean, 0.0);
}

// The LUT row kernel: every width around the 4-pixel (scalar) and 32-pixel (NEON) steps, every
// grey (the rows run through all 256), padded rows left alone, in place.
TEST(Lut, AppliesToEveryPixelOfTheViewOnly) {
  Lut lut{};
  for (int v = 0; v < 256; ++v) lut[static_cast<std::size_t>(v)] = static_cast<std::uint8_t>((v * 37 + 11) & 0xFF);
  for (int width : {1, 2, 3, 4, 5, 7, 8, 9, 31, 32, 33, 35, 36, 63, 64, 67, 95, 640}) {
    const int height = 3, stride = width + 5;
    std::vector<std::uint8_t> src(static_cast<std::size_t>(stride * height + 1)), dst(src.size(), 0xEE);
    for (std::size_t i = 0; i < src.size(); ++i) src[i] = static_cast<std::uint8_t>(i * 7 + 3);
    ASSERT_TRUE(apply_lut(GrayView{src.data() + 1, width, height, stride},
                          MutableGrayView{dst.data() + 1, width, height, stride}, lut).ok());
    std::vector<std::uint8_t> inplace = src;
    ASSERT_TRUE(apply_lut(GrayView{inplace.data() + 1, width, height, stride},
                          MutableGrayView{inplace.data() + 1, width, height, stride}, lut).ok());
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < stride; ++x) {
        const std::size_t i = static_cast<std::size_t>(1 + y * stride + x);
        if (i >= src.size()) continue;
        if (x < width) {
          ASSERT_EQ(dst[i], lut[src[i]]) << width << " at " << x << "," << y;
          ASSERT_EQ(inplace[i], lut[src[i]]) << width << " in place at " << x << "," << y;
        } else {
          ASSERT_EQ(dst[i], 0xEE) << width << ": wrote past the row at " << x;
          ASSERT_EQ(inplace[i], src[i]) << width << ": wrote past the row in place at " << x;
        }
      }
    }
  }
}

TEST(Grading, ThresholdsWithoutMemory) {
  const GradingParams p;
  EXPECT_EQ(classify(p.t_very_low - 0.01, p), BrightnessClass::kExtremelyDark);
  EXPECT_EQ(classify(p.t_very_low, p), BrightnessClass::kDark);
  EXPECT_EQ(classify(p.t_low - 0.01, p), BrightnessClass::kDark);
  EXPECT_EQ(classify(p.t_low, p), BrightnessClass::kNormal);
  EXPECT_EQ(classify(p.t_high, p), BrightnessClass::kNormal);
  EXPECT_EQ(classify(p.t_high + 0.01, p), BrightnessClass::kBright);
}

int class_changes_in_oscillating_replay(const GradingParams& grading, double threshold) {
  EnhanceParams params;
  params.grading = grading;
  FrameEnhancer enhancer;
  EXPECT_TRUE(enhancer.configure(params).ok());
  const GrayImage below = image_with_mean(threshold - 3.0);
  const GrayImage above = image_with_mean(threshold + 3.0);
  GrayImage out(100, 100);
  int changes = 0;
  BrightnessClass last{};
  for (int i = 0; i < 60; ++i) {
    EnhanceReport r;
    EXPECT_TRUE(enhancer.process((i % 2 == 0 ? below : above).view(), out.view(), r).ok());
    if (i > 0 && r.brightness != last) ++changes;
    last = r.brightness;
  }
  return changes;
}

TEST(Grading, MeanOscillatingByThreeChangesClassAtMostOnce) {
  const GradingParams p;
  for (double t : {p.t_very_low, p.t_low, p.t_high}) {
    EXPECT_LE(class_changes_in_oscillating_replay(p, t), 1) << "threshold " << t;
    // Without hysteresis the same replay flickers every frame: the check above is not vacuous.
    GradingParams none = p;
    none.hysteresis = 0.0;
    EXPECT_GE(class_changes_in_oscillating_replay(none, t), 50) << "threshold " << t;
  }
}

TEST(Grading, HysteresisStillFollowsARealChange) {
  const GradingParams p;
  BrightnessGrader g(p);
  EXPECT_EQ(g.update(100.0), BrightnessClass::kNormal);
  EXPECT_EQ(g.update(p.t_low - 2.0), BrightnessClass::kNormal);
  EXPECT_EQ(g.update(p.t_low - p.hysteresis - 0.5), BrightnessClass::kDark);
  EXPECT_EQ(g.update(p.t_low + 2.0), BrightnessClass::kDark);
  EXPECT_EQ(g.update(20.0), BrightnessClass::kExtremelyDark);
  EXPECT_EQ(g.update(230.0), BrightnessClass::kBright);
}

TEST(RealFrames, GradedAsTheArticleExpects) {
  ALE_REQUIRE_DATA(dark, "lighting/dark_frame/euroc_dark.png");
  ALE_REQUIRE_DATA(micro, "euroc_v101_micro/mav0/cam0/data");
  ALE_REQUIRE_DATA(webcams, "lighting/webcam");
  const GradingParams p;
  const BrightnessClass dark_class = classify(mean_of(load(dark)), p);
  EXPECT_EQ(dark_class, BrightnessClass::kExtremelyDark);

  // The darkest webcam frames (the three lowest means over all cameras).
  std::vector<std::pair<double, std::string>> by_mean;
  for (const char* cam : test::kWebcams)
    for (const std::string& f : test::image_files(webcams + "/" + cam)) by_mean.emplace_back(mean_of(load(f)), f);
  ASSERT_GE(by_mean.size(), 3u);
  std::sort(by_mean.begin(), by_mean.end());
  for (std::size_t i = 0; i < 3; ++i) {
    const BrightnessClass c = classify(by_mean[i].first, p);
    EXPECT_TRUE(c == BrightnessClass::kDark || c == BrightnessClass::kExtremelyDark)
        << by_mean[i].second << " mean " << by_mean[i].first << " graded " << to_string(c);
  }

  for (const std::string& f : test::every(test::image_files(micro), 5)) {
    const GrayImage img = load(f);
    EXPECT_EQ(classify(mean_of(img), p), BrightnessClass::kNormal) << f;
    EXPECT_EQ(classify(mean_of(scaled(img, 1.65)), p), BrightnessClass::kBright) << f << " brightened by 65 %";
  }
}

// FAST-20 corners before and after the enhancement; returns {before, after}.
std::pair<int, int> fast_before_after(const GrayImage& img, BrightnessClass expected_class) {
  FrameEnhancer enhancer;
  GrayImage out(img.width, img.height);
  EnhanceReport r;
  EXPECT_TRUE(enhancer.process(img.view(), out.view(), r).ok());
  EXPECT_EQ(r.brightness, expected_class);
  return {count_fast9(img.view(), 20), count_fast9(out.view(), 20)};
}

TEST(RealFrames, EnhancementAddsFastCornersOnDarkAndBrightFrames) {
  ALE_REQUIRE_DATA(dark, "lighting/dark_frame/euroc_dark.png");
  ALE_REQUIRE_DATA(micro, "euroc_v101_micro/mav0/cam0/data");
  ALE_REQUIRE_DATA(stlouis, "lighting/webcam/stlouis");

  const auto d = fast_before_after(load(dark), BrightnessClass::kExtremelyDark);
  std::printf("dark frame: FAST-20 %d -> %d\n", d.first, d.second);
  EXPECT_GT(d.second, d.first);

  for (const std::string& f : test::image_files(stlouis)) {
    const GrayImage img = load(f);
    if (classify(mean_of(img), GradingParams{}) != BrightnessClass::kDark) continue;
    const auto w = fast_before_after(img, BrightnessClass::kDark);
    std::printf("%s: FAST-20 %d -> %d\n", f.c_str(), w.first, w.second);
    EXPECT_GT(w.second, w.first) << f;
  }

  for (const std::string& f : test::every(test::image_files(micro), 30)) {
    const auto b = fast_before_after(scaled(load(f), 1.65), BrightnessClass::kBright);
    std::printf("%s x1.65: FAST-20 %d -> %d\n", f.c_str(), b.first, b.second);
    EXPECT_GT(b.second, b.first) << f;
  }
}

TEST(RealFrames, NormalFramesPassThroughUnchanged) {
  ALE_REQUIRE_DATA(micro, "euroc_v101_micro/mav0/cam0/data");
  FrameEnhancer enhancer;
  for (const std::string& f : test::every(test::image_files(micro), 10)) {
    const GrayImage img = load(f);
    GrayImage out(img.width, img.height, 7);
    EnhanceReport r;
    ASSERT_TRUE(enhancer.process(img.view(), out.view(), r).ok());
    EXPECT_EQ(r.brightness, BrightnessClass::kNormal) << f;
    EXPECT_EQ(r.gamma, 1.0);
    EXPECT_EQ(r.clip, 0.0);
    EXPECT_TRUE(out.pixels == img.pixels) << f;
  }
}

TEST(LevelClahe, TileEdgeAndClipFollowTheFormulas) {
  const LevelClaheParams p;
  const LevelClaheSettings l0 = level_clahe_settings(p, 1.0, 640, 480, 40.0, 80);
  EXPECT_EQ(l0.tile_edge, static_cast<int>(p.tile_base + p.tile_scale));
  EXPECT_EQ(l0.clahe.tiles_x, static_cast<int>(std::lround(640.0 / l0.tile_edge)));
  EXPECT_DOUBLE_EQ(l0.clahe.clip_limit, std::clamp(p.clip_base + p.clip_contrast * 0.5, p.clip_min, p.clip_max));
  const LevelClaheSettings l7 = level_clahe_settings(p, 1.0 / std::pow(1.2, 7), 179, 134, 40.0, 80);
  EXPECT_LT(l7.tile_edge, l0.tile_edge);
  LevelClaheParams tiny = p;
  tiny.tile_base = 1.0;
  tiny.tile_scale = 1.0;
  EXPECT_EQ(level_clahe_settings(tiny, 0.5, 30, 30, 10.0, 0).tile_edge, p.tile_min);
  EXPECT_EQ(level_clahe_settings(p, 1.0, 30, 30, 1000.0, 0).clahe.clip_limit, p.clip_max);
  EXPECT_EQ(level_clahe_settings(p, 1.0, 30, 30, 0.0, 200).clahe.clip_limit, std::max(p.clip_base, p.clip_min));
}

// Level 0 of the ALE pyramid: tile histograms counted before a global LUT and carried through
// it give the statistics compute_stats() gives and the same CLAHE as counting after the LUT, for
// grids that divide the image and grids that do not (reflected margins counted too).
TEST(LevelClahe, CountsCarriedThroughAGlobalLutGiveTheSameStatsAndOutput) {
  Lut gamma{};
  gamma_lut(0.45, gamma);
  for (const auto& [w, h] : {std::array<int, 2>{640, 480}, {533, 400}, {179, 134}}) {
    GrayImage img(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        img.view().at(x, y) = static_cast<std::uint8_t>((x * 7 / w) * 9 + (y * 5 / h) * 7 + (x * 13 + y * 29) % 11);
    ClaheContext ctx;
    const LevelClaheParams p;
    FrameStats counted, direct;
    ASSERT_TRUE(count_level(ctx, p, 1.0, img.view(), counted).ok());
    compute_stats(img.view(), direct);
    EXPECT_EQ(counted.histogram, direct.histogram) << w << "x" << h;
    EXPECT_EQ(counted.pixels, direct.pixels);
    EXPECT_EQ(counted.mean, direct.mean);
    EXPECT_EQ(counted.sigma, direct.sigma);
    EXPECT_EQ(counted.median, direct.median);

    GrayImage other(w, h, 1);
    EXPECT_FALSE(ctx.remap_counts(other.view(), gamma).ok()) << "counts of another image";
    ASSERT_TRUE(apply_lut(img.view(), img.view(), gamma).ok());
    ASSERT_TRUE(ctx.remap_counts(img.view(), gamma).ok());
    FrameStats mapped;
    remap_stats(counted, gamma, mapped);
    GrayImage carried(w, h);
    ASSERT_TRUE(contrast_guided_clahe(ctx, p, 1.0, mapped, img.view(), carried.view()).ok());

    ClaheContext fresh;
    FrameStats recounted;
    compute_stats(img.view(), recounted);
    GrayImage expected(w, h);
    ASSERT_TRUE(contrast_guided_clahe(fresh, p, 1.0, recounted, img.view(), expected.view()).ok());
    EXPECT_TRUE(carried.pixels == expected.pixels) << w << "x" << h;
  }
}

TEST(LevelClahe, CellsOfALevelWithOneReusableContext) {
  GrayImage level(160, 120);
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) level.view().at(x, y) = static_cast<std::uint8_t>(40 + (x * 3 + y * 5) % 23);
  GrayImage out(160, 120, 0);
  ClaheContext ctx;
  const LevelClaheParams p;
  // 36x36 cells (30 px plus the FAST radius on each side), written into the matching output cell.
  for (int cy = 0; cy + 36 <= 120; cy += 30) {
    for (int cx = 0; cx + 36 <= 160; cx += 30) {
      LevelClaheSettings used;
      ASSERT_TRUE(contrast_guided_clahe(ctx, p, 0.5, level.view().sub(cx, cy, 36, 36),
                                        out.view().sub(cx, cy, 36, 36), &used)
                      .ok());
      EXPECT_EQ(used.tile_edge, static_cast<int>(p.tile_base + p.tile_scale * 0.5));
      ClaheContext fresh;
      GrayImage expected(36, 36);
      ASSERT_TRUE(clahe(fresh, used.clahe, level.view().sub(cx, cy, 36, 36), expected.view()).ok());
      for (int y = 0; y < 36; ++y)
        for (int x = 0; x < 36; ++x) ASSERT_EQ(out.view().at(cx + x, cy + y), expected.view().at(x, y));
    }
  }
}

TEST(Enhancer, RejectsBadParametersAndSizes) {
  FrameEnhancer e;
  EnhanceParams p;
  p.grading.t_low = p.grading.t_very_low - 1.0;
  const Status st = e.configure(p);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("t_low"), std::string::npos) << st.message();
  GrayImage a(10, 10);
  GrayImage b(11, 10);
  EnhanceReport r;
  EXPECT_FALSE(e.process(a.view(), b.view(), r).ok());
  EXPECT_FALSE(e.process(GrayView{}, b.view(), r).ok());
}

// The policy's decisions per class and CLAHE setting: the one table every caller executes.
TEST(Policy, PlansEachClassAsTheSpecSays) {
  EnhancePolicy policy;
  ASSERT_TRUE(policy.configure(EnhanceParams{}, LevelEnhance::kNonNormalFrames).ok());
  const FramePlan normal = policy.plan_for(BrightnessClass::kNormal);
  EXPECT_FALSE(normal.clahe);
  EXPECT_FALSE(normal.needs_histogram);
  const FramePlan dark = policy.plan_for(BrightnessClass::kDark);
  EXPECT_TRUE(dark.clahe);
  EXPECT_FALSE(dark.negative);
  EXPECT_TRUE(policy.plan_for(BrightnessClass::kExtremelyDark).needs_histogram);
  EXPECT_TRUE(policy.plan_for(BrightnessClass::kBright).negative);
  ASSERT_TRUE(policy.configure(EnhanceParams{}, LevelEnhance::kNever).ok());
  EXPECT_FALSE(policy.plan_for(BrightnessClass::kDark).clahe);
  EXPECT_FALSE(policy.plan_for(BrightnessClass::kDark).needs_histogram);
  EXPECT_TRUE(policy.plan_for(BrightnessClass::kBright).needs_histogram);  // the negative is graded
  ASSERT_TRUE(policy.configure(EnhanceParams{}, LevelEnhance::kAlways).ok());
  EXPECT_TRUE(policy.plan_for(BrightnessClass::kNormal).clahe);
  EnhanceParams bad;
  bad.gamma.alpha = 0.0;
  EXPECT_EQ(policy.configure(bad, LevelEnhance::kNever).code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(policy.plan_for(BrightnessClass::kNormal).clahe) << "a rejected configuration changes nothing";
}

// The global LUT: gamma from the frame (or its negative) when extremely dark, composed after the
// inversion; the inversion back afterwards.
TEST(Policy, GlobalLutComposesNegativeAndGamma) {
  EnhancePolicy policy;
  ASSERT_TRUE(policy.configure(EnhanceParams{}, LevelEnhance::kNonNormalFrames).ok());
  FrameStats bright;  // every pixel 240: the negative (15) is extremely dark
  bright.histogram[240] = 100;
  stats_from_histogram(bright);
  FramePlan plan = policy.plan_for(BrightnessClass::kBright);
  policy.global_lut(bright, plan);
  EXPECT_EQ(plan.negative_brightness, BrightnessClass::kExtremelyDark);
  ASSERT_TRUE(plan.has_pre && plan.has_post);
  EXPECT_LT(plan.gamma, 1.0);
  Lut g{};
  gamma_lut(plan.gamma, g);
  for (int v = 0; v < 256; ++v) {
    EXPECT_EQ(plan.pre[static_cast<std::size_t>(v)], g[static_cast<std::size_t>(255 - v)]) << v;
    EXPECT_EQ(plan.post[static_cast<std::size_t>(v)], 255 - v) << v;
  }
  FrameStats dark;  // every pixel 60: dark, no gamma, no LUT
  dark.histogram[60] = 100;
  stats_from_histogram(dark);
  plan = policy.plan_for(BrightnessClass::kDark);
  policy.global_lut(dark, plan);
  EXPECT_FALSE(plan.has_pre);
  EXPECT_FALSE(plan.has_post);
  EXPECT_EQ(plan.gamma, 1.0);
}

}  // namespace
}  // namespace ale::enhance

// The 3x3 binomial of the dark frames (core/enhance/noise.h): the kernel's weights on an impulse,
// the border kept, a constant image unchanged, and white noise reduced by the stated gain.
TEST(Binomial3, WeightsBorderAndNoiseGain) {
  std::vector<std::uint8_t> rows;
  std::vector<std::uint16_t> sums;
  std::vector<std::uint8_t> px(7 * 6, 10);
  px[3 * 7 + 3] = 250;  // an impulse at (3, 3) on a background of 10
  ale::MutableGrayView img{px.data(), 7, 6, 7};
  ale::enhance::binomial3_in_place(img, rows, sums);
  // (16 * 10 + 240 * w + 8) >> 4 for the impulse's weight w in 16ths
  EXPECT_EQ(px[3 * 7 + 3], (160 + 240 * 4 + 8) >> 4);
  EXPECT_EQ(px[3 * 7 + 2], (160 + 240 * 2 + 8) >> 4);
  EXPECT_EQ(px[2 * 7 + 3], (160 + 240 * 2 + 8) >> 4);
  EXPECT_EQ(px[2 * 7 + 2], (160 + 240 * 1 + 8) >> 4);
  EXPECT_EQ(px[4 * 7 + 4], (160 + 240 * 1 + 8) >> 4);
  EXPECT_EQ(px[1 * 7 + 1], 10);
  for (int x = 0; x < 7; ++x) EXPECT_EQ(px[static_cast<std::size_t>(x)], 10) << "top border, x " << x;

  std::vector<std::uint8_t> flat(64 * 64, 77);
  ale::enhance::binomial3_in_place(ale::MutableGrayView{flat.data(), 64, 64, 64}, rows, sums);
  EXPECT_TRUE(std::all_of(flat.begin(), flat.end(), [](std::uint8_t v) { return v == 77; }));

  // White noise of sigma 8 around 128 (a fixed linear congruential sequence, sum of 12 uniforms).
  const int w = 320, h = 240;
  std::vector<std::uint8_t> noise(static_cast<std::size_t>(w * h));
  std::uint32_t state = 12345u;
  for (auto& v : noise) {
    double s = 0.0;
    for (int k = 0; k < 12; ++k) {
      state = state * 1664525u + 1013904223u;
      s += (state >> 8) / 16777216.0;
    }
    v = static_cast<std::uint8_t>(std::lround(128.0 + 8.0 * (s - 6.0)));
  }
  const auto sigma_of = [&](const std::vector<std::uint8_t>& a) {
    double m = 0.0, q = 0.0;
    int n = 0;
    for (int y = 1; y + 1 < h; ++y)
      for (int x = 1; x + 1 < w; ++x) {
        const double v = a[static_cast<std::size_t>(y * w + x)];
        m += v, q += v * v, ++n;
      }
    m /= n;
    return std::sqrt(q / n - m * m);
  };
  const double before = sigma_of(noise);
  ale::enhance::binomial3_in_place(ale::MutableGrayView{noise.data(), w, h, w}, rows, sums);
  const double after = sigma_of(noise);
  EXPECT_NEAR(after / before, ale::enhance::kBinomial3NoiseGain, 0.02) << before << " -> " << after;
}

// The NEON binomial against the reference, bit-exact: widths 3..40 (the reference below 16, the
// overlapping last steps above), odd heights, camera sizes, padded strides and unaligned starts
// on noise over the whole byte range; nothing outside the view is written.
// NEON builds only (not built on x86, rather than counted as skipped).
#if defined(__ARM_NEON)
TEST(Binomial3, NeonEqualsTheReference) {
  ASSERT_EQ(ale::compiled_vector_path(), ale::KernelPath::kNeon);
  std::uint32_t state = 777u;
  const auto check = [&](int w, int h, int pad, int offset) {
    const int stride = w + pad;
    std::vector<std::uint8_t> a(static_cast<std::size_t>(stride * h + offset));
    for (auto& v : a) {
      state = state * 1664525u + 1013904223u;
      v = static_cast<std::uint8_t>(state >> 24);
    }
    std::vector<std::uint8_t> b = a;
    std::vector<std::uint8_t> rows;
    std::vector<std::uint16_t> sums;
    ale::enhance::binomial3_in_place(ale::MutableGrayView{a.data() + offset, w, h, stride}, rows, sums,
                                     ale::KernelPath::kReference);
    ale::enhance::binomial3_in_place(ale::MutableGrayView{b.data() + offset, w, h, stride}, rows, sums,
                                     ale::KernelPath::kNeon);
    return a == b;
  };
  for (int w = 3; w <= 40; ++w)
    for (int h : {3, 4, 7, 13})
      EXPECT_TRUE(check(w, h, 0, 0)) << w << "x" << h;
  for (int w : {640, 752})
    for (int h : {480, 479})
      for (int offset : {0, 1, 3})
        for (int pad : {0, 5, 64}) EXPECT_TRUE(check(w, h, pad, offset)) << w << "x" << h << " pad " << pad << " offset " << offset;
}
#endif  // __ARM_NEON
