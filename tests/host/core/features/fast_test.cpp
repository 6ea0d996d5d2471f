// FAST-9: the reference against a brute-force reading of the definition in fast.h, and the
// dispatched kernel (NEON on the armhf build, run under qemu-arm) against the reference: the same
// corners in the same order with the same scores, on synthetic edge cases and real frames.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "core/features/fast.h"
#include "core/features/kernels.h"
#include "core/io/image_io.h"
#include "tests/host/core/enhance/real_frames.h"
#include "tests/host/core/features/blob_image.h"
#include "tests/host/support/padded_image.h"
#include "tests/host/support/test_data.h"

namespace ale::features {
namespace {

using Buffer = test::PaddedImage;

// Blobs, steps and noise spanning 0..255 (saturation at both ends), in a buffer whose first row
// starts `offset` bytes in and whose rows are `stride` apart; padding bytes hold 0xA5.
Buffer make_image(int width, int height, int stride, int offset, std::uint32_t seed) {
  Buffer b = test::padded_image(width, height, stride, offset, 0xA5);
  test::fill_blobs(b.view, seed, 40);
  return b;
}

std::vector<FastCorner> detect(GrayView img, PixelRect rect, int t, KernelPath path,
                               std::vector<std::uint8_t>* scores_out) {
  std::vector<std::uint8_t> scores(static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height), 0xEE);
  MutableGrayView sv{scores.data(), img.width, img.height, img.width};
  std::vector<FastCorner> out;
  const Status st = fast9_detect(img, rect, t, sv, out, path);
  EXPECT_TRUE(st.ok()) << st.to_string();
  if (scores_out != nullptr) *scores_out = scores;
  return out;
}

// Element-wise equality with a readable first difference.
::testing::AssertionResult same_corners(const std::vector<FastCorner>& a, const std::vector<FastCorner>& b) {
  if (a.size() != b.size())
    return ::testing::AssertionFailure() << "counts differ: " << a.size() << " vs " << b.size();
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].x != b[i].x || a[i].y != b[i].y || a[i].score != b[i].score)
      return ::testing::AssertionFailure() << "corner " << i << ": (" << a[i].x << "," << a[i].y << ") score "
                                           << int(a[i].score) << " vs (" << b[i].x << "," << b[i].y << ") score "
                                           << int(b[i].score);
  }
  return ::testing::AssertionSuccess();
}

// The definition read literally: 9 contiguous circle pixels all beyond +-t.
bool is_corner_brute(GrayView img, int x, int y, int t) {
  static constexpr int kDx[16] = {0, 1, 2, 3, 3, 3, 2, 1, 0, -1, -2, -3, -3, -3, -2, -1};
  static constexpr int kDy[16] = {-3, -3, -2, -1, 0, 1, 2, 3, 3, 3, 2, 1, 0, -1, -2, -3};
  const int p = img.at(x, y);
  for (int start = 0; start < 16; ++start) {
    bool bright = true;
    bool dark = true;
    for (int j = 0; j < 9; ++j) {
      const int k = (start + j) % 16;
      const int v = img.at(x + kDx[k], y + kDy[k]);
      bright = bright && v > p + t;
      dark = dark && v < p - t;
    }
    if (bright || dark) return true;
  }
  return false;
}

