// Per-frame cost of the enhancement at 752x480 and 640x480 on a real EuRoC frame: our CLAHE
// (reference and best path), OpenCV's CLAHE single-threaded in the same run, the gamma LUT, and
// the whole enhancement per brightness class. Figures go to docs/performance.md.
//   ale_enhance_bench [--benchmark_filter=...]   (data: $ALE_DATA_DIR or the build's default)
#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "core/enhance/enhancer.h"
#include "core/enhance/kernels.h"
#include "core/io/image_io.h"

namespace {

using namespace ale;
using namespace ale::enhance;

const GrayImage& frame() {
  static const GrayImage img = [] {
    const char* env = std::getenv("ALE_DATA_DIR");
    const std::string root = env != nullptr ? env : ALE_BENCH_DATA_DIR;
    GrayImage g;
    const Status st = io::read_gray(root + "/euroc_v101_micro/mav0/cam0/data/1403715273262142976.png", g);
    if (!st.ok()) {
      std::fprintf(stderr, "ale_enhance_bench: %s\n", st.to_string().c_str());
      std::exit(1);
    }
    return g;
  }();
  return img;
}

// The frame cropped to width x 480 (a view into the 752-wide frame).
GrayView input(int width) {
  const GrayImage& f = frame();
  return {f.pixels.data(), width, 480, f.width};
}

void BM_ClaheOurs(benchmark::State& state, KernelPath path) {
  const int w = static_cast<int>(state.range(0));
  GrayImage out(w, 480);
  ClaheContext ctx;
  const ClaheParams params{8, 8, 2.0};
  if (!clahe(ctx, params, input(w), out.view(), path).ok()) state.SkipWithError("clahe failed");
  for (auto _ : state) {
    (void)ctx.apply(input(w), out.view(), path);
    benchmark::DoNotOptimize(out.pixels.data());
  }
  state.SetLabel(to_string(path == KernelPath::kAuto ? kernels().path : path));
}

void BM_ClaheOpenCv(benchmark::State& state) {
  cv::setNumThreads(1);
  const int w = static_cast<int>(state.range(0));
  const GrayView in = input(w);
  const cv::Mat src(in.height, in.width, CV_8UC1, const_cast<std::uint8_t*>(in.data), static_cast<std::size_t>(in.stride));
  cv::Mat dst;
  const cv::Ptr<cv::CLAHE> c = cv::createCLAHE(2.0, cv::Size(8, 8));
  c->apply(src, dst);
  for (auto _ : state) {
    c->apply(src, dst);
    benchmark::DoNotOptimize(dst.data);
  }
}

void BM_GammaLut(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0));
  GrayImage out(w, 480);
  FrameStats stats;
  compute_stats(input(w), stats);
  Lut lut{};
  for (auto _ : state) {
    gamma_lut(cdf_gamma(stats, GammaParams{}), lut);
    (void)apply_lut(input(w), out.view(), lut);
    benchmark::DoNotOptimize(out.pixels.data());
  }
}

void BM_Enhance(benchmark::State& state, BrightnessClass cls) {
  const int w = static_cast<int>(state.range(0));
  GrayImage out(w, 480);
  FrameEnhancer e;
  EnhanceReport r;
  (void)e.enhance_as(cls, input(w), out.view(), r);
  for (auto _ : state) {
    (void)e.enhance_as(cls, input(w), out.view(), r);
    benchmark::DoNotOptimize(out.pixels.data());
  }
  state.SetLabel(to_string(cls));
}

#define ALE_SIZES ->Arg(752)->Arg(640)->Unit(benchmark::kMicrosecond)
BENCHMARK_CAPTURE(BM_ClaheOurs, reference, KernelPath::kReference) ALE_SIZES;
BENCHMARK_CAPTURE(BM_ClaheOurs, best, KernelPath::kAuto) ALE_SIZES;
BENCHMARK(BM_ClaheOpenCv) ALE_SIZES;
BENCHMARK(BM_GammaLut) ALE_SIZES;
BENCHMARK_CAPTURE(BM_Enhance, extremely_dark, BrightnessClass::kExtremelyDark) ALE_SIZES;
BENCHMARK_CAPTURE(BM_Enhance, dark, BrightnessClass::kDark) ALE_SIZES;
BENCHMARK_CAPTURE(BM_Enhance, normal, BrightnessClass::kNormal) ALE_SIZES;
BENCHMARK_CAPTURE(BM_Enhance, bright, BrightnessClass::kBright) ALE_SIZES;

}  // namespace

BENCHMARK_MAIN();
