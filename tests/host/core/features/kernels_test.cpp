// The extractor's kernels (score map, 7x7 Gaussian, ...): each scalar reference against a direct
// reading of its definition, and the NEON kernel (armhf build, run under qemu-arm) against the
// reference bit for bit, on synthetic images with saturated pixels and odd geometry and on a real
// frame. On x86 the NEON entry points fall back to the reference, so only the first half bites.
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "core/enhance/level_clahe.h"
#include "core/features/blur.h"
#include "core/features/brief.h"
#include "core/features/cell_clahe.h"
#include "core/features/orientation.h"
#include "core/features/pyramid.h"
#include "core/features/score_map.h"
#include "core/io/image_io.h"
#include "tests/host/core/features/blob_image.h"
#include "tests/host/support/test_data.h"

namespace ale::features {
namespace {

// Blobs, steps and noise over 0..255 with saturated pixels; stride > width, padding 0xA5.
struct TestImage {
  std::vector<std::uint8_t> pixels;
  int width = 0, height = 0, stride = 0;
  GrayView view() const { return {pixels.data(), width, height, stride}; }
};

TestImage make_image(int width, int height, std::uint32_t seed, int noise_amp = 40) {
  TestImage img;
  img.width = width;
  img.height = height;
  img.stride = width + 7;
  img.pixels.assign(static_cast<std::size_t>(img.stride) * static_cast<std::size_t>(height), 0xA5);
  test::fill_blobs(MutableGrayView{img.pixels.data(), width, height, img.stride}, seed, noise_amp);
  return img;
}

struct ScoreRun {
  std::vector<std::uint8_t> scores;
  std::vector<FastCorner> corners;
};

ScoreRun score_map(GrayView img, PixelRect rect, int t, KernelPath path) {
  ScoreRun r;
  r.scores.assign(static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height), 0xEE);
  fast9_score_map(img, rect, t, MutableGrayView{r.scores.data(), img.width, img.height, img.width}, r.corners, path);
  return r;
}

void expect_same(const ScoreRun& a, const ScoreRun& b, const std::string& what) {
  ASSERT_EQ(a.scores, b.scores) << what;
  ASSERT_EQ(a.corners.size(), b.corners.size()) << what;
  for (std::size_t i = 0; i < a.corners.size(); ++i) {
    ASSERT_EQ(a.corners[i].x, b.corners[i].x) << what << " corner " << i;
    ASSERT_EQ(a.corners[i].y, b.corners[i].y) << what << " corner " << i;
    ASSERT_EQ(a.corners[i].score, b.corners[i].score) << what << " corner " << i;
  }
}

TEST(ScoreMap, ReferenceIsTheThresholdedScoreOfEveryPixel) {
  const TestImage img = make_image(61, 23, 7);
  const PixelRect rect{3, 3, 55, 17};
  for (int t : {1, 7, 20, 30, 60, 200}) {
    const ScoreRun r = score_map(img.view(), rect, t, KernelPath::kReference);
    std::size_t n = 0;
    for (int y = 0; y < img.height; ++y) {
      for (int x = 0; x < img.width; ++x) {
        const std::uint8_t got = r.scores[static_cast<std::size_t>(y * img.width + x)];
        const bool inside = x >= rect.x && x < rect.x + rect.width && y >= rect.y && y < rect.y + rect.height;
        if (!inside) {
          ASSERT_EQ(got, 0xEE) << x << "," << y << " outside the rect was written";
          continue;
        }
        const int s = fast9_score(img.view().row(y) + x, img.stride);
        ASSERT_EQ(got, s >= t ? s : 0) << x << "," << y << " t=" << t;
        if (s >= t) {
          ASSERT_LT(n, r.corners.size());
          EXPECT_EQ(r.corners[n].x, x);
          EXPECT_EQ(r.corners[n].y, y);
          EXPECT_EQ(r.corners[n].score, s);
          ++n;
        }
      }
    }
    EXPECT_EQ(n, r.corners.size()) << "t=" << t;
    if (t == 20) {
      EXPECT_GT(n, 50u) << "the image should have corners";
    }
  }
}

TEST(ScoreMap, NeonMatchesReferenceOnEveryGeometry) {
  const TestImage img = make_image(80, 30, 11);
  for (int x0 = 3; x0 < 10; ++x0) {
    for (int w = 1; x0 + w <= 77 && w <= 60; ++w) {
      for (int t : {5, 20}) {
        const PixelRect rect{x0, 3, w, 24};
        const std::string what = "x0=" + std::to_string(x0) + " w=" + std::to_string(w) + " t=" + std::to_string(t);
        expect_same(score_map(img.view(), rect, t, KernelPath::kReference),
                    score_map(img.view(), rect, t, KernelPath::kNeon), what);
      }
    }
  }
}

TEST(ScoreMap, NeonMatchesReferenceOnNarrowSegmentsAtTheRightEdge) {
  // The narrow vector moves left to stay inside the image (22 pixels wide at least; narrower
  // images take the reference).
  for (int width : {21, 22, 23, 40, 57}) {
    const TestImage img = make_image(width, 20, static_cast<std::uint32_t>(width));
    for (int x0 = std::max(3, width - 3 - 18); x0 < width - 3; ++x0) {
      for (int w = 1; x0 + w <= width - 3 && w < 16; ++w) {
        for (int t : {5, 20}) {
          const PixelRect rect{x0, 3, w, 14};
          const std::string what = "width=" + std::to_string(width) + " x0=" + std::to_string(x0) +
                                   " w=" + std::to_string(w) + " t=" + std::to_string(t);
          expect_same(score_map(img.view(), rect, t, KernelPath::kReference),
                      score_map(img.view(), rect, t, KernelPath::kNeon), what);
        }
      }
    }
  }
}

TEST(ScoreMap, NeonMatchesReferenceOnConstantAndAllThresholds) {
  TestImage flat = make_image(40, 12, 3);
  std::fill(flat.pixels.begin(), flat.pixels.end(), std::uint8_t{128});
  EXPECT_TRUE(score_map(flat.view(), {3, 3, 34, 6}, 1, KernelPath::kNeon).corners.empty());
  const TestImage img = make_image(50, 14, 5, 120);
  for (int t = 1; t <= 254; t += 3)
    expect_same(score_map(img.view(), {3, 3, 44, 8}, t, KernelPath::kReference),
                score_map(img.view(), {3, 3, 44, 8}, t, KernelPath::kNeon), "t=" + std::to_string(t));
}

TEST(ScoreMap, NeonMatchesReferenceOnARealFrame) {
  ALE_REQUIRE_DATA(data, "euroc_v101_micro");
  GrayImage img;
  const Status st = io::read_gray(data + "/mav0/cam0/data/1403715273262142976.png", img);
  ASSERT_TRUE(st.ok()) << st.to_string();
  const PixelRect rect{3, 3, img.width - 6, img.height - 6};
  for (int t : {7, 20, 30}) {
    const ScoreRun ref = score_map(img.view(), rect, t, KernelPath::kReference);
    EXPECT_GT(ref.corners.size(), 100u);
    expect_same(ref, score_map(img.view(), rect, t, KernelPath::kNeon), "real frame t=" + std::to_string(t));
  }
}

TEST(ScoreMap, NonmaxAtKeepsStrictMaximaAboveTheThreshold) {
  std::vector<std::uint8_t> s(25, 0);
  const MutableGrayView sv{s.data(), 5, 5, 5};
  sv.at(2, 2) = 30;
  sv.at(1, 1) = 30;  // a tie: neither is a strict maximum
  sv.at(3, 3) = 10;
  const std::vector<FastCorner> in = {{1, 1, 30}, {2, 2, 30}, {3, 3, 10}};
  std::vector<FastCorner> out;
  fast9_nonmax_at(sv, in, 5, out);
  EXPECT_TRUE(out.empty());
  sv.at(1, 1) = 0;
  fast9_nonmax_at(sv, in, 31, out);
  EXPECT_TRUE(out.empty());
  fast9_nonmax_at(sv, in, 30, out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].x, 2);
}