TEST(Fast9Reference, MatchesTheDefinitionBruteForce) {
  const Buffer b = make_image(40, 30, 40, 0, 7);
  for (int t : {1, 5, 20, 60}) {
    std::vector<std::uint8_t> scores;
    const auto got = detect(b.view, {3, 3, 34, 24}, t, KernelPath::kReference, &scores);
    std::vector<FastCorner> want;
    for (int y = 3; y < 27; ++y) {
      for (int x = 3; x < 37; ++x) {
        if (!is_corner_brute(b.view, x, y, t)) continue;
        int s = t;
        while (s < 254 && is_corner_brute(b.view, x, y, s + 1)) ++s;
        want.push_back({static_cast<std::int16_t>(x), static_cast<std::int16_t>(y), static_cast<std::uint8_t>(s)});
        EXPECT_EQ(internal::fast9_score_ref(&b.view.at(x, y), b.view.stride), s);
        EXPECT_EQ(fast9_score(&b.view.at(x, y), b.view.stride), s);
      }
    }
    EXPECT_FALSE(want.empty());
    EXPECT_TRUE(same_corners(got, want)) << "threshold " << t;
    for (const FastCorner& c : got) EXPECT_EQ(scores[static_cast<std::size_t>(c.y * 40 + c.x)], c.score);
    EXPECT_EQ(scores[0], 0xEE) << "wrote outside the rect";
  }
}

// fast9_score() (NEON on armhf) against its scalar definition on one exact 7x7 patch (stride 7, no
// byte beyond it readable without leaving the allocation).
class ScorePatch {
 public:
  std::uint8_t& centre() { return patch_[kCentre]; }
  std::uint8_t& circle(int k) {
    return patch_[static_cast<std::size_t>(kCentre + internal::kCircleDy[k] * kEdge + internal::kCircleDx[k])];
  }
  // Fills the whole patch, so the 24 pixels off the circle (which no score may depend on) hold `v`
  // until the centre and circle are drawn over it.
  void fill(std::uint8_t v) { std::fill(patch_.begin(), patch_.end(), v); }
  ::testing::AssertionResult matches() {
    ++checked_;
    const int want = internal::fast9_score_ref(patch_.data() + kCentre, kEdge);
    const int got = fast9_score(patch_.data() + kCentre, kEdge);
    if (want == got) return ::testing::AssertionSuccess();
    ::testing::AssertionResult r = ::testing::AssertionFailure();
    r << "score " << got << ", reference " << want << "; centre " << int{centre()} << ", circle";
    for (int k = 0; k < 16; ++k) r << ' ' << int{circle(k)};
    return r;
  }
  long checked() const { return checked_; }

 private:
  static constexpr int kEdge = 2 * kFastRadius + 1;
  static constexpr int kCentre = kFastRadius * kEdge + kFastRadius;
  std::vector<std::uint8_t> patch_ = std::vector<std::uint8_t>(kEdge * kEdge, 0);
  long checked_ = 0;
};

TEST(Fast9Score, MatchesTheReferenceOnRandomCircles) {
  ScorePatch s;
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> byte(0, 255);
  std::uniform_int_distribution<int> near(-4, 4);
  for (int i = 0; i < 200000; ++i) {
    s.fill(static_cast<std::uint8_t>(byte(rng)));
    const int c = byte(rng);
    s.centre() = static_cast<std::uint8_t>(c);
    // Half the circles hug the centre, where the windows' minima tie and signs flip.
    const bool close = (i & 1) != 0;
    for (int k = 0; k < 16; ++k)
      s.circle(k) = static_cast<std::uint8_t>(close ? std::clamp(c + near(rng), 0, 255) : byte(rng));
    ASSERT_TRUE(s.matches()) << "random circle " << i;
  }
}

TEST(Fast9Score, MatchesTheReferenceOnEveryTwoValuedCircle) {
  // Every arc layout (all 2^16 masks) with levels at the extremes, at the centre and one step off it.
  struct Levels {
    int set, unset, centre;
  };
  const Levels levels[] = {{255, 0, 128}, {255, 0, 0},   {255, 0, 255},  {0, 255, 0},
                           {138, 118, 128}, {129, 128, 128}, {127, 128, 128}, {1, 0, 0}, {254, 255, 255}};
  ScorePatch s;
  s.fill(77);
  for (const Levels& l : levels) {
    s.centre() = static_cast<std::uint8_t>(l.centre);
    for (unsigned mask = 0; mask < 65536u; ++mask) {
      for (int k = 0; k < 16; ++k) s.circle(k) = static_cast<std::uint8_t>(((mask >> k) & 1u) != 0 ? l.set : l.unset);
      ASSERT_TRUE(s.matches()) << "mask " << mask;
    }
  }
  EXPECT_EQ(s.checked(), 9 * 65536);
}

