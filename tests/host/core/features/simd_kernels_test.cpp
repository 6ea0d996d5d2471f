// The build's vector kernels (compiled_vector_path(): SSE2 on x86_64, NEON in the armhf build under
// qemu-arm) against the scalar references, bit for bit: the FAST-9 score map, the 7x7 Gaussian and
// the pyramid's bilinear downscale and the orientation moments,
// on every segment geometry around the 16-pixel vector width, every threshold, saturated pixels
// and real frames (normal and dark). kernels_test.cpp checks the references against their
// definitions; here the reference is the oracle.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/features/blur.h"
#include "core/features/brief.h"
#include "core/features/orientation.h"
#include "core/features/pyramid.h"
#include "core/features/score_map.h"
#include "core/io/image_io.h"
#include "tests/host/support/test_data.h"

namespace ale::features {
namespace {

// Uniform noise with runs of 0 and 255, on rows `pad` bytes longer than the image (padding 0x5A).
struct Noise {
  std::vector<std::uint8_t> px;
  GrayView view;
};

Noise noise_image(int width, int height, int pad, int amplitude, std::uint32_t seed) {
  Noise n;
  const int stride = width + pad;
  n.px.assign(static_cast<std::size_t>(stride) * static_cast<std::size_t>(height), 0x5A);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> centre(0, 255), jitter(-amplitude, amplitude), kind(0, 15);
  for (int y = 0; y < height; ++y) {
    int base = centre(rng);
    for (int x = 0; x < width; ++x) {
      if (x % 7 == 0) base = centre(rng);
      int v = base + jitter(rng);
      const int k = kind(rng);
      if (k == 0) v = 0;
      if (k == 1) v = 255;
      n.px[static_cast<std::size_t>(y * stride + x)] = static_cast<std::uint8_t>(v < 0 ? 0 : v > 255 ? 255 : v);
    }
  }
  n.view = GrayView{n.px.data(), width, height, stride};
  return n;
}

struct Map {
  std::vector<std::uint8_t> scores;
  std::vector<FastCorner> corners;
};

Map run_map(GrayView img, PixelRect rect, int t, KernelPath path) {
  Map m;
  m.scores.assign(static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height), 0xC3);
  // Corners already in the list must survive: the kernels append.
  m.corners.push_back({1, 1, 1});
  fast9_score_map(img, rect, t, MutableGrayView{m.scores.data(), img.width, img.height, img.width}, m.corners, path);
  return m;
}

::testing::AssertionResult same_map(const Map& a, const Map& b) {
  if (a.scores != b.scores) return ::testing::AssertionFailure() << "score maps differ";
  if (a.corners.size() != b.corners.size())
    return ::testing::AssertionFailure() << a.corners.size() << " vs " << b.corners.size() << " corners";
  for (std::size_t i = 0; i < a.corners.size(); ++i) {
    const FastCorner &p = a.corners[i], &q = b.corners[i];
    if (p.x != q.x || p.y != q.y || p.score != q.score)
      return ::testing::AssertionFailure() << "corner " << i << ": " << p.x << "," << p.y << " s" << int{p.score}
                                           << " vs " << q.x << "," << q.y << " s" << int{q.score};
  }
  return ::testing::AssertionSuccess();
}

TEST(SimdKernels, ReportsTheVectorPath) {
#if defined(__SSE2__)
  EXPECT_EQ(compiled_vector_path(), KernelPath::kSse2);
#elif defined(__ARM_NEON)
  EXPECT_EQ(compiled_vector_path(), KernelPath::kNeon);
#elif defined(__arm__) || defined(__aarch64__)
  // The product's target: every equivalence test here would compare the reference with itself.
  ADD_FAILURE() << "ARM build without NEON (check -mfpu=neon in the toolchain file)";
#else
  ADD_FAILURE() << "no vector path on this architecture: the equivalence tests compare nothing";
#endif
  EXPECT_EQ(resolve_kernel_path(KernelPath::kAuto),
            reference_kernels_forced() ? KernelPath::kReference : compiled_vector_path());
  EXPECT_EQ(resolve_kernel_path(compiled_vector_path()), compiled_vector_path());
  EXPECT_EQ(resolve_kernel_path(KernelPath::kReference), KernelPath::kReference);
  EXPECT_STREQ(to_string(KernelPath::kSse2), "sse2");
  std::printf("vector path: %s\n", to_string(compiled_vector_path()));
}

TEST(SimdKernels, ScoreMapEverySegmentGeometry) {
  // Segments from 1 to 70 pixels at every start modulo 16, ending flush with the readable area or
  // not: covers the masked narrow vector, the reference fallback and the overlapping last vector.
  const Noise img = noise_image(90, 16, 5, 50, 3);
  int compared = 0;
  for (int x0 = 3; x0 < 19; ++x0) {
    for (int w = 1; x0 + w <= 87 && w <= 70; ++w) {
      for (int t : {3, 25}) {
        const PixelRect rect{x0, 3, w, 10};
        ASSERT_TRUE(same_map(run_map(img.view, rect, t, KernelPath::kReference),
                             run_map(img.view, rect, t, compiled_vector_path())))
            << "x0=" << x0 << " w=" << w << " t=" << t;
        ++compared;
      }
    }
  }
  EXPECT_GT(compared, 2000);
}

TEST(SimdKernels, ScoreMapEveryThreshold) {
  for (int amplitude : {10, 60, 128}) {
    const Noise img = noise_image(53, 13, 0, amplitude, static_cast<std::uint32_t>(amplitude));
    std::size_t corners = 0;
    for (int t = 1; t <= 254; ++t) {
      const Map ref = run_map(img.view, {3, 3, 47, 7}, t, KernelPath::kReference);
      ASSERT_TRUE(same_map(ref, run_map(img.view, {3, 3, 47, 7}, t, compiled_vector_path())))
          << "amplitude " << amplitude << " t=" << t;
      corners += ref.corners.size() - 1;
    }
    EXPECT_GT(corners, 100u) << "amplitude " << amplitude;
  }
}

TEST(SimdKernels, ScoreMapEveryArcPattern) {
  // Candidates 7 pixels apart on a flat background, each circle a brighter arc of a pixels and a
  // darker arc of b pixels (gap g between them) at every rotation, with differences just at, just
  // above or far above the threshold: every choice of the vector kernels' passes (one polarity,
  // both polarities in different lanes, a lane that may be either), corners whose arc the
  // compass points alone do not rule out, and the diagonal test's rejections.
  constexpr int kCells = 40, kCentre = 100;
  for (int t : {7, 20}) {
    std::vector<std::array<int, 16>> circles;
    const std::pair<int, int> deltas[] = {{t, t}, {t + 1, t + 1}, {t + 1, 60}, {60, t + 1}, {60, 60}};
    for (int a : {0, 4, 5, 7, 8, 9, 12, 16})
      for (int b : {0, 3, 5, 7, 8, 9})
        for (int g : {0, 2})
          for (const auto& [db, dd] : deltas)
            for (int r = 0; r < 16; ++r) {
              if (a + g + b > 16 || (a == 16 && g > 0)) continue;
              std::array<int, 16> c;
              c.fill(kCentre);
              for (int i = 0; i < a; ++i) c[static_cast<std::size_t>((r + i) % 16)] = kCentre + db;
              for (int i = 0; i < b; ++i) c[static_cast<std::size_t>((r + a + g + i) % 16)] = kCentre - dd;
              circles.push_back(c);
            }
    const int rows = static_cast<int>((circles.size() + kCells - 1) / kCells);
    const int width = 7 * kCells + 6, height = 7 * rows + 6;
    std::vector<std::uint8_t> px(static_cast<std::size_t>(width * height), static_cast<std::uint8_t>(kCentre));
    for (std::size_t i = 0; i < circles.size(); ++i) {
      const int x = 6 + 7 * static_cast<int>(i % kCells), y = 6 + 7 * static_cast<int>(i / kCells);
      for (int k = 0; k < 16; ++k)
        px[static_cast<std::size_t>((y + internal::kCircleDy[k]) * width + x + internal::kCircleDx[k])] =
            static_cast<std::uint8_t>(circles[i][static_cast<std::size_t>(k)]);
    }
    const GrayView img{px.data(), width, height, width};
    const PixelRect rect{3, 3, width - 6, height - 6};
    const Map ref = run_map(img, rect, t, KernelPath::kReference);
    EXPECT_GT(ref.corners.size(), circles.size() / 4) << "t=" << t;
    EXPECT_TRUE(same_map(ref, run_map(img, rect, t, compiled_vector_path()))) << "t=" << t;
  }
}

TEST(SimdKernels, ScoreMapRealFrames) {
  ALE_REQUIRE_DATA(data, "euroc_v101_micro");
  ALE_REQUIRE_DATA(dark, "lighting/dark_frame/euroc_dark.png");
  for (const std::string& f : {data + "/mav0/cam0/data/1403715273262142976.png", dark}) {
    GrayImage img;
    const Status st = io::read_gray(f, img);
    ASSERT_TRUE(st.ok()) << st.to_string();
    for (int t : {5, 7, 12, 20}) {
      const PixelRect rect{3, 3, img.width - 6, img.height - 6};
      const Map ref = run_map(img.view(), rect, t, KernelPath::kReference);
      EXPECT_GT(ref.corners.size(), 10u) << f << " t=" << t;
      EXPECT_TRUE(same_map(ref, run_map(img.view(), rect, t, compiled_vector_path()))) << f << " t=" << t;
    }
  }
}

TEST(SimdKernels, Fast9DetectVectorPathMatches) {
  const Noise img = noise_image(70, 20, 9, 70, 8);
  std::vector<std::uint8_t> sa(70 * 20, 0), sb(70 * 20, 0);
  std::vector<FastCorner> a, b;
  const PixelRect r{3, 3, 64, 14};
  ASSERT_TRUE(fast9_detect(img.view, r, 15, MutableGrayView{sa.data(), 70, 20, 70}, a, KernelPath::kReference).ok());
  ASSERT_TRUE(fast9_detect(img.view, r, 15, MutableGrayView{sb.data(), 70, 20, 70}, b, compiled_vector_path()).ok());
  EXPECT_EQ(sa, sb);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_GT(a.size(), 20u);
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_TRUE(a[i].x == b[i].x && a[i].y == b[i].y && a[i].score == b[i].score);
}

std::vector<std::uint8_t> blurred(GrayView img, KernelPath path) {
  std::vector<std::uint8_t> out(static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height), 0xC3);
  std::vector<std::uint8_t> scratch;
  gaussian7_interior(img, MutableGrayView{out.data(), img.width, img.height, img.width}, scratch, path);
  return out;
}

