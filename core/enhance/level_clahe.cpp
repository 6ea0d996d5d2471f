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

Status count_level(ClaheContext& ctx, const LevelClaheParams& p, double scale, GrayView src, FrameStats& stats) {
  ALE_RETURN_IF_ERROR(check_view(src, "level clahe source"));
  // The grid does not depend on the statistics, so the tile histograms are counted once and give
  // the image's histogram (sigma, median) as well: one pass over the pixels instead of two.
  const LevelClaheSettings grid = level_clahe_settings(p, scale, src.width, src.height, 0.0, 1);
  ALE_RETURN_IF_ERROR(ctx.configure(src.width, src.height, grid.clahe));
  ALE_RETURN_IF_ERROR(ctx.count(src));
  ctx.image_histogram(src, stats.histogram);
  stats_from_histogram(stats);
  return {};
}

Status contrast_guided_clahe(ClaheContext& ctx, const LevelClaheParams& p, double scale, GrayView src,
                             MutableGrayView dst, LevelClaheSettings* used) {
  FrameStats stats;
  ALE_RETURN_IF_ERROR(count_level(ctx, p, scale, src, stats));
  const LevelClaheSettings s = level_clahe_settings(p, scale, src.width, src.height, stats.sigma, stats.median);
  if (used != nullptr) *used = s;
  ALE_RETURN_IF_ERROR(ctx.set_clip_limit(s.clahe.clip_limit));
  return ctx.apply(src, dst);
}

}  // namespace ale::enhance
