// Extraction time per 752x480 EuRoC frame, 1000 features, 8 levels, scale 1.2: our baseline
// (ORB-SLAM3-like), ALE on a normal and on the dark frame, CLAHE-everywhere, the FAST kernel alone,
// and OpenCV's cv::ORB single-threaded when OpenCV's features2d is in the dependency build.
//
//   ALE_DATA_DIR=../shared/data build/host/bin/ale_features_bench
#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>
#ifdef ALE_HAVE_FEATURES2D
#include <opencv2/features2d.hpp>
#endif

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "core/features/orb.h"
#include "core/frontend/frame_path.h"
#include "core/io/image_io.h"

namespace {

using namespace ale;
using namespace ale::features;

std::string data_dir() {
  const char* d = std::getenv("ALE_DATA_DIR");
  return d != nullptr ? d : "../shared/data";
}

const GrayImage& frame(bool dark) {
  static GrayImage normal_img, dark_img;
  GrayImage& img = dark ? dark_img : normal_img;
  if (img.pixels.empty()) {
    const std::string path = data_dir() + (dark ? "/lighting/dark_frame/euroc_dark.png"
                                                 : "/euroc_v101_micro/mav0/cam0/data/1403715273262142976.png");
    const Status st = io::read_gray(path, img);
    if (!st.ok()) {
      std::fprintf(stderr, "%s (set ALE_DATA_DIR)\n", st.to_string().c_str());
      std::exit(1);
    }
  }
  return img;
}

void extract_bench(benchmark::State& state, ExtractorMode mode, bool dark) {
  cv::setNumThreads(1);
  const GrayImage& img = frame(dark);
  ExtractorConfig cfg;
  cfg.mode = mode;
  frontend::FramePath ex;
  if (!ex.configure(cfg).ok()) state.SkipWithError("configure");
  std::vector<Keypoint> k;
  std::vector<Descriptor> d;
  for (auto _ : state) {
    ex.reset();
    if (!ex.extract(img.view(), k, d).ok()) state.SkipWithError("extract");
    benchmark::DoNotOptimize(d.data());
  }
  state.counters["features"] = static_cast<double>(k.size());
}

void BM_Baseline(benchmark::State& s) { extract_bench(s, ExtractorMode::kBaseline, false); }
void BM_Ale(benchmark::State& s) { extract_bench(s, ExtractorMode::kAle, false); }
void BM_AleDark(benchmark::State& s) { extract_bench(s, ExtractorMode::kAle, true); }
void BM_BaselineDark(benchmark::State& s) { extract_bench(s, ExtractorMode::kBaseline, true); }
void BM_ClaheEverywhere(benchmark::State& s) { extract_bench(s, ExtractorMode::kClahe, false); }
BENCHMARK(BM_Baseline)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ale)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BaselineDark)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AleDark)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ClaheEverywhere)->Unit(benchmark::kMillisecond);

void BM_Fast9Level0(benchmark::State& state) {
  const GrayImage& img = frame(false);
  std::vector<std::uint8_t> scores(img.pixels.size());
  const MutableGrayView sv{scores.data(), img.width, img.height, img.width};
  std::vector<FastCorner> corners;
  const auto path = static_cast<KernelPath>(state.range(0));
  for (auto _ : state) {
    corners.clear();
    if (!fast9_detect(img.view(), {3, 3, img.width - 6, img.height - 6}, 20, sv, corners, path).ok())
      state.SkipWithError("fast9");
    benchmark::DoNotOptimize(corners.data());
  }
  state.SetLabel(to_string(path == KernelPath::kAuto ? active_kernel_path() : path));
}
BENCHMARK(BM_Fast9Level0)->Arg(static_cast<int>(KernelPath::kReference))->Arg(static_cast<int>(KernelPath::kAuto))
    ->Unit(benchmark::kMicrosecond);

#ifdef ALE_HAVE_FEATURES2D
void BM_OpenCvOrb(benchmark::State& state) {
  cv::setNumThreads(1);
  const GrayImage& img = frame(false);
  const cv::Mat m(img.height, img.width, CV_8UC1, const_cast<std::uint8_t*>(img.pixels.data()));
  cv::Ptr<cv::ORB> orb = cv::ORB::create(1000, 1.2f, 8, 19, 0, 2, cv::ORB::HARRIS_SCORE, 31, 20);
  std::vector<cv::KeyPoint> k;
  cv::Mat d;
  for (auto _ : state) {
    orb->detectAndCompute(m, cv::noArray(), k, d);
    benchmark::DoNotOptimize(d.data);
  }
  state.counters["features"] = static_cast<double>(k.size());
}
BENCHMARK(BM_OpenCvOrb)->Unit(benchmark::kMillisecond);
#endif

}  // namespace

BENCHMARK_MAIN();