// Every cell size the extractor uses at every level scale, on synthetic and real content, low and
// high contrast (clip limits from 1 to 4) and a flat cell: bit-exact with the general CLAHE.
TEST(CellClahe, MatchesContrastGuidedClaheBitForBit) {
  ALE_REQUIRE_DATA(data, "euroc_v101_micro");
  GrayImage frame;
  const Status st = io::read_gray(data + "/mav0/cam0/data/1403715273262142976.png", frame);
  ASSERT_TRUE(st.ok()) << st.to_string();
  const TestImage synth = make_image(140, 140, 21, 60);
  const enhance::LevelClaheParams params;
  CellClahe cell;
  enhance::ClaheContext general;
  int single = 0, total = 0;
  std::mt19937 rng(5);
  for (int w = 9; w <= 72; w += 3) {
    for (int h : {9, 20, 36, 41, 66}) {
      for (double scale : {1.0, 1 / 1.2, 1 / 1.728, 1 / 2.986, 1 / 3.583}) {
        for (int src_kind = 0; src_kind < 3; ++src_kind) {
          GrayView src;
          std::vector<std::uint8_t> flat(static_cast<std::size_t>(w * h), 77);
          if (src_kind == 0) {
            src = synth.view().sub(static_cast<int>(rng() % 60u), static_cast<int>(rng() % 60u), w, h);
          } else if (src_kind == 1) {
            src = frame.view().sub(static_cast<int>(rng() % 600u), static_cast<int>(rng() % 400u), w, h);
          } else {
            src = GrayView{flat.data(), w, h, w};
          }
          std::vector<std::uint8_t> a(static_cast<std::size_t>(w * h)), b(a.size());
          ASSERT_TRUE(cell.apply(params, scale, src, MutableGrayView{a.data(), w, h, w}).ok());
          ASSERT_TRUE(enhance::contrast_guided_clahe(general, params, scale, src, MutableGrayView{b.data(), w, h, w}).ok());
          ASSERT_EQ(a, b) << w << "x" << h << " scale " << scale << " kind " << src_kind;
          single += cell.last_was_single_tile() ? 1 : 0;
          ++total;
        }
      }
    }
  }
  EXPECT_GT(single, total / 2) << "the single-tile path should serve most cells";
  EXPECT_LT(single, total) << "some grids should have more than one tile";
}

