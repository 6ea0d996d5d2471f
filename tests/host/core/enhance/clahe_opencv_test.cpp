// Our fixed-point CLAHE against OpenCV's cv::createCLAHE on real frames: same clip limit and
// grid, max |diff| <= 1 grey level and mean |diff| <= 0.05 per frame.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/enhance/clahe.h"
#include "core/io/image_io.h"
#include "tests/host/core/enhance/real_frames.h"
#include "tests/host/support/test_data.h"

namespace ale::enhance {
namespace {

struct Agreement {
  int max_diff = 0;
  double mean_diff = 0.0;
};

Agreement compare_with_opencv(const GrayImage& img, const ClaheParams& params) {
  cv::setNumThreads(1);
  const cv::Mat src(img.height, img.width, CV_8UC1, const_cast<std::uint8_t*>(img.pixels.data()));
  cv::Mat expected;
  cv::createCLAHE(params.clip_limit, cv::Size(params.tiles_x, params.tiles_y))->apply(src, expected);

  GrayImage ours(img.width, img.height);
  ClaheContext ctx;
  EXPECT_TRUE(clahe(ctx, params, img.view(), ours.view()).ok());
  Agreement a;
  long long sum = 0;
  for (int y = 0; y < img.height; ++y) {
    for (int x = 0; x < img.width; ++x) {
      const int d = std::abs(int{ours.view().at(x, y)} - int{expected.at<std::uint8_t>(y, x)});
      a.max_diff = std::max(a.max_diff, d);
      sum += d;
    }
  }
  a.mean_diff = static_cast<double>(sum) / (static_cast<double>(img.width) * img.height);
  return a;
}

void expect_agreement(const std::vector<std::string>& files, const ClaheParams& params) {
  ASSERT_FALSE(files.empty());
  double worst_mean = 0.0;
  int worst_max = 0;
  for (const std::string& f : files) {
    GrayImage img;
    const Status st = io::read_gray(f, img);
    ASSERT_TRUE(st.ok()) << st.to_string();
    const Agreement a = compare_with_opencv(img, params);
    EXPECT_LE(a.max_diff, 1) << f;
    EXPECT_LE(a.mean_diff, 0.05) << f;
    worst_mean = std::max(worst_mean, a.mean_diff);
    worst_max = std::max(worst_max, a.max_diff);
  }
  std::printf("clip %.2f grid %dx%d: %zu frames, worst max |diff| %d, worst mean |diff| %.5f\n",
              params.clip_limit, params.tiles_x, params.tiles_y, files.size(), worst_max, worst_mean);
}

const ClaheParams kSettings[] = {{8, 8, 2.0}, {8, 8, 4.0}, {4, 6, 3.0}, {16, 12, 1.5}};

TEST(ClaheVsOpenCv, EurocMicro) {
  ALE_REQUIRE_DATA(dir, "euroc_v101_micro/mav0/cam0/data");
  for (const ClaheParams& p : kSettings) expect_agreement(test::every(test::image_files(dir), 10), p);
}

TEST(ClaheVsOpenCv, DarkFrame) {
  ALE_REQUIRE_DATA(file, "lighting/dark_frame/euroc_dark.png");
  for (const ClaheParams& p : kSettings) expect_agreement({file}, p);
}

TEST(ClaheVsOpenCv, WebcamsInGrey) {
  ALE_REQUIRE_DATA(dir, "lighting/webcam");
  for (const char* cam : test::kWebcams)
    for (const ClaheParams& p : kSettings) expect_agreement(test::every(test::image_files(dir + "/" + cam), 4), p);
}

}  // namespace
}  // namespace ale::enhance
