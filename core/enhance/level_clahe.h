// Contrast-guided CLAHE for one pyramid level or one feature cell (spec section 5): tile edge
// from the level's scale, clip limit from the image's contrast (sigma / median).
#pragma once

#include "core/enhance/clahe.h"
#include "core/enhance/grading.h"
#include "core/enhance/params.h"

namespace ale::enhance {

struct LevelClaheSettings {
  int tile_edge = 0;  // pixels, after clamping
  ClaheParams clahe;  // grid and clip limit actually used
  double sigma = 0.0;
  int median = 0;
};

// scale: 1 at level 0, 1/scale_factor^n at level n. Median 0 counts as 1.
LevelClaheSettings level_clahe_settings(const LevelClaheParams& p, double scale, int width, int height,
                                        double sigma, int median);

// Measures src, derives the settings and runs CLAHE into dst (which may be src). `ctx` is the
// caller's reusable context: after it has seen the largest size nothing is allocated.
Status contrast_guided_clahe(ClaheContext& ctx, const LevelClaheParams& p, double scale, GrayView src,
                             MutableGrayView dst, LevelClaheSettings* used = nullptr);

// The first half of the above for a caller that changes src between counting and CLAHE (e.g. a
// global LUT, followed by ctx.remap_counts()): configures ctx for src's level CLAHE grid, counts
// its tile histograms and gives src's statistics from them (the values compute_stats() gives),
// one pass over the pixels for both. A later contrast_guided_clahe() on the same pixels (same
// data and stride) with these statistics, or their remapped ones, reuses the counts.
Status count_level(ClaheContext& ctx, const LevelClaheParams& p, double scale, GrayView src, FrameStats& stats);

// The same with statistics the caller already has (e.g. from grading).
Status contrast_guided_clahe(ClaheContext& ctx, const LevelClaheParams& p, double scale, const FrameStats& stats,
                             GrayView src, MutableGrayView dst, LevelClaheSettings* used = nullptr);

}  // namespace ale::enhance