std::vector<std::uint8_t> blur(GrayView img, KernelPath path) {
  std::vector<std::uint8_t> out(static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height), 0xEE);
  std::vector<std::uint8_t> scratch;
  gaussian7_interior(img, MutableGrayView{out.data(), img.width, img.height, img.width}, scratch, path);
  return out;
}

TEST(Blur, ReferenceIsTheRoundedSeparableKernelOnTheInterior) {
  const TestImage img = make_image(29, 17, 9, 120);
  const std::vector<std::uint8_t> got = blur(img.view(), KernelPath::kReference);
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const std::uint8_t g = got[static_cast<std::size_t>(y * img.width + x)];
      if (x < 3 || y < 3 || x >= img.width - 3 || y >= img.height - 3) {
        ASSERT_EQ(g, 0xEE) << x << "," << y << " border written";
        continue;
      }
      int h = 128;
      for (int i = -3; i <= 3; ++i) {
        int v = 128;
        for (int j = -3; j <= 3; ++j) v += kBlurTaps[j + 3] * img.view().at(x + i, y + j);
        h += kBlurTaps[i + 3] * (v >> 8);
      }
      ASSERT_EQ(g, h >> 8) << x << "," << y;
    }
  }
}

TEST(Blur, NeonMatchesReference) {
  for (int w : {6, 7, 8, 15, 16, 21, 22, 23, 37, 64, 101}) {
    for (int h : {6, 7, 9, 20}) {
      const TestImage img = make_image(w, h, static_cast<std::uint32_t>(w * 100 + h), 120);
      EXPECT_EQ(blur(img.view(), KernelPath::kReference), blur(img.view(), KernelPath::kNeon)) << w << "x" << h;
    }
  }
}

std::vector<std::uint8_t> blur_patches(GrayView img, const std::vector<FastCorner>& centres, int radius,
                                       KernelPath path) {
  std::vector<std::uint8_t> out(static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height), 0xEE);
  BlurScratch scratch;
  gaussian7_patches(img, MutableGrayView{out.data(), img.width, img.height, img.width}, centres, radius, scratch,
                    path);
  return out;
}