TEST(SimdKernels, GaussianEveryWidth) {
  for (int w = 6; w <= 56; ++w) {
    for (int h : {6, 7, 8, 19}) {
      const Noise img = noise_image(w, h, w % 4, 127, static_cast<std::uint32_t>(w * 31 + h));
      ASSERT_EQ(blurred(img.view, KernelPath::kReference), blurred(img.view, compiled_vector_path())) << w << "x" << h;
    }
  }
  // Saturated extremes: the widest sums the u16 lanes must hold.
  std::vector<std::uint8_t> white(40 * 12, 255);
  const GrayView wv{white.data(), 40, 12, 40};
  const std::vector<std::uint8_t> ref = blurred(wv, KernelPath::kReference);
  EXPECT_EQ(ref[5 * 40 + 5], 255);
  EXPECT_EQ(ref, blurred(wv, compiled_vector_path()));
}

TEST(SimdKernels, GaussianRealFrame) {
  ALE_REQUIRE_DATA(data, "euroc_v101_micro");
  GrayImage img;
  const Status st = io::read_gray(data + "/mav0/cam0/data/1403715273262142976.png", img);
  ASSERT_TRUE(st.ok()) << st.to_string();
  EXPECT_EQ(blurred(img.view(), KernelPath::kReference), blurred(img.view(), compiled_vector_path()));
}

