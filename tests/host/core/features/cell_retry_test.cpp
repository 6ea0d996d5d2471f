// The bound that lets the extractor skip a cell's CLAHE retry (cell_clahe.h): every corner FAST
// finds on the enhanced cell at t must have at least the bound's score on the original cell, and
// skipping the retries the bound rules out must leave the extractor's output unchanged.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/features/cell_clahe.h"
#include "core/features/orb.h"
#include "core/frontend/frame_path.h"
#include "core/features/score_map.h"
#include "core/io/image_io.h"
#include "tests/host/support/test_data.h"

namespace ale::features {
namespace {

// A w x h cell of grey `base` with noise of +-amp and, with `edge`, a step of `edge` grey levels
// through it: the low-contrast cells the retry is for, and some it can rescue.
std::vector<std::uint8_t> make_cell(int w, int h, int base, int amp, int edge, std::mt19937& rng) {
  std::vector<std::uint8_t> px(static_cast<std::size_t>(w * h));
  std::uniform_int_distribution<int> noise(-amp, amp);
  const int cut = static_cast<int>(rng() % static_cast<unsigned>(w));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      px[static_cast<std::size_t>(y * w + x)] =
          static_cast<std::uint8_t>(std::clamp(base + noise(rng) + (x + y / 2 > cut ? edge : 0), 0, 255));
  return px;
}

struct Bounds {
  int exact = 0;  // min_raw_gap(t) - 1
  int quick = 0;
};

// Largest FAST score on the original among the corners at t on the enhanced cell (-1: none).
int worst_case_raw_score(CellClahe& clahe, const enhance::LevelClaheParams& p, double scale, GrayView src, int t,
                         Bounds& b) {
  const int w = src.width, h = src.height;
  EXPECT_TRUE(clahe.plan(p, scale, src).ok());
  EXPECT_TRUE(clahe.last_was_single_tile());
  b.exact = clahe.min_raw_gap(t) - 1;
  b.quick = CellClahe::quick_needed_score(p, scale, src, t);
  std::vector<std::uint8_t> enhanced(static_cast<std::size_t>(w * h));
  clahe.map(src, MutableGrayView{enhanced.data(), w, h, w});
  std::vector<std::uint8_t> scores(enhanced.size(), 0);
  std::vector<FastCorner> corners;
  const PixelRect inner{kFastRadius, kFastRadius, w - 2 * kFastRadius, h - 2 * kFastRadius};
  fast9_score_map(GrayView{enhanced.data(), w, h, w}, inner, t, MutableGrayView{scores.data(), w, h, w}, corners,
                  KernelPath::kReference);
  int lowest = 256;
  for (const FastCorner& c : corners)
    lowest = std::min(lowest, fast9_score(src.data + c.y * src.stride + c.x, src.stride));
  return corners.empty() ? -1 : lowest;
}

TEST(CellRetryBound, EveryCornerOfTheEnhancedCellReachesTheBoundOnTheOriginal) {
  const enhance::LevelClaheParams params;
  CellClahe clahe;
  std::mt19937 rng(17);
  int with_corners = 0, tight = 0, quick_useful = 0, cells = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const int w = 24 + static_cast<int>(rng() % 16u);
    const int h = 24 + static_cast<int>(rng() % 16u);
    const int amp = 1 + static_cast<int>(rng() % 12u);
    const int edge = static_cast<int>(rng() % 4u) == 0 ? 0 : static_cast<int>(rng() % 40u);
    const int base = 20 + static_cast<int>(rng() % 200u);
    const std::vector<std::uint8_t> px = make_cell(w, h, base, amp, edge, rng);
    const GrayView src{px.data(), w, h, w};
    for (int t : {20, 30, 45}) {
      Bounds b;
      const int lowest = worst_case_raw_score(clahe, params, 1.0, src, t, b);
      ++cells;
      ASSERT_LE(b.quick, b.exact) << "the quick bound must be the weaker one (trial " << trial << ", t " << t << ")";
      ASSERT_LE(CellClahe::param_needed_score(params, 1.0, w, h, t), b.quick) << "trial " << trial << ", t " << t;
      if (b.quick >= 7) ++quick_useful;
      if (lowest < 0) continue;
      ++with_corners;
      ASSERT_GE(lowest, b.exact) << "a corner at " << t << " after CLAHE scores " << lowest
                                 << " on the original, below the bound (trial " << trial << ")";
      if (lowest == b.exact) ++tight;
    }
  }
  // The check must see corners, and the bounds must be of use (skips happen when they exceed t_low = 7).
  EXPECT_GT(with_corners, cells / 10);
  EXPECT_GT(tight, 0) << "the exact bound should be reached by some corner";
  EXPECT_GT(quick_useful, cells / 4);
}

// min_raw_gap() (NEON on ARM: whole vectors past the cell's range, a first gap from the clip)
// against the two-pointer reference, over cells of every kind the retry sees and some it does not
// (wide ranges, no clipping, one grey level).
TEST(CellRetryBound, MinRawGapMatchesTheReference) {
  CellClahe clahe;
  std::mt19937 rng(5);
  int found = 0, none = 0;
  for (int trial = 0; trial < 400; ++trial) {
    enhance::LevelClaheParams params;
    if (trial % 4 == 1) params.clip_contrast = 0.0;
    if (trial % 4 == 2) params.clip_min = params.clip_max = 40.0;  // nothing clipped
    const int w = 8 + static_cast<int>(rng() % 40u);
    const int h = 8 + static_cast<int>(rng() % 40u);
    const int amp = trial % 9 == 0 ? 0 : 1 + static_cast<int>(rng() % 60u);
    const int edge = static_cast<int>(rng() % 3u) == 0 ? 0 : static_cast<int>(rng() % 120u);
    const int base = static_cast<int>(rng() % 256u);
    const std::vector<std::uint8_t> px = make_cell(w, h, base, amp, edge, rng);
    ASSERT_TRUE(clahe.plan(params, 1.0, GrayView{px.data(), w, h, w}).ok());
    if (!clahe.last_was_single_tile()) continue;
    for (int t = 0; t <= 256; t += 1 + static_cast<int>(rng() % 7u)) {
      const int gap = clahe.min_raw_gap(t);
      ASSERT_EQ(gap, clahe.min_raw_gap_ref(t)) << "trial " << trial << " " << w << "x" << h << " t " << t;
      ++(gap == 256 ? none : found);
    }
  }
  EXPECT_GT(found, 1000);
  EXPECT_GT(none, 100);
}

// CellClahe::moments() (NEON on ARM for cell-sized images) gives enhance::compute_moments()'s
// values to the bit: odd widths, tails of every length, stride != width, unaligned starts and
// sizes at and past its limits.
TEST(CellRetryBound, CellMomentsMatchTheEnhanceMoments) {
  std::mt19937 rng(9);
  std::vector<std::uint8_t> px(300 * 300 + 64);
  for (std::uint8_t& v : px) v = static_cast<std::uint8_t>(rng() >> 24);
  const std::vector<std::pair<int, int>> sizes = {{1, 1}, {15, 40}, {16, 1}, {17, 3},  {31, 31},
                                                  {37, 38}, {48, 48}, {63, 70}, {257, 257}, {258, 257}};
  for (int trial = 0; trial < 300; ++trial) {
    const bool listed = static_cast<std::size_t>(trial) < sizes.size();
    const int w = listed ? sizes[static_cast<std::size_t>(trial)].first : 1 + static_cast<int>(rng() % 80u);
    const int h = listed ? sizes[static_cast<std::size_t>(trial)].second : 1 + static_cast<int>(rng() % 80u);
    const int stride = w + static_cast<int>(rng() % 20u);
    const int offset = static_cast<int>(rng() % 16u);
    if (trial % 3 == 0) {  // a low-contrast cell, as the retry sees
      const int base = static_cast<int>(rng() % 200u);
      for (int i = 0; i < stride * h; ++i) px[static_cast<std::size_t>(offset + i)] = static_cast<std::uint8_t>(base + static_cast<int>(rng() % 40u));
    }
    const GrayView src{px.data() + offset, w, h, stride};
    const enhance::Moments a = CellClahe::moments(src), b = enhance::compute_moments(src);
    ASSERT_EQ(a.pixels, b.pixels) << w << "x" << h;
    ASSERT_EQ(a.mean, b.mean) << w << "x" << h;
    ASSERT_EQ(a.sigma, b.sigma) << w << "x" << h;
    ASSERT_EQ(a.min, b.min) << w << "x" << h;
  }
}

struct Output {
  std::vector<Keypoint> kps;
  std::vector<Descriptor> desc;
  int skipped = 0;
  int retried = 0;
};

Output extract(const GrayImage& img, bool bound) {
  frontend::FramePath ex;
  ExtractorConfig c;
  c.retry_normal_frames = true;  // the normal frame too exercises the retry (and its bound)
  EXPECT_TRUE(ex.configure(c).ok());
  ex.set_retry_bound_for_test(bound);
  Output o;
  EXPECT_TRUE(ex.extract(img.view(), o.kps, o.desc).ok());
  for (int l = 0; l < ex.stats().levels; ++l) {
    o.skipped += ex.stats().level[static_cast<std::size_t>(l)].cells_skipped;
    o.retried += ex.stats().level[static_cast<std::size_t>(l)].cells_retry;
  }
  return o;
}

TEST(CellRetryBound, SkippingChangesNothingOnRealFrames) {
  ALE_REQUIRE_DATA(euroc, "euroc_v101_micro");
  ALE_REQUIRE_DATA(dark, "lighting/dark_frame");
  std::vector<std::string> frames = {euroc + "/mav0/cam0/data/1403715273262142976.png", dark + "/euroc_dark.png"};
  int skipped = 0;
  for (const std::string& path : frames) {
    GrayImage img;
    const Status st = io::read_gray(path, img);
    ASSERT_TRUE(st.ok()) << st.to_string();
    const Output with = extract(img, true);
    const Output without = extract(img, false);
    EXPECT_GT(with.retried, 0) << path;
    ASSERT_EQ(with.kps.size(), without.kps.size()) << path;
    for (std::size_t i = 0; i < with.kps.size(); ++i) {
      ASSERT_EQ(with.kps[i].x, without.kps[i].x) << path << " keypoint " << i;
      ASSERT_EQ(with.kps[i].y, without.kps[i].y) << path << " keypoint " << i;
      ASSERT_EQ(with.kps[i].level, without.kps[i].level) << path << " keypoint " << i;
      ASSERT_EQ(with.kps[i].score, without.kps[i].score) << path << " keypoint " << i;
      ASSERT_EQ(with.desc[i].bytes, without.desc[i].bytes) << path << " keypoint " << i;
    }
    skipped += with.skipped;
    std::printf("%s: %d retries skipped, %d rescued\n", path.c_str(), with.skipped, with.retried);
  }
  EXPECT_GT(skipped, 0) << "the bound should rule out some retries on real frames";
}

}  // namespace
}  // namespace ale::features