TEST(Blur, PatchesHoldTheInteriorBlurAroundEveryCentre) {
  // Centres in the middle, on the interior's edges and outside it; two radii.
  const TestImage img = make_image(101, 77, 5, 120);
  const std::vector<std::uint8_t> full = blur(img.view(), KernelPath::kReference);
  const std::vector<FastCorner> centres = {{50, 38, 1}, {0, 0, 1}, {100, 5, 1}, {20, 76, 1}, {60, 60, 1}, {66, 61, 1}};
  for (int radius : {4, 15}) {
    for (KernelPath path : {KernelPath::kReference, KernelPath::kNeon}) {
      const std::vector<std::uint8_t> got = blur_patches(img.view(), centres, radius, path);
      int written = 0;
      for (int y = 0; y < img.height; ++y) {
        for (int x = 0; x < img.width; ++x) {
          const std::size_t i = static_cast<std::size_t>(y * img.width + x);
          const bool interior = x >= 3 && y >= 3 && x < img.width - 3 && y < img.height - 3;
          if (!interior) {
            ASSERT_EQ(got[i], 0xEE) << x << "," << y << " border written";
            continue;
          }
          if (got[i] != 0xEE) ++written;
          bool needed = false;
          for (const FastCorner& c : centres) needed |= std::abs(x - c.x) <= radius && std::abs(y - c.y) <= radius;
          if (needed || got[i] != 0xEE) {
            ASSERT_EQ(got[i], full[i]) << "r " << radius << " at " << x << "," << y;
          }
        }
      }
      EXPECT_LT(written, (img.width - 6) * (img.height - 6) * 3 / 4) << "r " << radius << ": should leave cells out";
    }
  }
  EXPECT_EQ(blur_patches(img.view(), {}, 15, KernelPath::kNeon),
            std::vector<std::uint8_t>(static_cast<std::size_t>(img.width * img.height), 0xEE));
}

TEST(Blur, PatchesTrimEachRunToTheNeededColumns) {
  // One centre away from the cell grid's lines: the written columns are exactly its patch's, in
  // whole 8-row groups; two centres in the same groups make one run from the first's left edge to
  // the second's right edge. Rectangles narrower than a vector grow to 16 columns.
  const TestImage img = make_image(120, 77, 11, 120);
  struct Case {
    std::vector<FastCorner> centres;
    int radius, x0, x1;  // expected written columns [x0, x1]
  };
  const std::vector<Case> cases = {{{{52, 38, 1}}, 15, 37, 67}, {{{40, 30, 1}, {70, 31, 1}}, 15, 25, 85},
                                   {{{60, 40, 1}}, 3, 57, 72}};
  for (const Case& k : cases) {
    for (KernelPath path : {KernelPath::kReference, KernelPath::kNeon}) {
      const std::vector<std::uint8_t> got = blur_patches(img.view(), k.centres, k.radius, path);
      int lo = img.width, hi = -1;
      for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
          if (got[static_cast<std::size_t>(y * img.width + x)] != 0xEE) {
            lo = std::min(lo, x);
            hi = std::max(hi, x);
          }
      EXPECT_EQ(lo, k.x0) << k.centres.size() << " centres, r " << k.radius;
      EXPECT_EQ(hi, k.x1) << k.centres.size() << " centres, r " << k.radius;
    }
  }
}

TEST(Blur, NeonPatchesMatchReference) {
  std::mt19937 rng(3);
  for (int w : {7, 16, 22, 23, 37, 64, 101}) {
    for (int h : {7, 9, 20, 41}) {
      const TestImage img = make_image(w, h, static_cast<std::uint32_t>(w * 7 + h), 120);
      std::uniform_int_distribution<int> px(0, w - 1), py(0, h - 1);
      std::vector<FastCorner> centres;
      for (int i = 0; i < 3; ++i)
        centres.push_back({static_cast<std::int16_t>(px(rng)), static_cast<std::int16_t>(py(rng)), 1});
      EXPECT_EQ(blur_patches(img.view(), centres, 5, KernelPath::kReference),
                blur_patches(img.view(), centres, 5, KernelPath::kNeon))
          << w << "x" << h;
    }
  }
}