TEST(SimdKernels, GaussianPatchesRealFrame) {
  ALE_REQUIRE_DATA(data, "euroc_v101_micro");
  GrayImage img;
  const Status st = io::read_gray(data + "/mav0/cam0/data/1403715273262142976.png", img);
  ASSERT_TRUE(st.ok()) << st.to_string();
  std::mt19937 rng(17);
  std::uniform_int_distribution<int> px(0, img.width - 1), py(0, img.height - 1);
  std::vector<FastCorner> centres;
  for (int i = 0; i < 300; ++i)
    centres.push_back({static_cast<std::int16_t>(px(rng)), static_cast<std::int16_t>(py(rng)), 1});
  const std::vector<std::uint8_t> full = blurred(img.view(), KernelPath::kReference);
  for (KernelPath path : {KernelPath::kReference, compiled_vector_path()}) {
    std::vector<std::uint8_t> out(full.size(), 0xC3);
    BlurScratch scratch;
    // Twice: the second call reuses the scratch.
    for (int k = 0; k < 2; ++k)
      gaussian7_patches(img.view(), MutableGrayView{out.data(), img.width, img.height, img.width}, centres,
                        kPatchRadius, scratch, path);
    for (std::size_t i = 0; i < out.size(); ++i)
      if (out[i] != 0xC3) {
        ASSERT_EQ(out[i], full[i]) << "pixel " << i;
      }
    for (const FastCorner& c : centres)
      for (int y = std::max(3, c.y - kPatchRadius); y <= std::min(img.height - 4, c.y + kPatchRadius); ++y)
        for (int x = std::max(3, c.x - kPatchRadius); x <= std::min(img.width - 4, c.x + kPatchRadius); ++x)
          ASSERT_EQ(out[static_cast<std::size_t>(y * img.width + x)], full[static_cast<std::size_t>(y * img.width + x)]);
  }
}

