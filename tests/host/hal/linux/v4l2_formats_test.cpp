#include "hal/linux/v4l2_formats.h"

#include <gtest/gtest.h>
#include <linux/videodev2.h>

#include <cstdint>
#include <vector>

namespace ale::linux_hal {
namespace {

// A packed 4:2:2 buffer whose luma at (x, y) is 7x + 13y + 1 and whose chroma bytes are 0xC5
// (a value no luma takes in these sizes, so a chroma byte leaking into the output shows).
std::vector<std::uint8_t> make_packed(int width, int height, int stride, int luma_offset) {
  std::vector<std::uint8_t> buf(static_cast<std::size_t>(stride) * static_cast<std::size_t>(height), 0xC5);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      buf[static_cast<std::size_t>(y * stride + 2 * x + luma_offset)] = static_cast<std::uint8_t>((7 * x + 13 * y + 1) % 0xC5);
  return buf;
}

void expect_luma(GrayView g) {
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x)
      ASSERT_EQ(g.at(x, y), static_cast<std::uint8_t>((7 * x + 13 * y + 1) % 0xC5)) << "at " << x << "," << y;
}

void check_packed(int w, int h, int stride, int luma_offset) {
  const auto src = make_packed(w, h, stride, luma_offset);
  GrayImage dst(w, h, 0);
  packed422_to_gray(src.data(), stride, luma_offset, dst.view());
  expect_luma(dst.view());
}

TEST(Packed422ToGray, YuyvTakesEvenBytes) { check_packed(6, 3, 12, 0); }

TEST(Packed422ToGray, UyvyTakesOddBytes) { check_packed(8, 2, 16, 1); }

TEST(Packed422ToGray, PaddedSourceAndStridedDestination) {
  const int w = 5, h = 4, stride = 2 * w + 7;  // odd width and a padded line
  const auto src = make_packed(w, h, stride, 0);
  std::vector<std::uint8_t> out(static_cast<std::size_t>(16 * h), 0xEE);
  packed422_to_gray(src.data(), stride, 0, MutableGrayView{out.data(), w, h, 16});
  expect_luma(GrayView{out.data(), w, h, 16});
  for (int y = 0; y < h; ++y)
    for (int x = w; x < 16; ++x) EXPECT_EQ(out[static_cast<std::size_t>(y * 16 + x)], 0xEE) << "wrote past the row";
}

TEST(Packed422ToGray, OnePixel) {
  const std::uint8_t src[4] = {200, 1, 2, 3};
  std::uint8_t dst = 0;
  packed422_to_gray(src, 4, 0, MutableGrayView{&dst, 1, 1, 1});
  EXPECT_EQ(dst, 200);
}

TEST(ChooseFormat, PreferenceOrder) {
  EXPECT_EQ(choose_format({V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_GREY})->fourcc, V4L2_PIX_FMT_GREY);
  EXPECT_EQ(choose_format({V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_YUV420})->fourcc, V4L2_PIX_FMT_YUV420);
  EXPECT_EQ(choose_format({V4L2_PIX_FMT_MJPEG, V4L2_PIX_FMT_YUYV})->fourcc, V4L2_PIX_FMT_YUYV);
  EXPECT_EQ(choose_format({V4L2_PIX_FMT_UYVY})->luma_offset, 1);
  EXPECT_FALSE(choose_format({V4L2_PIX_FMT_MJPEG, V4L2_PIX_FMT_RGB24}).has_value());
  EXPECT_FALSE(choose_format({}).has_value());
  const auto all = usable_formats({V4L2_PIX_FMT_YUYV, V4L2_PIX_FMT_MJPEG, V4L2_PIX_FMT_NV12});
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all[0].fourcc, V4L2_PIX_FMT_NV12);
  EXPECT_EQ(all[1].fourcc, V4L2_PIX_FMT_YUYV);
}

TEST(ChooseFormat, BytesPerLineAndNames) {
  EXPECT_EQ(min_bytes_per_line(*luma_format(V4L2_PIX_FMT_YUYV), 640), 1280);
  EXPECT_EQ(min_bytes_per_line(*luma_format(V4L2_PIX_FMT_NV12), 640), 640);
  EXPECT_EQ(min_bytes_per_line(*luma_format(V4L2_PIX_FMT_GREY), 641), 641);
  EXPECT_EQ(fourcc_to_string(V4L2_PIX_FMT_YUYV), "YUYV");
  EXPECT_EQ(fourcc_to_string(0x01020304u), "????");
  EXPECT_EQ(accepted_formats().rfind("GREY ", 0), 0u);
}

}  // namespace
}  // namespace ale::linux_hal
