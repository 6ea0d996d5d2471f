#include "core/enhance/grading.h"

#include <algorithm>
#include <cmath>

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
  out.pixels = n;
  out.mean = out.sigma = 0.0;
  out.median = 0;
  if (n == 0) return;
  const double dn = static_cast<double>(n);
  out.mean = static_cast<double>(sum) / dn;
  out.sigma = std::sqrt(std::max(0.0, static_cast<double>(sum_sq) / dn - out.mean * out.mean));
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
  // Four tables for neighbouring pixels: in dark or flat images neighbours share a bin, and
  // increments of one counter in a row wait for each other. Eight pixels per step, each table
  // through its own pointer: per pixel one byte load and the counter's load, add and store (ARM).
  std::uint32_t sub[4][256] = {};
  std::uint32_t* const h0 = sub[0];
  std::uint32_t* const h1 = sub[1];
  std::uint32_t* const h2 = sub[2];
  std::uint32_t* const h3 = sub[3];
  const std::size_t width = image.width > 0 ? static_cast<std::size_t>(image.width) : 0;
  for (int y = 0; y < image.height; ++y) {
    const std::uint8_t* p = image.row(y);
    const std::uint8_t* const end = p + width;
    for (const std::uint8_t* const end8 = p + (width & ~std::size_t{7}); p != end8; p += 8) {
      ++h0[p[0]];
      ++h1[p[1]];
      ++h2[p[2]];
      ++h3[p[3]];
      ++h0[p[4]];
      ++h1[p[5]];
      ++h2[p[6]];
      ++h3[p[7]];
    }
    for (; p != end; ++p) ++h0[*p];
  }
  for (std::size_t v = 0; v < 256; ++v) out.histogram[v] = h0[v] + h1[v] + h2[v] + h3[v];
  finish_stats(out);
}

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