// dst of dw x dh from src through the bilinear downscale; rows of dst are dw + 3 apart, padding 0xEE.
std::vector<std::uint8_t> downscale(GrayView src, int dw, int dh, KernelPath path) {
  ResizePlan plan;
  plan_resize(src.width, src.height, dw, dh, plan);
  std::vector<std::uint8_t> out(static_cast<std::size_t>(dw + 3) * static_cast<std::size_t>(dh), 0xEE);
  std::vector<std::uint16_t> row;
  resize_bilinear(src, MutableGrayView{out.data(), dw, dh, dw + 3}, plan, row, path);
  return out;
}

// The sample position of output d in 1/256 pixel, from the definition in floating point.
int sample_256(int d, int src, int dst) {
  return static_cast<int>(std::floor(256.0 * ((d + 0.5) * src / dst - 0.5) + 0.5));
}

TEST(Pyramid, ReferenceIsTheFixedPointBilinearRoundedOnce) {
  const TestImage img = make_image(53, 31, 11, 120);
  for (const auto& [dw, dh] : {std::pair{44, 26}, std::pair{26, 15}, std::pair{53, 31}, std::pair{7, 3}, std::pair{1, 1}}) {
    const std::vector<std::uint8_t> got = downscale(img.view(), dw, dh, KernelPath::kReference);
    const auto sample = [](int d, int src, int dst, int& c0, int& w) {
      const int p = std::max(0, sample_256(d, src, dst));
      c0 = p >> 8;
      w = p & 255;
      if (c0 >= src - 1) {
        c0 = src - 1;
        w = 0;
      }
    };
    for (int y = 0; y < dh; ++y) {
      int y0 = 0, wy = 0;
      sample(y, img.height, dh, y0, wy);
      for (int x = 0; x < dw + 3; ++x) {
        const std::uint8_t g = got[static_cast<std::size_t>(y * (dw + 3) + x)];
        if (x >= dw) {
          ASSERT_EQ(g, 0xEE) << "padding written at " << x << "," << y;
          continue;
        }
        int x0 = 0, wx = 0;
        sample(x, img.width, dw, x0, wx);
        const auto v = [&](int xx) {
          return img.view().at(xx, y0) * (256 - wy) + (wy == 0 ? 0 : img.view().at(xx, y0 + 1) * wy);
        };
        ASSERT_EQ(g, (v(x0) * (256 - wx) + (wx == 0 ? 0 : v(x0 + 1) * wx) + 32768) >> 16)
            << dw << "x" << dh << " at " << x << "," << y;
      }
    }
  }
}

TEST(Pyramid, CloseToOpenCvBilinear) {
  // The same sampling as cv::resize(INTER_LINEAR); only the fixed-point rounding differs.
  const TestImage img = make_image(640, 480, 12, 120);
  const int dw = 533, dh = 400;
  const std::vector<std::uint8_t> got = downscale(img.view(), dw, dh, KernelPath::kReference);
  cv::Mat src(img.height, img.width, CV_8UC1, const_cast<std::uint8_t*>(img.pixels.data()),
              static_cast<std::size_t>(img.stride));
  cv::Mat want;
  cv::resize(src, want, cv::Size(dw, dh), 0, 0, cv::INTER_LINEAR);
  int worst = 0;
  int differ = 0;
  for (int y = 0; y < dh; ++y) {
    for (int x = 0; x < dw; ++x) {
      const int d = std::abs(got[static_cast<std::size_t>(y * (dw + 3) + x)] - want.at<std::uint8_t>(y, x));
      worst = std::max(worst, d);
      differ += d != 0;
    }
  }
  // 8-bit weights against OpenCV's 11 bits, on noise with saturated pixels (the worst case).
  EXPECT_LE(worst, 1);
  EXPECT_LT(differ, dw * dh / 5) << "pixels off cv::resize";
  std::printf("pyramid vs cv::resize: %d of %d pixels differ, by at most %d\n", differ, dw * dh, worst);
}

TEST(Pyramid, NeonMatchesReference) {
  // Scales around the pyramid's 1.2, 2 and above (no vtbl window: reference horizontal pass),
  // outputs narrower than a block, views starting at odd addresses with odd strides.
  const TestImage big = make_image(211, 67, 13, 120);
  for (int sw : {1, 2, 9, 16, 17, 31, 64, 101, 211}) {
    for (int sh : {1, 2, 7, 20, 67}) {
      for (int div10 : {10, 12, 15, 20, 23, 35}) {
        const int dw = std::max(1, sw * 10 / div10);
        const int dh = std::max(1, sh * 10 / div10);
        for (int start : {0, 3}) {
          if (start + sw > big.width) continue;
          const GrayView src{big.pixels.data() + start, sw, sh, big.stride};
          EXPECT_EQ(downscale(src, dw, dh, KernelPath::kReference), downscale(src, dw, dh, KernelPath::kNeon))
              << sw << "x" << sh << " -> " << dw << "x" << dh << " from column " << start;
        }
      }
    }
  }
}

