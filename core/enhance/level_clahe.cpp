#include "core/enhance/level_clahe.h"

#include <algorithm>
#include <cmath>

namespace ale::enhance {

LevelClaheSettings level_clahe_settings(const LevelClaheParams& p, double scale, int width, int height,
                                        double sigma, int median) {
  LevelClaheSettings s;
  s.sigma = sigma;
  s.median = median;
  s.tile_edge = std::max(static_cast<int>(p.tile_base + p.tile_scale * scale), p.tile_min);
  const auto tiles = [&](int extent) {
    return std::clamp(static_cast<int>(std::lround(static_cast<double>(extent) / s.tile_edge)), 1, 254);
  };
  s.clahe.tiles_x = tiles(width);
  s.clahe.tiles_y = tiles(height);
  const double contrast = sigma / static_cast<double>(std::max(median, 1));
  s.clahe.clip_limit = std::clamp(p.clip_base + p.clip_contrast * contrast, p.clip_min, p.clip_max);
  return s;
}

Status contrast_guided_clahe(ClaheContext& ctx, const LevelClaheParams& p, double scale, const FrameStats& stats,
                             GrayView src, MutableGrayView dst, LevelClaheSettings* used) {
  ALE_RETURN_IF_ERROR(check_view(src, "level clahe source"));
  const LevelClaheSettings s = level_clahe_settings(p, scale, src.width, src.height, stats.sigma, stats.median);
  if (used != nullptr) *used = s;
  return clahe(ctx, s.clahe, src, dst);
}

Status contrast_guided_clahe(ClaheContext& ctx, const LevelClaheParams& p, double scale, GrayView src,
                             MutableGrayView dst, LevelClaheSettings* used) {
  ALE_RETURN_IF_ERROR(check_view(src, "level clahe source"));
  FrameStats stats;
  compute_stats(src, stats);
  return contrast_guided_clahe(ctx, p, scale, stats, src, dst, used);
}

}  // namespace ale::enhance
