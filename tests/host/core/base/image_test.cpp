#include "core/base/image.h"

#include <gtest/gtest.h>

#include <utility>

namespace ale {
namespace {

TEST(ImageViewTest, RowsFollowStride) {
  std::uint8_t buf[4 * 3] = {};
  MutableGrayView v{buf, 3, 3, 4};
  v.at(2, 1) = 7;
  EXPECT_EQ(buf[1 * 4 + 2], 7);
  GrayView c = v;  // mutable converts to const
  EXPECT_EQ(c.at(2, 1), 7);
  GrayView s = c.sub(1, 1, 2, 2);
  EXPECT_EQ(s.at(1, 0), 7);
  EXPECT_TRUE(c.contains(1, 1, 2, 2));
  EXPECT_FALSE(c.contains(2, 2, 2, 2));
}

TEST(ImageViewTest, CheckViewNamesTheProblem) {
  std::uint8_t px = 0;
  EXPECT_TRUE(check_view(GrayView{&px, 1, 1, 1}, "in").ok());
  EXPECT_EQ(check_view(GrayView{nullptr, 1, 1, 1}, "in").code(), StatusCode::kInvalidArgument);
  Status s = check_view(GrayView{&px, 4, 1, 2}, "cell");
  EXPECT_NE(s.message().find("stride"), std::string::npos);
  EXPECT_NE(s.message().find("cell"), std::string::npos);
}

TEST(PooledImageTest, ComesFromPoolAndGoesBack) {
  BlockPool pool("img", static_cast<std::size_t>(aligned_stride(33)) * 10, 1);
  {
    Result<PooledImage> img = PooledImage::create(pool, 33, 10);
    ASSERT_TRUE(img.ok()) << img.status().to_string();
    EXPECT_EQ(img->stride(), 48);
    EXPECT_EQ(pool.stats().in_use, 1u);
    EXPECT_EQ(PooledImage::create(pool, 33, 10).status().code(), StatusCode::kOutOfMemory);
    PooledImage moved = std::move(*img);
    EXPECT_TRUE(img->empty());
    EXPECT_EQ(pool.stats().in_use, 1u);
    moved.view().at(32, 9) = 1;
  }
  EXPECT_EQ(pool.stats().in_use, 0u);
  EXPECT_EQ(pool.stats().bad_frees, 0u);
}

TEST(PooledImageTest, TooLargeForBlocksIsRejected) {
  BlockPool pool("small", 64, 4);
  Result<PooledImage> img = PooledImage::create(pool, 640, 480);
  EXPECT_EQ(img.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(PooledImage::create(pool, 0, 4).status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(pool.stats().in_use, 0u);
}

TEST(GrayImageTest, CopyPixelsHonoursStrides) {
  GrayImage a(5, 3, 9);
  std::uint8_t buf[8 * 3] = {};
  copy_pixels(a.view(), MutableGrayView{buf, 5, 3, 8});
  EXPECT_EQ(buf[2 * 8 + 4], 9);
  EXPECT_EQ(buf[2 * 8 + 5], 0);
}

}  // namespace
}  // namespace ale