TEST(Pyramid, NeonMatchesReferenceOnARealFrame) {
  ALE_REQUIRE_DATA(data, "euroc_v101_micro");
  GrayImage img;
  const Status st = io::read_gray(data + "/mav0/cam0/data/1403715273262142976.png", img);
  ASSERT_TRUE(st.ok()) << st.to_string();
  const GrayView v = img.view();
  EXPECT_EQ(downscale(v, 627, 400, KernelPath::kReference), downscale(v, 627, 400, KernelPath::kNeon));
}

TEST(Orientation, ReferenceMomentsAreTheDiskSums) {
  const TestImage img = make_image(45, 40, 21, 120);
  for (const auto& [x, y] : {std::pair{15, 15}, std::pair{20, 22}, std::pair{29, 24}}) {
    int m10 = 0, m01 = 0;
    for (int v = -15; v <= 15; ++v) {
      for (int u = -15; u <= 15; ++u) {
        if (u * u + v * v > 15 * 15 + 15) continue;
        m10 += u * img.view().at(x + u, y + v);
        m01 += v * img.view().at(x + u, y + v);
      }
    }
    const Moments m = ic_moments(img.view(), x, y, KernelPath::kReference);
    EXPECT_EQ(m.m10, m10) << x << "," << y;
    EXPECT_EQ(m.m01, m01) << x << "," << y;
  }
}

TEST(Orientation, NeonMatchesReference) {
  // Every centre of images with odd strides, saturated pixels and flat areas (the u16 lanes at
  // their extremes), including centres too close to the right edge for the 32-pixel window.
  for (int w : {31, 32, 33, 47, 64}) {
    for (int amp : {40, 255}) {
      TestImage img = make_image(w, 40, static_cast<std::uint32_t>(w * 7 + amp), amp);
      if (amp == 255) std::fill(img.pixels.begin(), img.pixels.begin() + img.stride * 20, std::uint8_t{255});
      for (int y = 15; y < img.height - 15; ++y) {
        for (int x = 15; x < img.width - 15; ++x) {
          const Moments r = ic_moments(img.view(), x, y, KernelPath::kReference);
          const Moments n = ic_moments(img.view(), x, y, KernelPath::kNeon);
          ASSERT_EQ(r.m10, n.m10) << w << " " << x << "," << y;
          ASSERT_EQ(r.m01, n.m01) << w << " " << x << "," << y;
        }
      }
    }
  }
}

// The distance by definition: differing bits counted one by one.
int differing_bits(const Descriptor& a, const Descriptor& b) {
  int d = 0;
  for (std::size_t i = 0; i < a.bytes.size(); ++i) {
    for (int k = 0; k < 8; ++k) d += ((a.bytes[i] ^ b.bytes[i]) >> k) & 1;
  }
  return d;
}

TEST(Hamming, ReferenceCountsTheDifferingBits) {
  // Every single bit, all bits, and random pairs (one byte pattern per lane of the NEON sums).
  Descriptor zero, ones;
  ones.bytes.fill(0xFF);
  EXPECT_EQ(internal::hamming_ref(zero, zero), 0);
  EXPECT_EQ(internal::hamming_ref(zero, ones), kDescriptorBits);
  EXPECT_EQ(internal::hamming_ref(ones, ones), 0);
  for (int bit = 0; bit < kDescriptorBits; ++bit) {
    Descriptor one;
    one.bytes[static_cast<std::size_t>(bit / 8)] = static_cast<std::uint8_t>(1u << (bit % 8));
    ASSERT_EQ(internal::hamming_ref(zero, one), 1) << bit;
    ASSERT_EQ(internal::hamming_ref(ones, one), kDescriptorBits - 1) << bit;
  }
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> byte(0, 255);
  for (int n = 0; n < 2000; ++n) {
    Descriptor a, b;
    for (auto& v : a.bytes) v = static_cast<std::uint8_t>(byte(rng));
    for (auto& v : b.bytes) v = static_cast<std::uint8_t>(byte(rng));
    ASSERT_EQ(internal::hamming_ref(a, b), differing_bits(a, b)) << n;
  }
}

