// The ORB front end on real data (../shared/data): ALE against the ORB-SLAM3-like baseline.
// - Illumination change on the fixed TILDE webcams (ground truth: identity, 2 px allowed).
// - Feature counts on the article's frames (dark EuRoC frame, EuRoC frame brightened by 65 %).
// - Matching under a viewpoint change with ground truth (graf1 -> graf3 homography).
// Figures are printed; docs/features.md quotes them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/features/orb.h"
#include "core/frontend/frame_path.h"
#include "tests/host/core/features/feature_metrics.h"
#include "core/io/image_io.h"
#include "tests/host/core/enhance/real_frames.h"
#include "tests/host/support/test_data.h"

namespace ale::features {
namespace {

using test::Extraction;
using test::matching_score;
using test::mean_grey;
using test::repeatability;

Extraction extract(ExtractorMode mode, const GrayImage& img) {
  ExtractorConfig cfg;
  cfg.mode = mode;
  return test::extract(cfg, img);
}

constexpr std::size_t kMaxPairsPerWebcam = 40;

struct IlluminationFigures {
  int pairs = 0;
  double repeatability[2] = {0, 0};  // baseline, ale
  double matching_score[2] = {0, 0};
};

// Every pair of frames of one webcam whose mean grey differs by >= 40 (at most
// kMaxPairsPerWebcam per webcam, every step-th pair in (i, j) order), both modes.
void measure_illumination(const std::string& webcam, IlluminationFigures& out) {
  double sum[2][2] = {{0, 0}, {0, 0}};  // [mode: baseline, ale][repeatability, matching score]
  int pairs_used = 0;
  int pairs_eligible = 0;
  for (const char* cam : test::kWebcams) {
    const std::vector<std::string> files = test::image_files(webcam + "/" + cam);
    ASSERT_GE(files.size(), 10u) << cam;
    std::vector<GrayImage> frames(files.size());
    std::vector<double> means(files.size());
    for (std::size_t i = 0; i < files.size(); ++i) {
      ASSERT_TRUE(io::read_gray(files[i], frames[i]).ok()) << files[i];
      means[i] = mean_grey(frames[i]);
    }
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (std::size_t i = 0; i < files.size(); ++i)
      for (std::size_t j = i + 1; j < files.size(); ++j)
        if (std::abs(means[i] - means[j]) >= 40.0) pairs.push_back({i, j});
    pairs_eligible += static_cast<int>(pairs.size());
    // Deterministic subsample: every step-th pair in (i, j) order, so at most kMaxPairsPerWebcam.
    const std::size_t step = (pairs.size() + kMaxPairsPerWebcam - 1) / kMaxPairsPerWebcam;
    std::map<std::size_t, Extraction> cache[2];
    double cam_sum[2][2] = {{0, 0}, {0, 0}};
    int cam_pairs = 0;
    for (std::size_t k = 0; k < pairs.size(); k += std::max<std::size_t>(step, 1)) {
      const auto [i, j] = pairs[k];
      for (int m = 0; m < 2; ++m) {
        const ExtractorMode mode = m == 0 ? ExtractorMode::kBaseline : ExtractorMode::kAle;
        for (std::size_t f : {i, j})
          if (cache[m].count(f) == 0) cache[m][f] = extract(mode, frames[f]);
        const double r = repeatability(cache[m][i], cache[m][j], 2.0);
        const double s = matching_score(cache[m][i], cache[m][j], 2.0);
        cam_sum[m][0] += r;
        cam_sum[m][1] += s;
        sum[m][0] += r;
        sum[m][1] += s;
      }
      ++cam_pairs;
      ++pairs_used;
    }
    if (cam_pairs == 0) {
      const auto [lo, hi] = std::minmax_element(means.begin(), means.end());
      std::printf("webcam %-10s no pair differs by 40 grey levels (means %.1f..%.1f)\n", cam, *lo, *hi);
      continue;
    }
    std::printf("webcam %-10s pairs %3d/%3zu  repeatability baseline %.4f ale %.4f  matching score baseline %.5f ale %.5f\n",
                cam, cam_pairs, pairs.size(), cam_sum[0][0] / cam_pairs, cam_sum[1][0] / cam_pairs,
                cam_sum[0][1] / cam_pairs, cam_sum[1][1] / cam_pairs);
  }
  ASSERT_GT(pairs_used, 0) << "no pair of webcam frames differs by 40 grey levels";
  out.pairs = pairs_used;
  for (int m = 0; m < 2; ++m) {
    out.repeatability[m] = sum[m][0] / pairs_used;
    out.matching_score[m] = sum[m][1] / pairs_used;
  }
  std::printf("webcams all    pairs %3d/%3d  repeatability baseline %.4f ale %.4f  matching score baseline %.5f ale %.5f\n",
              pairs_used, pairs_eligible, out.repeatability[0], out.repeatability[1], out.matching_score[0],
              out.matching_score[1]);
}

// The figures, with checks that catch a broken detector or descriptor (identity ground truth
// must give clearly more than chance agreement).
TEST(FeaturesRealData, IlluminationChangeFigures) {
  ALE_REQUIRE_DATA(webcam, "lighting/webcam");
  IlluminationFigures f;
  measure_illumination(webcam, f);
  ASSERT_GT(f.pairs, 0);
  for (int m = 0; m < 2; ++m) {
    EXPECT_GT(f.repeatability[m], 0.08) << m;
    EXPECT_GT(f.matching_score[m], 0.003) << m;
  }
}

// The acceptance criterion: ALE beats the baseline on the mean of both figures over the
// webcam pairs. (The extractor's level-CLAHE clip was chosen on the held-out relit frames of
// lighting_ablation_test.cpp, not on these pairs; docs/features.md.)
TEST(FeaturesRealData, AleBeatsBaselineUnderIlluminationChange) {
  ALE_REQUIRE_DATA(webcam, "lighting/webcam");
  IlluminationFigures f;
  measure_illumination(webcam, f);
  EXPECT_GT(f.repeatability[1], f.repeatability[0]) << "mean repeatability";
  EXPECT_GT(f.matching_score[1], f.matching_score[0]) << "mean matching score";
}

struct ModeCounts {
  int ale = 0;
  int baseline = 0;
  int low_ale = 0;   // cells that needed the weak threshold: corners of the noise floor, not structure
  int low_base = 0;
  int retry = 0;     // cells rescued by ALE's CLAHE retry
  BrightnessClass brightness = BrightnessClass::kNormal;
};

ModeCounts count_features(const GrayImage& img) {
  ModeCounts c;
  ExtractorConfig cfg;
  frontend::FramePath ale, base;
  cfg.mode = ExtractorMode::kAle;
  EXPECT_TRUE(ale.configure(cfg).ok());
  cfg.mode = ExtractorMode::kBaseline;
  EXPECT_TRUE(base.configure(cfg).ok());
  std::vector<Keypoint> k;
  std::vector<Descriptor> d;
  EXPECT_TRUE(ale.extract(img.view(), k, d).ok());
  c.ale = static_cast<int>(k.size());
  EXPECT_TRUE(base.extract(img.view(), k, d).ok());
  c.baseline = static_cast<int>(k.size());
  for (int l = 0; l < cfg.num_levels; ++l) {
    c.low_ale += ale.stats().level[static_cast<std::size_t>(l)].cells_low;
    c.retry += ale.stats().level[static_cast<std::size_t>(l)].cells_retry;
    c.low_base += base.stats().level[static_cast<std::size_t>(l)].cells_low;
  }
  c.brightness = ale.stats().brightness;
  return c;
}

void print_counts(const char* label, const ModeCounts& c, int budget) {
  std::printf("%-13s class %-14s features ale %d baseline %d (budget %d); cells at t_low ale %d baseline %d; "
              "cells rescued by the CLAHE retry %d\n",
              label, to_string(c.brightness), c.ale, c.baseline, budget, c.low_ale, c.low_base, c.retry);
}

TEST(FeaturesRealData, AleKeepsTheBudgetOnDarkAndBrightenedFrames) {
  ALE_REQUIRE_DATA(normal_path, "euroc_v101_micro/mav0/cam0/data/1403715273262142976.png");
  ALE_REQUIRE_DATA(dark_path, "lighting/dark_frame/euroc_dark.png");
  GrayImage normal, dark;
  ASSERT_TRUE(io::read_gray(normal_path, normal).ok());
  ASSERT_TRUE(io::read_gray(dark_path, dark).ok());
  GrayImage bright = normal;
  for (auto& v : bright.pixels) v = static_cast<std::uint8_t>(std::min(255, (v * 165 + 50) / 100));
  const int budget = ExtractorConfig{}.num_features;
  for (const auto& [label, img] : {std::pair<const char*, const GrayImage*>{"dark", &dark}, {"brightened65", &bright}}) {
    const ModeCounts c = count_features(*img);
    print_counts(label, c, budget);
    EXPECT_GE(c.ale, budget * 9 / 10) << label;
    EXPECT_GE(c.ale, c.baseline) << label;
    if (c.brightness == BrightnessClass::kNormal) {
      // The brightened frame keeps its contrast (sigma 49 >= bright_min_sigma): treated as normal,
      // it gets the baseline's output (issue 13: the negative path only reordered corners there).
      EXPECT_EQ(c.low_ale, c.low_base) << label;
      EXPECT_EQ(c.ale, c.baseline) << label;
    } else {
      EXPECT_LT(c.low_ale, c.low_base) << label << ": ALE should need the noise-level threshold in fewer cells";
    }
  }
}

// The shared dark frame (mean 43.7) still gives the baseline its whole budget through T_low, so
// the "ALE keeps >= 90 % where the baseline extracts less" property shows only on darker frames
// (the article's very dark MH04 frames are not in ../shared/data): the real dark frame scaled to a
// quarter and to 15 % of its intensities, rounded.
TEST(FeaturesRealData, AleKeepsTheBudgetWhereTheBaselineFallsShort) {
  ALE_REQUIRE_DATA(dark_path, "lighting/dark_frame/euroc_dark.png");
  GrayImage dark;
  ASSERT_TRUE(io::read_gray(dark_path, dark).ok());
  const int budget = ExtractorConfig{}.num_features;
  for (const auto& [label, percent] : {std::pair<const char*, int>{"dark x0.25", 25}, {"dark x0.15", 15}}) {
    GrayImage darker = dark;
    for (auto& v : darker.pixels) v = static_cast<std::uint8_t>((v * percent + 50) / 100);
    const ModeCounts c = count_features(darker);
    print_counts(label, c, budget);
    EXPECT_LT(c.baseline, budget * 9 / 10) << label << ": the baseline should fall short here";
    EXPECT_GE(c.ale, budget * 9 / 10) << label;
  }
}

// The 3x3 matrix of an OpenCV FileStorage XML file (<rows>3</rows><cols>3</cols>... <data>).
bool read_homography(const std::string& path, double h[9]) {
  const std::string xml = test::read_file(path);
  const std::size_t rows = xml.find("<rows>3</rows>");
  const std::size_t cols = xml.find("<cols>3</cols>");
  const std::size_t begin = xml.find("<data>");
  const std::size_t end = xml.find("</data>");
  if (rows == std::string::npos || cols == std::string::npos || begin == std::string::npos || end == std::string::npos ||
      end < begin)
    return false;
  std::istringstream data(xml.substr(begin + 6, end - begin - 6));
  for (int i = 0; i < 9; ++i)
    if (!(data >> h[i])) return false;
  std::string extra;
  return !(data >> extra);
}

TEST(FeaturesRealData, GrafHomographyCorrectMatches) {
  ALE_REQUIRE_DATA(dir, "homography_graf");
  double h[9];
  ASSERT_TRUE(read_homography(dir + "/H1to3p.xml", h));
  GrayImage g1, g3;
  ASSERT_TRUE(io::read_gray(dir + "/graf1.png", g1).ok());
  ASSERT_TRUE(io::read_gray(dir + "/graf3.png", g3).ok());
  for (ExtractorMode mode : {ExtractorMode::kBaseline, ExtractorMode::kAle}) {
    const Extraction a = extract(mode, g1);
    const Extraction b = extract(mode, g3);
    const auto matches = mutual_matches(a, b);
    int correct = 0;
    for (const auto& [i, j] : matches) {
      const Keypoint& p = a.kps[static_cast<std::size_t>(i)];
      const Keypoint& q = b.kps[static_cast<std::size_t>(j)];
      const double w = h[6] * p.x + h[7] * p.y + h[8];
      const double x = (h[0] * p.x + h[1] * p.y + h[2]) / w;
      const double y = (h[3] * p.x + h[4] * p.y + h[5]) / w;
      if (std::hypot(x - q.x, y - q.y) < 3.0) ++correct;
    }
    const double share = matches.empty() ? 0.0 : static_cast<double>(correct) / static_cast<double>(matches.size());
    std::printf("graf1->graf3 mode %-8s keypoints %zu/%zu mutual matches %zu correct (<3 px) %d share %.3f\n",
                to_string(mode), a.kps.size(), b.kps.size(), matches.size(), correct, share);
    // A working descriptor finds a clear share of correct matches on this 40-degree viewpoint change;
    // random descriptors would give about none.
    EXPECT_GT(share, 0.10) << to_string(mode);
    EXPECT_GT(correct, 50) << to_string(mode);
  }
}

}  // namespace
}  // namespace ale::features
