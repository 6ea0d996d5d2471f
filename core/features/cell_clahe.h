// The per-cell CLAHE of the ALE ladder (a cell plus the FAST margin, contrast-guided, spec
// section 5) without the machinery of a general CLAHE: the tile edge at any pyramid scale exceeds
// most cells, so their grid is a single tile, and a single-tile CLAHE is one histogram, one clipped
// CDF and one look-up table; the interpolation of core/enhance reduces to a fixed rescaling of that
// table. The result is bit-exact with enhance::contrast_guided_clahe() (tested); grids of more than
// one tile go to it.
//
// The table also bounds what FAST can find on the enhanced cell without enhancing it: the table is
// monotonic, so two pixels whose enhanced values differ by more than t differ in the original by
// at least min_raw_gap(t). A corner at t on the enhanced cell is therefore a corner at
// min_raw_gap(t) - 1 on the original, and a cell whose original has no such corner can be skipped
// (orb.cpp; exact, tested). quick_needed_score() gives a weaker bound of the same kind from the
// cell's minimum, mean and spread alone (no histogram), which settles most flat cells cheaper.
#pragma once

#include <array>
#include <cstdint>

#include "core/base/image.h"
#include "core/base/status.h"
#include "core/enhance/clahe.h"
#include "core/enhance/grading.h"
#include "core/enhance/params.h"

namespace ale::features {

class CellClahe {
 public:
  // dst = enhance::contrast_guided_clahe(p, scale, src) (dst must not overlap src).
  Status apply(const enhance::LevelClaheParams& p, double scale, GrayView src, MutableGrayView dst);
  // Whether the last apply() or plan() took the single-tile path.
  bool last_was_single_tile() const { return single_; }

  // The first half of apply(): measures src and, for a single-tile grid, builds its table (nothing
  // is written). After it, map() gives apply()'s output for a single tile; other grids need apply().
  Status plan(const enhance::LevelClaheParams& p, double scale, GrayView src);
  // The same, given src's moments (moments(src), which quick_needed_score() needs
  // as well): sigma is not taken again from the histogram and the range scan starts at the minimum.
  Status plan(const enhance::LevelClaheParams& p, double scale, GrayView src, const enhance::Moments& moments);
  // enhance::compute_moments(src), cheaper for a cell's size.
  static enhance::Moments moments(GrayView src);
  // dst = table(src), after plan() chose a single tile (dst must not overlap src).
  void map(GrayView src, MutableGrayView dst) const;
  // After plan() with a single tile: the smallest d such that two grey values of the planned cell
  // that are d apart can map more than `threshold` apart (256 when no two can).
  int min_raw_gap(int threshold) const;
  // The portable version of min_raw_gap() (tests compare the two).
  int min_raw_gap_ref(int threshold) const;
  // After plan() with a single tile: the FAST score at (x, y) of the enhanced src (what map() and
  // fast9_score() would give), from the pixel's circle alone; (x, y) keeps kFastRadius inside src.
  int mapped_score(GrayView src, int x, int y) const;
  // Without planning: a FAST score on src that every corner at `threshold` on the enhanced src
  // reaches (0 when the parameters allow no bound, e.g. no clipping or a multi-tile grid).
  static int quick_needed_score(const enhance::LevelClaheParams& p, double scale, GrayView src, int threshold);
  // The same from src's moments (moments() of a w x h src).
  static int quick_needed_score(const enhance::LevelClaheParams& p, double scale, int w, int h,
                                const enhance::Moments& moments, int threshold);
  // The same from the parameters alone (the clip limit at its largest, clip_max): no pixel read,
  // never above quick_needed_score().
  static int param_needed_score(const enhance::LevelClaheParams& p, double scale, int w, int h, int threshold);

 private:
  enhance::ClaheContext general_;
  void build_table(const enhance::LevelClaheParams& p, double scale, int w, int h, double sigma, std::uint32_t lo,
                   std::uint32_t hi);

  std::array<std::uint32_t, 256> hist_{};  // zero between calls
  static constexpr int kLutPad = 16;  // lut_[hi_] repeated past hi_ (min_raw_gap() reads whole vectors)
  std::array<std::uint8_t, 256 + kLutPad> lut_{};
  bool single_ = false;
  int lo_ = 0;  // grey range of the planned cell: the table is defined on [lo_, hi_]
  int hi_ = 255;
  std::uint32_t area_ = 1;     // of the planned cell
  std::uint32_t bin_max_ = 1;  // at most this many pixels in a bin of its clipped, spread histogram
};

}  // namespace ale::features