TEST(Fast9Score, MatchesTheReferenceOnFlatCirclesAndSingleOutliers) {
  ScorePatch s;
  for (int rest : {0, 255}) {
    s.fill(static_cast<std::uint8_t>(rest));
    // A flat circle of every level around every centre (all equal, saturated, in between).
    for (int c = 0; c < 256; ++c) {
      for (int v = 0; v < 256; ++v) {
        s.centre() = static_cast<std::uint8_t>(c);
        for (int k = 0; k < 16; ++k) s.circle(k) = static_cast<std::uint8_t>(v);
        ASSERT_TRUE(s.matches());
      }
    }
  }
  // One outlier at each position, which caps every window holding it.
  s.fill(9);
  const int values[] = {0, 1, 60, 127, 128, 129, 200, 254, 255};
  for (int c : values) {
    for (int v : values) {
      for (int out : values) {
        for (int k = 0; k < 16; ++k) {
          s.centre() = static_cast<std::uint8_t>(c);
          for (int j = 0; j < 16; ++j) s.circle(j) = static_cast<std::uint8_t>(j == k ? out : v);
          ASSERT_TRUE(s.matches()) << "outlier at " << k;
        }
      }
    }
  }
}

// Inside a larger image (wide odd stride, rows not aligned) every pixel's score matches too.
TEST(Fast9Score, MatchesTheReferenceInAnImage) {
  const Buffer b = make_image(61, 23, 77, 5, 3);
  for (int y = kFastRadius; y < 23 - kFastRadius; ++y)
    for (int x = kFastRadius; x < 61 - kFastRadius; ++x)
      ASSERT_EQ(fast9_score(&b.view.at(x, y), b.view.stride), internal::fast9_score_ref(&b.view.at(x, y), b.view.stride))
          << "at " << x << "," << y;
}

TEST(Fast9Dispatch, ReportsThePath) {
  // The table kAuto reads (chosen before main()) is the one ALE_FORCE_REF asks for.
  const KernelPath p = kernels().path;
  EXPECT_EQ(p, reference_kernels_forced() ? KernelPath::kReference : compiled_vector_path());
  std::printf("fast9 auto path: %s\n", to_string(p));
}

TEST(Fast9Equivalence, SyntheticEdgeCases) {
  int compared = 0;
  for (int rect_w = 1; rect_w <= 40; ++rect_w) {
    for (int pad : {0, 13}) {
      for (int offset : {0, 1, 3}) {
        const int w = rect_w + 6;
        const int h = 7 + (rect_w % 5) * 2;  // odd heights
        const Buffer b = make_image(w, h, w + pad, offset, static_cast<std::uint32_t>(rect_w * 977 + pad + offset));
        for (int t = 1; t <= 60; t += (rect_w % 7 == 0 ? 1 : 9)) {
          const PixelRect r{3, 3, rect_w, h - 6};
          EXPECT_TRUE(same_corners(detect(b.view, r, t, KernelPath::kAuto, nullptr),
                                   detect(b.view, r, t, KernelPath::kReference, nullptr)))
              << "width " << rect_w << " pad " << pad << " offset " << offset << " threshold " << t;
          ++compared;
        }
      }
    }
  }
  EXPECT_GT(compared, 1000);
}

TEST(Fast9Equivalence, EveryThresholdOnOneImage) {
  const Buffer b = make_image(61, 23, 64, 1, 99);
  for (int t = 1; t <= 254; ++t) {
    const PixelRect r{3, 3, 55, 17};
    std::vector<std::uint8_t> sa, sb;
    const auto a = detect(b.view, r, t, KernelPath::kAuto, &sa);
    const auto c = detect(b.view, r, t, KernelPath::kReference, &sb);
    ASSERT_TRUE(same_corners(a, c)) << "threshold " << t;
    ASSERT_EQ(sa, sb) << "score maps differ at threshold " << t;
  }
}

