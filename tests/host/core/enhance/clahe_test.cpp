// The NEON CLAHE (ARM builds) against the scalar reference: max difference 0 at every width
// 1-17, 640 and 752, odd heights, stride > width, unaligned row starts and grids that do not
// divide the image. x86 builds have no vector CLAHE, so the equivalence tests are not built there rather
// than compare the reference with itself; an ARM build without NEON fails
// (ClaheKernels.ArmBuildsHaveTheNeonKernel). The armhf build runs this file under qemu-arm.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <string>
#include <algorithm>
#include <vector>

#include "core/enhance/clahe.h"
#include "core/enhance/kernels.h"
#include "tests/host/support/padded_image.h"

namespace ale::enhance {
namespace {

// Pixels with structure at several scales (so tile LUTs differ) and noise (so bins get clipped).
using TestImage = test::PaddedImage;

TestImage make_image(int width, int height, int stride, int offset, std::uint32_t seed) {
  TestImage t = test::padded_image(width, height, stride, offset, 0xA5, 16);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(-25, 25);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const int base = ((x * 7 / (width + 1)) * 37 + (y * 5 / (height + 1)) * 23 + (x ^ y) % 17) % 200;
      t.view.at(x, y) = static_cast<std::uint8_t>(std::clamp(base + 20 + noise(rng), 0, 255));
    }
  }
  return t;
}

#if defined(__ARM_NEON)
// Runs path `path` and the reference on the same input; returns the largest difference, and
// checks that bytes beyond each row's width are left alone.
int max_diff_vs_reference(int width, int height, const ClaheParams& params, int stride_pad, int offset,
                          KernelPath path) {
  const int stride = width + stride_pad;
  const TestImage src = make_image(width, height, stride, offset, static_cast<std::uint32_t>(width * 131 + height));
  TestImage ref = make_image(width, height, stride, (offset + 1) % 4, 1);
  TestImage out = make_image(width, height, stride, (offset + 3) % 4, 2);
  ClaheContext ctx_ref;
  ClaheContext ctx;
  EXPECT_TRUE(clahe(ctx_ref, params, src.view, ref.view, KernelPath::kReference).ok());
  const Status st = clahe(ctx, params, src.view, out.view, path);
  EXPECT_TRUE(st.ok()) << st.to_string();
  int worst = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) worst = std::max(worst, std::abs(ref.view.at(x, y) - out.view.at(x, y)));
    for (int x = width; x < stride; ++x) EXPECT_EQ(out.view.row(y)[x], 0xA5) << "wrote past the row end";
  }
  return worst;
}
#endif  // __ARM_NEON

// The vector paths this build has (none on x86).
std::vector<KernelPath> paths_under_test() {
  std::vector<KernelPath> p;
  if (compiled_vector_path() == KernelPath::kNeon) p.push_back(KernelPath::kNeon);
  return p;
}

// For properties every path must have (not equivalence): the reference and the vector paths.
std::vector<KernelPath> every_path() {
  std::vector<KernelPath> p = paths_under_test();
  p.insert(p.begin(), KernelPath::kReference);
  return p;
}

#if defined(__arm__) || defined(__aarch64__)
TEST(ClaheKernels, ArmBuildsHaveTheNeonKernel) {
  EXPECT_EQ(compiled_vector_path(), KernelPath::kNeon) << "ARM build without NEON: the equivalence tests would not be built";
}
#endif

// The equivalence tests exist where there is a vector CLAHE (NEON); x86 builds have none, so they
// are not built there (rather than counted as skipped: a skip in the host run stands out).
#if defined(__ARM_NEON)

TEST(ClaheKernels, Widths1To17AndOddHeights) {
  ASSERT_FALSE(paths_under_test().empty());
  for (const KernelPath path : paths_under_test()) {
    for (int w = 1; w <= 17; ++w) {
      for (int h : {1, 3, 7, 13, 33}) {
        for (const ClaheParams& p : {ClaheParams{8, 8, 2.0}, ClaheParams{3, 2, 4.0}, ClaheParams{1, 1, 0.0}}) {
          EXPECT_EQ(max_diff_vs_reference(w, h, p, 0, 0, path), 0)
              << "w=" << w << " h=" << h << " grid " << p.tiles_x << "x" << p.tiles_y << " " << to_string(path);
        }
      }
    }
  }
}

TEST(ClaheKernels, CameraSizesStrideAndUnalignedStarts) {
  ASSERT_FALSE(paths_under_test().empty());
  for (const KernelPath path : paths_under_test()) {
    for (int w : {640, 752}) {
      for (int h : {480, 479}) {
        for (int offset : {0, 1, 3}) {
          for (int pad : {0, 5, 64}) {
            EXPECT_EQ(max_diff_vs_reference(w, h, ClaheParams{8, 8, 2.0}, pad, offset, path), 0)
                << w << "x" << h << " offset " << offset << " pad " << pad << " " << to_string(path);
          }
        }
      }
    }
  }
}

TEST(ClaheKernels, GridsThatDoNotDivideTheImage) {
  ASSERT_FALSE(paths_under_test().empty());
  for (const KernelPath path : paths_under_test()) {
    for (const ClaheParams& p : {ClaheParams{7, 5, 2.0}, ClaheParams{3, 9, 3.0}, ClaheParams{13, 11, 1.0},
                                 ClaheParams{2, 3, 40.0}, ClaheParams{64, 40, 2.5}}) {
      for (int w : {641, 752, 99}) {
        EXPECT_EQ(max_diff_vs_reference(w, 481, p, 3, 1, path), 0)
            << "w=" << w << " grid " << p.tiles_x << "x" << p.tiles_y << " " << to_string(path);
      }
    }
  }
}

