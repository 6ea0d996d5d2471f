#include "core/enhance/grading.h"

#include <algorithm>
#include <cmath>

#include "core/enhance/kernels.h"

namespace ale::enhance {

namespace {

// mean, sigma, median and pixel count from the histogram.
void finish_stats(FrameStats& out) {
  std::uint64_t n = 0;
  std::uint64_t sum = 0;
  std::uint64_t sum_sq = 0;
  for (std::size_t i = 0; i < 256; ++i) {
    const std::uint64_t v = i;
    const std::uint64_t c = out.histogram[i];
    n += c;
    sum += c * v;
    sum_sq += c * v * v;
  }
  const Moments m = moments_from_sums(n, sum, sum_sq);
  out.pixels = m.pixels;
  out.mean = m.mean;
  out.sigma = m.sigma;
  out.median = 0;
  if (n == 0) return;
  std::uint64_t cum = 0;
  for (int v = 0; v < 256; ++v) {
    cum += out.histogram[static_cast<std::size_t>(v)];
    if (2 * cum >= n) {
      out.median = v;
      break;
    }
  }
}

}  // namespace

void compute_stats(GrayView image, FrameStats& out) {
  // Two tables for neighbouring pixels: in dark or flat images neighbours share a bin, and
  // increments of one counter in a row wait for each other.
  std::uint32_t sub[2][256] = {};
  kernels().histogram(image, sub[0], sub[1]);
  for (std::size_t v = 0; v < 256; ++v) out.histogram[v] = sub[0][v] + sub[1][v];
  finish_stats(out);
}

void stats_from_histogram(FrameStats& out) { finish_stats(out); }

Moments compute_moments(GrayView image) { return kernels().moments(image); }

void remap_stats(const FrameStats& stats, const Lut& lut, FrameStats& out) {
  FrameStats mapped;
  for (std::size_t v = 0; v < 256; ++v) mapped.histogram[lut[v]] += stats.histogram[v];
  finish_stats(mapped);
  out = mapped;
}

namespace {

// Thresholds in dark-to-bright order; class i holds means below thresholds[i] (bright: the rest).
// `shift[i]` moves threshold i: +h when the held class is darker (harder to brighten), -h when
// it is brighter.
BrightnessClass classify_shifted(double mean, const GradingParams& p, const double shift[3]) {
  if (mean < p.t_very_low + shift[0]) return BrightnessClass::kExtremelyDark;
  if (mean < p.t_low + shift[1]) return BrightnessClass::kDark;
  if (mean <= p.t_high + shift[2]) return BrightnessClass::kNormal;
  return BrightnessClass::kBright;
}

}  // namespace

BrightnessClass classify(double mean, const GradingParams& p) {
  const double none[3] = {0.0, 0.0, 0.0};
  return classify_shifted(mean, p, none);
}

BrightnessClass BrightnessGrader::update(double mean) {
  if (!held_) {
    held_ = classify(mean, params_);
    return *held_;
  }
  const int held = static_cast<int>(*held_);  // enum order is dark to bright
  double shift[3];
  for (int i = 0; i < 3; ++i) shift[i] = held <= i ? params_.hysteresis : -params_.hysteresis;
  held_ = classify_shifted(mean, params_, shift);
  return *held_;
}

}  // namespace ale::enhance