TEST(Fast9Equivalence, ConstantImagesHaveNoCorners) {
  for (int v : {0, 1, 128, 254, 255}) {
    std::vector<std::uint8_t> px(50 * 20, static_cast<std::uint8_t>(v));
    const GrayView img{px.data(), 50, 20, 50};
    for (int t : {1, 20, 254}) {
      EXPECT_TRUE(detect(img, {3, 3, 44, 14}, t, KernelPath::kAuto, nullptr).empty());
      EXPECT_TRUE(detect(img, {3, 3, 44, 14}, t, KernelPath::kReference, nullptr).empty());
    }
  }
}

TEST(Fast9Equivalence, RealFrames) {
  ALE_REQUIRE_DATA(micro, "euroc_v101_micro/mav0/cam0/data");
  ALE_REQUIRE_DATA(dark, "lighting/dark_frame/euroc_dark.png");
  ALE_REQUIRE_DATA(webcam, "lighting/webcam");
  std::vector<std::string> files = test::every(test::image_files(micro), 30);
  files.push_back(dark);
  for (const char* cam : test::kWebcams) files.push_back(test::image_files(webcam + "/" + cam).front());
  for (const std::string& f : files) {
    GrayImage img;
    ASSERT_TRUE(io::read_gray(f, img).ok()) << f;
    const PixelRect r{3, 3, img.width - 6, img.height - 6};
    for (int t : {7, 20, 30}) {
      const auto a = detect(img.view(), r, t, KernelPath::kAuto, nullptr);
      const auto c = detect(img.view(), r, t, KernelPath::kReference, nullptr);
      EXPECT_TRUE(same_corners(a, c)) << f << " threshold " << t;
      EXPECT_GT(c.size(), 10u) << f << " threshold " << t;
    }
  }
}

TEST(Fast9Nonmax, KeepsStrictLocalMaxima) {
  std::vector<std::uint8_t> s(8 * 6, 0);
  const MutableGrayView sv{s.data(), 8, 6, 8};
  sv.at(2, 2) = 30;  // beats its neighbour (3, 2)
  sv.at(3, 2) = 25;
  sv.at(5, 3) = 40;  // ties with (6, 3): both go, as in OpenCV
  sv.at(6, 3) = 40;
  const std::vector<FastCorner> in = {{2, 2, 30}, {3, 2, 25}, {5, 3, 40}, {6, 3, 40}};
  std::vector<FastCorner> out;
  fast9_nonmax(sv, in, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].x, 2);
  EXPECT_EQ(out[0].y, 2);
}

TEST(Fast9Detect, RejectsBadArguments) {
  std::vector<std::uint8_t> px(20 * 20, 9), sc(20 * 20);
  const GrayView img{px.data(), 20, 20, 20};
  const MutableGrayView sv{sc.data(), 20, 20, 20};
  std::vector<FastCorner> out;
  EXPECT_FALSE(fast9_detect(img, {2, 3, 5, 5}, 20, sv, out).ok());     // too close to the left
  EXPECT_FALSE(fast9_detect(img, {3, 3, 15, 5}, 20, sv, out).ok());    // past the right margin
  EXPECT_FALSE(fast9_detect(img, {3, 3, 5, 5}, 0, sv, out).ok());      // threshold
  EXPECT_FALSE(fast9_detect(img, {3, 3, 5, 5}, 255, sv, out).ok());
  const MutableGrayView small{sc.data(), 10, 10, 10};
  EXPECT_FALSE(fast9_detect(img, {3, 3, 5, 5}, 20, small, out).ok());  // score map size
  EXPECT_FALSE(fast9_detect(GrayView{}, {3, 3, 5, 5}, 20, sv, out).ok());
  EXPECT_TRUE(out.empty());
}

}  // namespace
}  // namespace ale::features