TEST(ClaheKernels, LargeTilesWithQuantisedWeights) {
  ASSERT_FALSE(paths_under_test().empty());
  for (const KernelPath path : paths_under_test()) {
    // 1x1 and 2x1 grids give tiles wider than 254 px (weights in 255ths).
    EXPECT_EQ(max_diff_vs_reference(753, 480, ClaheParams{1, 1, 2.0}, 0, 2, path), 0);
    EXPECT_EQ(max_diff_vs_reference(753, 480, ClaheParams{2, 1, 2.0}, 0, 2, path), 0);
  }
}

#endif  // __ARM_NEON

TEST(ClaheKernels, InPlaceEqualsOutOfPlace) {
  for (const KernelPath path : every_path()) {
    TestImage a = make_image(101, 77, 112, 1, 7);
    GrayImage out(101, 77);
    ClaheContext ctx;
    ASSERT_TRUE(clahe(ctx, {8, 8, 2.0}, a.view, out.view(), path).ok());
    ASSERT_TRUE(clahe(ctx, {8, 8, 2.0}, a.view, a.view, path).ok());
    for (int y = 0; y < 77; ++y)
      for (int x = 0; x < 101; ++x) ASSERT_EQ(a.view.at(x, y), out.view().at(x, y)) << x << "," << y;
  }
}

TEST(ClaheKernels, FlatImageStaysFlatAndMonotoneInput) {
  // A flat tile's LUT maps its grey to cdf = 1 at that bin; identical tiles blend to exactly it.
  GrayImage flat(64, 48, 90);
  GrayImage out(64, 48);
  ClaheContext ctx;
  ASSERT_TRUE(clahe(ctx, {4, 4, 0.0}, flat.view(), out.view()).ok());
  for (std::uint8_t v : out.pixels) ASSERT_EQ(v, 255);
}

// The two-step use (count, read the image's histogram, change the clip, apply): the histogram is
// the image's own whatever the grid's reflected margin, and the output equals a one-step CLAHE
// with the final clip.
TEST(ClaheKernels, CountedTilesGiveTheImageHistogramAndTheSameOutput) {
  for (const auto& [w, h, tx, ty] : {std::array<int, 4>{64, 48, 8, 6}, {101, 77, 8, 8}, {33, 250, 3, 7},
                                     {17, 9, 4, 2}, {640, 480, 8, 6}, {7, 5, 3, 2}}) {
    const TestImage src = make_image(w, h, w + 3, 1, static_cast<std::uint32_t>(w * 7 + h));
    std::array<std::uint32_t, 256> want{};
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) ++want[src.view.row(y)[x]];
    for (const KernelPath path : every_path()) {
      ClaheContext ctx;
      ASSERT_TRUE(ctx.configure(w, h, ClaheParams{tx, ty, 1.0}).ok());
      ASSERT_TRUE(ctx.count(src.view).ok());
      std::array<std::uint32_t, 256> got{};
      ctx.image_histogram(src.view, got);
      EXPECT_EQ(got, want) << w << "x" << h << " grid " << tx << "x" << ty;
      ASSERT_TRUE(ctx.set_clip_limit(3.0).ok());
      TestImage two = make_image(w, h, w + 3, 2, 5);
      ASSERT_TRUE(ctx.apply(src.view, two.view, path).ok());
      TestImage one = make_image(w, h, w + 3, 2, 6);
      ClaheContext fresh;
      ASSERT_TRUE(clahe(fresh, ClaheParams{tx, ty, 3.0}, src.view, one.view, path).ok());
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          ASSERT_EQ(two.view.at(x, y), one.view.at(x, y)) << w << "x" << h << " at " << x << "," << y;
    }
  }
  ClaheContext unconfigured;
  const TestImage img = make_image(8, 8, 8, 0, 1);
  EXPECT_FALSE(unconfigured.count(img.view).ok());
  EXPECT_FALSE(unconfigured.set_clip_limit(2.0).ok());
}

TEST(ClaheKernels, RejectsBadArguments) {
  ClaheContext ctx;
  GrayImage img(16, 16);
  GrayImage small(8, 16);
  EXPECT_FALSE(ctx.apply(img.view(), img.view()).ok());  // not configured
  EXPECT_FALSE(ctx.configure(0, 10, {}).ok());
  EXPECT_FALSE(ctx.configure(16, 16, {0, 8, 2.0}).ok());
  EXPECT_FALSE(ctx.configure(16, 16, {8, 300, 2.0}).ok());
  ASSERT_TRUE(ctx.configure(16, 16, {}).ok());
  EXPECT_FALSE(ctx.apply(small.view(), img.view()).ok());
  MutableGrayView shifted{img.pixels.data() + 1, 15, 16, 16};
  ASSERT_TRUE(ctx.configure(15, 16, {}).ok());
  EXPECT_FALSE(ctx.apply(GrayView{img.pixels.data(), 15, 16, 16}, shifted).ok());  // partial overlap
  if (compiled_vector_path() != KernelPath::kNeon) {
    ASSERT_TRUE(ctx.configure(16, 16, {}).ok());
    EXPECT_EQ(ctx.apply(img.view(), img.view(), KernelPath::kNeon).code(), StatusCode::kUnsupported);
  }
}

TEST(ClaheKernels, ForceRefEnvironmentVariable) {
  // The dispatcher reads ALE_FORCE_REF once per process; this checks the value it saw.
  const char* v = std::getenv("ALE_FORCE_REF");
  const bool forced = v != nullptr && std::string(v) == "1";
  const bool neon = compiled_vector_path() == KernelPath::kNeon;
  EXPECT_EQ(kernels().path, neon && !forced ? KernelPath::kNeon : KernelPath::kReference);
}

}  // namespace
}  // namespace ale::enhance
