#include "core/enhance/gamma.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/enhance/kernels.h"

namespace ale::enhance {

double cdf_gamma(const FrameStats& stats, const GammaParams& p, double noise_sigma) {
  if (stats.pixels == 0) return 1.0;
  if (p.target_mean > 0.0) {
    const double m = stats.mean;
    if (m <= 0.0 || m >= p.target_mean) return 1.0;
    const auto gamma_to = [&](double target) {
      return std::clamp(std::log(target / 255.0) / std::log(m / 255.0), p.gamma_min, 1.0);
    };
    // The noise at the mean after the gamma: sigma times the curve's slope there, g * T / m
    // (255 (x/255)^g has slope g (x/255)^(g-1), and (m/255)^g = T/255); it grows with T.
    const auto lifted_noise = [&](double target) { return noise_sigma * gamma_to(target) * target / m; };
    if (p.noise_max <= 0.0 || noise_sigma <= 0.0 || lifted_noise(p.target_mean) <= p.noise_max)
      return gamma_to(p.target_mean);
    if (noise_sigma >= p.noise_max) return 1.0;
    double lo = m, hi = p.target_mean;  // lifted_noise(lo) = sigma < noise_max < lifted_noise(hi)
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (lo + hi);
      (lifted_noise(mid) <= p.noise_max ? lo : hi) = mid;
    }
    return gamma_to(lo);
  }
  const int t = std::clamp(p.cdf_point, 0, 255);
  std::uint64_t cum = 0;
  for (int v = 0; v <= t; ++v) cum += stats.histogram[static_cast<std::size_t>(v)];
  if (cum == 0) return 1.0;  // nothing at or below t: the frame needs no lift
  const double c = static_cast<double>(cum) / static_cast<double>(stats.pixels);
  return std::clamp(p.alpha / c, p.gamma_min, 1.0);
}

void gamma_lut(double gamma, Lut& lut) {
  for (int i = 0; i < 256; ++i)
    lut[static_cast<std::size_t>(i)] =
        static_cast<std::uint8_t>(std::lround(255.0 * std::pow(static_cast<double>(i) / 255.0, gamma)));
}

void equalisation_lut(const FrameStats& stats, Lut& lut) {
  int lo = 0;
  while (lo < 256 && stats.histogram[static_cast<std::size_t>(lo)] == 0) ++lo;
  const std::uint64_t base = lo < 256 ? stats.histogram[static_cast<std::size_t>(lo)] : 0;
  const std::uint64_t span = stats.pixels - base;
  if (lo == 256 || span == 0) {
    for (int i = 0; i < 256; ++i) lut[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(i);
    return;
  }
  std::uint64_t cum = 0;
  for (int i = 0; i < 256; ++i) {
    cum += stats.histogram[static_cast<std::size_t>(i)];
    const std::uint64_t above = cum > base ? cum - base : 0;
    lut[static_cast<std::size_t>(i)] = static_cast<std::uint8_t>((above * 255 + span / 2) / span);
  }
}

Status apply_lut(GrayView src, MutableGrayView dst, const Lut& lut) {
  ALE_RETURN_IF_ERROR(check_view(src, "lut source"));
  ALE_RETURN_IF_ERROR(check_view(dst, "lut destination"));
  if (src.width != dst.width || src.height != dst.height)
    return invalid_argument("apply_lut: source and destination sizes differ");
  kernels().apply_lut(src, dst, lut.data());
  return {};
}

}  // namespace ale::enhance