// `vector_ran`, when given, says whether `path` ran vector code: SSE2 does at every size, NEON only
// when the plan has blocks (pyramid.h: dst_w >= 16, src_w >= 32, scale up to about 2), else the
// reference runs.
std::vector<std::uint8_t> resized(GrayView src, int dw, int dh, KernelPath path, bool* vector_ran = nullptr) {
  ResizePlan plan;
  plan_resize(src.width, src.height, dw, dh, plan);
  std::vector<std::uint8_t> out(static_cast<std::size_t>(dw + 5) * static_cast<std::size_t>(dh), 0xC3);
  std::vector<std::uint16_t> row;
  resize_bilinear(src, MutableGrayView{out.data(), dw, dh, dw + 5}, plan, row, path);
  if (vector_ran != nullptr)
    *vector_ran = (path == KernelPath::kSse2 && compiled_vector_path() == KernelPath::kSse2) ||
                  (path == KernelPath::kNeon && compiled_vector_path() == KernelPath::kNeon && !plan.blocks.empty());
  return out;
}

TEST(SimdKernels, DownscaleEverySize) {
  // Every destination width up to the source's (scale 1 to 64, both sides of the 8- and
  // 16-sample vectors), saturated noise, heights including 1. Sources of 32 pixels and more give
  // the NEON path its blocks (16 outputs from a 32-pixel window) at scales up to about 2: widths
  // around 32, 48 and 64 outputs, the last block overlapping. Only comparisons that ran vector
  // code count: the others compare the reference with itself.
  int compared = 0;
  for (int sw : {1, 2, 7, 8, 9, 16, 17, 23, 32, 33, 40, 47, 64, 65, 97, 130}) {
    for (int sh : {1, 3, 10}) {
      const Noise img = noise_image(sw, sh, sw % 3, 127, static_cast<std::uint32_t>(sw * 7 + sh));
      for (int dw = 1; dw <= sw; ++dw) {
        for (int dh : {1, (sh + 1) / 2, sh}) {
          bool vector_ran = false;
          const std::vector<std::uint8_t> vec = resized(img.view, dw, dh, compiled_vector_path(), &vector_ran);
          ASSERT_EQ(resized(img.view, dw, dh, KernelPath::kReference), vec)
              << sw << "x" << sh << " -> " << dw << "x" << dh;
          if (vector_ran) ++compared;
        }
      }
    }
  }
  std::printf("vector resizes compared: %d\n", compared);
  EXPECT_GT(compared, 600);
}