TEST(Hamming, NeonMatchesReference) {
  // Random pairs with every density of differing bits (0..256), descriptors at odd addresses
  // (unaligned loads), and the dispatcher's kAuto path.
  std::mt19937 rng(9);
  std::uniform_int_distribution<int> byte(0, 255), position(0, kDescriptorBits - 1);
  std::vector<std::uint8_t> storage(2 * sizeof(Descriptor) + 3);
  for (int differing = 0; differing <= kDescriptorBits; ++differing) {
    for (int n = 0; n < 8; ++n) {
      Descriptor a;
      for (auto& v : a.bytes) v = static_cast<std::uint8_t>(byte(rng));
      Descriptor b = a;
      for (int k = 0; k < differing; ++k) {
        const int bit = position(rng);
        b.bytes[static_cast<std::size_t>(bit / 8)] ^= static_cast<std::uint8_t>(1u << (bit % 8));
      }
      const int want = internal::hamming_ref(a, b);
      ASSERT_EQ(hamming_distance(a, b, KernelPath::kNeon), want) << differing << " " << n;
      ASSERT_EQ(hamming_distance(a, b), want) << differing << " " << n;
      // the kernel a search takes once (hamming_kernel) is the one hamming_distance calls
      ASSERT_EQ(hamming_kernel(KernelPath::kNeon)(a, b), want) << differing << " " << n;
      ASSERT_EQ(hamming_kernel()(a, b), want) << differing << " " << n;
      ASSERT_EQ(hamming_kernel(KernelPath::kReference)(a, b), want) << differing << " " << n;
      // the same bytes at an odd address
      std::memcpy(storage.data() + 1, &a, sizeof a);
      std::memcpy(storage.data() + 1 + sizeof a, &b, sizeof b);
      const auto* ua = reinterpret_cast<const Descriptor*>(storage.data() + 1);
      const auto* ub = reinterpret_cast<const Descriptor*>(storage.data() + 1 + sizeof a);
      ASSERT_EQ(hamming_distance(*ua, *ub, KernelPath::kNeon), want) << differing << " " << n;
    }
  }
}

TEST(Brief, DescribeIsTheComparisonOfTheRotatedPatternPoints) {
  // Every angle bin at centres near the image corners; noise_amp 0 leaves flat runs, so many
  // pairs compare equal pixels (bit 0: "first < second" is strict).
  const BriefPattern pattern = make_brief_pattern();
  for (int amp : {0, 120}) {
    const TestImage img = make_image(41, 38, static_cast<std::uint32_t>(31 + amp), amp);
    RotatedPattern rotated;
    rotated.build(pattern, img.stride);
    for (int bin = 0; bin < kAngleBins; ++bin) {
      const double a = 2.0 * M_PI * bin / kAngleBins;
      const double c = std::cos(a), s = std::sin(a);
      for (const auto& [x, y] : {std::pair{15, 15}, std::pair{25, 15}, std::pair{15, 22}, std::pair{25, 22}}) {
        Descriptor want;
        for (int i = 0; i < kDescriptorBits; ++i) {
          int v[2];
          for (int k = 0; k < 2; ++k) {
            const double px = pattern.xy[static_cast<std::size_t>(4 * i + 2 * k)];
            const double py = pattern.xy[static_cast<std::size_t>(4 * i + 2 * k + 1)];
            v[k] = img.view().at(x + static_cast<int>(std::lround(px * c - py * s)),
                                 y + static_cast<int>(std::lround(px * s + py * c)));
          }
          if (v[0] < v[1]) want.bytes[static_cast<std::size_t>(i / 8)] |= static_cast<std::uint8_t>(1u << (i % 8));
        }
        Descriptor got;
        got.bytes.fill(0xEE);
        describe(img.view(), x, y, rotated, bin, got);
        ASSERT_EQ(got.bytes, want.bytes) << "amp " << amp << " bin " << bin << " at " << x << "," << y;
      }
    }
  }
}

}  // namespace
}  // namespace ale::features
