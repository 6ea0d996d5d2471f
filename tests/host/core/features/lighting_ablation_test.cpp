// A lighting set held out from the webcams the issue judges on: real frames (EuRoC V1_01
// keyframes, TUM fr2/desk) against relit copies of themselves — darkened with sensor noise, dimmed,
// and washed out — so the ground truth is the identity, as for the fixed webcams. It decides the
// extractor's lighting defaults (docs/features.md) without tuning on the pairs that judge them:
// every mode and level_enhance choice is measured here, and ALE as configured by default must beat
// the baseline on both figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/enhance/params.h"
#include "core/features/orb.h"
#include "core/io/image_io.h"
#include "tests/host/core/enhance/real_frames.h"
#include "tests/host/core/features/feature_metrics.h"
#include "tests/host/support/test_data.h"

namespace ale::features {
namespace {

// A relit copy: out = gain * in + offset, with shot noise (variance 0.5 grey levels per grey level
// of signal) and read noise (sigma 1.5) for darkened copies, rounded and clipped to 8 bits.
struct Relight {
  const char* name;
  double gain;
  double offset;
  bool noise;
};

constexpr Relight kRelights[] = {
    {"dark x0.22+noise", 0.22, 0.0, true},  // extremely dark: gamma + CLAHE
    {"dim x0.5+noise", 0.5, 0.0, true},     // dark: CLAHE
    {"washed x1.3+70", 1.3, 70.0, false},   // bright: the negative path
};

GrayImage relight(const GrayImage& in, const Relight& r, std::uint32_t seed) {
  GrayImage out = in;
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  for (std::size_t i = 0; i < in.pixels.size(); ++i) {
    double v = r.gain * in.pixels[i] + r.offset;
    if (r.noise) v += unit(rng) * std::sqrt(0.5 * v + 1.5 * 1.5);
    out.pixels[i] = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
  }
  return out;
}

struct Variant {
  const char* name;
  ExtractorConfig config;
};

std::vector<Variant> variants() {
  std::vector<Variant> v;
  ExtractorConfig c;
  c.mode = ExtractorMode::kBaseline;
  v.push_back({"baseline", c});
  v.push_back({"ale (default)", ExtractorConfig{}});
  v.push_back({"ale (article recipe)", article_config()});
  for (double k : {0.0, 1.5, 2.5, 3.0, 4.0}) {
    static std::vector<std::string> names;
    names.push_back("ale, noise_gate " + std::to_string(k).substr(0, 3));
    c = ExtractorConfig{};
    c.noise_gate = k;
    v.push_back({names.back().c_str(), c});
  }
  for (double sg : {0.0, 20.0, 25.0, 45.0}) {
    static std::vector<std::string> names;
    names.push_back("ale, bright_min_sigma " + std::to_string(static_cast<int>(sg)));
    c = ExtractorConfig{};
    c.noise_gate = 2.0;
    c.bright_min_sigma = sg;
    v.push_back({names.back().c_str(), c});
  }
  for (double gm : {0.6, 0.7, 0.85}) {
    static std::vector<std::string> names;
    names.push_back("ale, gamma_min " + std::to_string(gm).substr(0, 4));
    c = ExtractorConfig{};
    c.enhance.gamma.gamma_min = gm;
    v.push_back({names.back().c_str(), c});
  }
  c = ExtractorConfig{};
  c.enhance.clahe = enhance::LevelClaheParams{};  // the frame enhancer's: 1.5 + sigma / median
  v.push_back({"ale, clip 1.5+sigma/median", c});
  c = ExtractorConfig{};
  c.enhance.clahe.clip_base = 1.25;
  v.push_back({"ale, clip 1.25", c});
  c = ExtractorConfig{};
  c.enhance.clahe.clip_contrast = 0.25;
  v.push_back({"ale, clip 1+0.25 sigma/median", c});
  c = ExtractorConfig{};
  c.level_enhance = enhance::LevelEnhance::kAlways;
  v.push_back({"ale, level_enhance=always", c});
  c.level_enhance = enhance::LevelEnhance::kNever;
  v.push_back({"ale, level_enhance=never", c});
  c = ExtractorConfig{};
  c.mode = ExtractorMode::kClahe;
  v.push_back({"clahe everywhere", c});
  return v;
}

struct Figures {
  std::vector<double> rep_all, match_all;  // per variant, mean over relights and frames
  std::vector<std::vector<double>> match;  // [variant][relight], mean over frames
};

// Every variant on every frame against its relit copies; prints the table docs/features.md quotes.
Figures measure(const std::vector<Variant>& vs, const std::string& euroc, const std::string& tum) {
  std::vector<std::string> files = test::every(test::image_files(euroc), 10);
  for (const std::string& f : test::every(test::image_files(tum), 4)) files.push_back(f);
  EXPECT_GE(files.size(), 12u);
  // [variant][relight] sums of repeatability and matching score.
  std::vector<std::vector<double>> rep(vs.size(), std::vector<double>(std::size(kRelights), 0.0));
  std::vector<std::vector<double>> match = rep;
  int n = 0;
  std::uint32_t seed = 1;
  for (const std::string& path : files) {
    GrayImage frame;
    const Status st = io::read_gray(path, frame);
    EXPECT_TRUE(st.ok()) << st.to_string();
    if (!st.ok()) continue;
    std::vector<GrayImage> relit;
    for (const Relight& r : kRelights) relit.push_back(relight(frame, r, seed++));
    for (std::size_t v = 0; v < vs.size(); ++v) {
      const test::Extraction a = test::extract(vs[v].config, frame);
      for (std::size_t r = 0; r < relit.size(); ++r) {
        const test::Extraction b = test::extract(vs[v].config, relit[r]);
        rep[v][r] += test::repeatability(a, b, 2.0);
        match[v][r] += test::matching_score(a, b, 2.0);
      }
    }
    ++n;
  }
  Figures f{std::vector<double>(vs.size(), 0.0), std::vector<double>(vs.size(), 0.0), match};
  if (n == 0) return f;
  std::printf("%d frames, each against %zu relit copies (identity, 2 px):\n", n, std::size(kRelights));
  for (std::size_t v = 0; v < vs.size(); ++v) {
    std::printf("  %-30s", vs[v].name);
    for (std::size_t r = 0; r < std::size(kRelights); ++r) {
      std::printf("  %s rep %.4f match %.4f", kRelights[r].name, rep[v][r] / n, match[v][r] / n);
      f.rep_all[v] += rep[v][r] / n / static_cast<double>(std::size(kRelights));
      f.match_all[v] += match[v][r] / n / static_cast<double>(std::size(kRelights));
      f.match[v][r] = match[v][r] / n;
    }
    std::printf("  | mean rep %.4f match %.4f\n", f.rep_all[v], f.match_all[v]);
  }
  return f;
}

// The defaults' check (baseline and ALE as configured by default only, so that it stays quick
// under qemu-arm).
TEST(FeaturesLightingAblation, AleBeatsBaselineOnRelitRealFrames) {
  ALE_REQUIRE_DATA(euroc, "euroc_v101_keyframes/cam0");
  ALE_REQUIRE_DATA(tum, "tum_fr2_desk_20/rgb");
  const std::vector<Variant> all = variants();
  const std::vector<Variant> vs(all.begin(), all.begin() + 2);  // baseline, ale (default)
  const Figures f = measure(vs, euroc, tum);
  // Sanity: identity ground truth gives far more than chance agreement.
  for (std::size_t v = 0; v < vs.size(); ++v) EXPECT_GT(f.match_all[v], 0.05) << vs[v].name;
  EXPECT_GT(f.rep_all[1], f.rep_all[0]) << "ALE (default) against the baseline: repeatability";
  EXPECT_GT(f.match_all[1], f.match_all[0]) << "ALE (default) against the baseline: matching score";
  // Issue 13: not only on the mean (equal where ALE leaves the copy alone, as washed-out ones).
  for (std::size_t r = 0; r < std::size(kRelights); ++r)
    EXPECT_GE(f.match[1][r], f.match[0][r]) << kRelights[r].name << ": ALE's matching score against the baseline's";
}

// The whole ablation table of docs/features.md (every variant; about 2.5 min under qemu-arm, so
// not run by default: --gtest_also_run_disabled_tests).
TEST(FeaturesLightingAblation, DISABLED_AllVariantsTable) {
  ALE_REQUIRE_DATA(euroc, "euroc_v101_keyframes/cam0");
  ALE_REQUIRE_DATA(tum, "tum_fr2_desk_20/rgb");
  // ALE_ABLATION_ONLY=text keeps the baseline and the variants whose name contains it.
  const char* only = std::getenv("ALE_ABLATION_ONLY");
  std::vector<Variant> vs;
  for (const Variant& v : variants())
    if (only == nullptr || vs.empty() || std::string(v.name).find(only) != std::string::npos) vs.push_back(v);
  // ALE_ABLATION_SET="key=value key=value" adds ALE with those keys of the extractor's table set
  // (as ale-features --set), for measuring a setting without editing the list above.
  static std::string set_name;
  if (const char* set = std::getenv("ALE_ABLATION_SET")) {
    ExtractorConfig c;
    std::istringstream words(set);
    for (std::string kv; words >> kv;) {
      const std::size_t eq = kv.find('=');
      const Status st = eq == std::string::npos
                            ? invalid_argument(kv + ": expected key=value")
                            : set_field(extractor_config_table(), &c, kv.substr(0, eq), kv.substr(eq + 1), "ALE_ABLATION_SET");
      ASSERT_TRUE(st.ok()) << st.to_string();
    }
    set_name = std::string("ale, ") + set;
    vs.push_back({set_name.c_str(), c});
  }
  const Figures f = measure(vs, euroc, tum);
  for (std::size_t v = 0; v < vs.size(); ++v) EXPECT_GT(f.match_all[v], 0.05) << vs[v].name;
}

}  // namespace
}  // namespace ale::features