TEST(SimdKernels, DownscaleEveryHeightOfATallSource) {
  // Every destination height from half the source's to all of it: the NEON path takes consecutive
  // output rows on source rows c, c + 1 and c + 1, c + 2 in one pass, alone otherwise, and an
  // output row on one source row (weight 0) by itself; every mix of the three occurs here.
  const Noise img = noise_image(64, 41, 2, 127, 23);
  for (int dh = 21; dh <= 41; ++dh) {
    for (int dw : {16, 37, 64}) {
      ASSERT_EQ(resized(img.view, dw, dh, KernelPath::kReference), resized(img.view, dw, dh, compiled_vector_path()))
          << "64x41 -> " << dw << "x" << dh;
    }
  }
}

TEST(SimdKernels, DownscaleRealFramePyramid) {
  ALE_REQUIRE_DATA(data, "euroc_v101_micro");
  GrayImage img;
  const Status st = io::read_gray(data + "/mav0/cam0/data/1403715273262142976.png", img);
  ASSERT_TRUE(st.ok()) << st.to_string();
  // The extractor's level sizes (scale 1.2) and one coarse step.
  for (const auto& [dw, dh] : {std::pair{627, 400}, std::pair{522, 333}, std::pair{250, 160}, std::pair{93, 60}}) {
    const std::vector<std::uint8_t> ref = resized(img.view(), dw, dh, KernelPath::kReference);
    EXPECT_EQ(ref, resized(img.view(), dw, dh, compiled_vector_path())) << dw << "x" << dh;
  }
}

TEST(SimdKernels, OrientationMomentsEveryPosition) {
  // Saturated noise (the largest sums), a constant patch (m10 = m01 = 0) and every column up to the
  // right edge, where the 32-pixel window no longer fits and the reference takes over.
  const Noise img = noise_image(80, 40, 3, 127, 17);
  int compared = 0;
  for (int y = kPatchRadius; y < img.view.height - kPatchRadius; y += 3) {
    for (int x = kPatchRadius; x < img.view.width - kPatchRadius; ++x) {
      const Moments a = ic_moments(img.view, x, y, KernelPath::kReference);
      const Moments b = ic_moments(img.view, x, y, compiled_vector_path());
      ASSERT_TRUE(a.m10 == b.m10 && a.m01 == b.m01) << x << "," << y << ": " << a.m10 << "," << a.m01 << " vs "
                                                    << b.m10 << "," << b.m01;
      ++compared;
    }
  }
  EXPECT_EQ(compared, 4 * 50);
  std::vector<std::uint8_t> white(40 * 40, 255);
  const GrayView wv{white.data(), 40, 40, 40};
  const Moments w = ic_moments(wv, 18, 18, compiled_vector_path());
  EXPECT_EQ(w.m10, 0);
  EXPECT_EQ(w.m01, 0);
  // One bright pixel at the disk's edge (u = 15, v = 0), on black.
  std::vector<std::uint8_t> dot(40 * 40, 0);
  dot[18 * 40 + 18 + kPatchRadius] = 255;
  const Moments d = ic_moments(GrayView{dot.data(), 40, 40, 40}, 18, 18, compiled_vector_path());
  EXPECT_EQ(d.m10, 15 * 255);
  EXPECT_EQ(d.m01, 0);
}

TEST(SimdKernels, OrientationMomentsRealFrame) {
  ALE_REQUIRE_DATA(data, "euroc_v101_micro");
  GrayImage img;
  const Status st = io::read_gray(data + "/mav0/cam0/data/1403715273262142976.png", img);
  ASSERT_TRUE(st.ok()) << st.to_string();
  for (int y = kPatchRadius; y < img.height - kPatchRadius; y += 7) {
    for (int x = kPatchRadius; x < img.width - kPatchRadius; x += 5) {
      const Moments a = ic_moments(img.view(), x, y, KernelPath::kReference);
      const Moments b = ic_moments(img.view(), x, y, compiled_vector_path());
      ASSERT_TRUE(a.m10 == b.m10 && a.m01 == b.m01) << x << "," << y;
    }
  }
}

}  // namespace
}  // namespace ale::features
