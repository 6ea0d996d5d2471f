// Runs CLAHE on one real frame a given number of times, for counting ARM instructions under
// qemu (../shared/tools/arm_icount.py): per-frame cost = (count(N=3) - count(N=1)) / 2, which
// cancels start-up, file decoding and first-call allocation.
//
//   ale_clahe_icount ours|ref|opencv|none FRAME WIDTHxHEIGHT REPEATS
// The frame is cropped (top-left) to WIDTHxHEIGHT; grid 8x8, clip limit 2.0, one thread.
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "core/enhance/clahe.h"
#include "core/enhance/kernels.h"
#include "core/io/image_io.h"

int main(int argc, char** argv) {
  using namespace ale;
  int w = 0;
  int h = 0;
  if (argc != 5 || std::sscanf(argv[3], "%dx%d", &w, &h) != 2) {
    std::fprintf(stderr, "usage: %s ours|ref|opencv|none FRAME WIDTHxHEIGHT REPEATS\n", argv[0]);
    return 2;
  }
  const std::string mode = argv[1];
  const int repeats = std::atoi(argv[4]);
  GrayImage frame;
  const Status st = io::read_gray(argv[2], frame);
  if (!st.ok()) {
    std::fprintf(stderr, "%s\n", st.to_string().c_str());
    return 1;
  }
  if (frame.width < w || frame.height < h) {
    std::fprintf(stderr, "%s is %dx%d, smaller than %dx%d\n", argv[2], frame.width, frame.height, w, h);
    return 1;
  }
  const GrayView src{frame.pixels.data(), w, h, frame.width};
  GrayImage out(w, h);
  unsigned checksum = 0;
  if (mode == "ours" || mode == "ref") {
    enhance::ClaheContext ctx;
    const auto path = mode == "ours" ? KernelPath::kAuto : KernelPath::kReference;
    for (int i = 0; i < repeats; ++i) {
      const Status s = enhance::clahe(ctx, {8, 8, 2.0}, src, out.view(), path);
      if (!s.ok()) {
        std::fprintf(stderr, "%s\n", s.to_string().c_str());
        return 1;
      }
    }
    std::printf("path %s\n", ale::to_string(mode == "ours" ? enhance::kernels().path : path));
  } else if (mode == "opencv") {
    cv::setNumThreads(1);
    const cv::Mat in(h, w, CV_8UC1, const_cast<std::uint8_t*>(src.data), static_cast<std::size_t>(frame.width));
    cv::Mat dst(h, w, CV_8UC1, out.pixels.data());
    const cv::Ptr<cv::CLAHE> clahe = cv::createCLAHE(2.0, cv::Size(8, 8));
    for (int i = 0; i < repeats; ++i) clahe->apply(in, dst);
  } else if (mode != "none") {
    std::fprintf(stderr, "unknown mode %s\n", mode.c_str());
    return 2;
  }
  for (std::uint8_t v : out.pixels) checksum = checksum * 31u + v;
  std::printf("%s %dx%d x%d checksum %08x\n", mode.c_str(), w, h, repeats, checksum);
  return 0;
}
