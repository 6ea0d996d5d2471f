// Contrast-limited adaptive histogram equalisation in fixed point (spec section 3).
//
// Two interchangeable kernels share one plan: a portable scalar reference (clahe_ref.cpp, the
// specification) and an ARM NEON path (clahe_neon.cpp) that is bit-exact with it, chosen through
// the enhance kernels' table (kernels.h). The same two files hold the histogram kernels every
// CLAHE here counts with (the tile grid, the frame statistics, the feature cells' single-tile
// CLAHE) and the single-tile table's gap search (core/features/cell_clahe.h).
//
// Geometry and clipping follow OpenCV's cv::createCLAHE so that our output agrees with it within
// one grey level: tiles of (W/tiles_x) x (H/tiles_y) when both divide, otherwise
// (W/tiles_x + 1) x (H/tiles_y + 1) tiles laid over the image extended to the right and bottom by
// reflection (BORDER_REFLECT_101); the clip limit is int(clip_limit * tile_area / 256), at least 1;
// the clipped excess is spread evenly with the residual on every (256/residual)-th bin.
// What we do differently: integer LUTs rounded half up, interpolation weights that are exact
// integer fractions of the tile size (tiles up to 127 pixels, even ones up to 254) or fractions
// of 255 otherwise, and a
// vertical blend in Q(15+log2 Dx) with one explicit rounding; no allocation after configure().
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/base/image.h"
#include "core/base/kernel_path.h"
#include "core/base/status.h"

namespace ale::enhance {

struct ClaheParams {
  int tiles_x = 8;          // grid columns, 1..254
  int tiles_y = 8;          // grid rows, 1..254
  double clip_limit = 2.0;  // OpenCV units: multiple of the mean bin height; <= 0 disables clipping
};

namespace internal {
// Counts image into two histograms (alternate pixels of a row; pass the same table twice for one).
void histogram_ref(GrayView image, std::uint32_t* h0, std::uint32_t* h1);
void histogram_neon(GrayView image, std::uint32_t* h0, std::uint32_t* h1);
// Counts the rows `rows[0..n_rows)` of `src` into `n_tiles` histograms of 256 bins at `hists`,
// tile t taking the columns [col_end[t - 1], col_end[t]) (from 0 for t = 0).
void tile_histograms_ref(GrayView src, const int* rows, int n_rows, const int* col_end, int n_tiles,
                         std::uint32_t* hists);
void tile_histograms_neon(GrayView src, const int* rows, int n_rows, const int* col_end, int n_tiles,
                          std::uint32_t* hists);
// The smallest d in [first, hi - lo] with lut[v + d] - lut[v] > threshold for some v in [lo, hi - d]
// (256 when there is none) of a monotonic table; the NEON kernel reads lut up to hi + 15, which
// must repeat lut[hi]. `first` is a gap below which no rise can exceed threshold.
int min_gap_ref(const std::uint8_t* lut, int lo, int hi, int first, int threshold);
int min_gap_neon(const std::uint8_t* lut, int lo, int hi, int first, int threshold);

// The two histogram kernels' walks over the rows, given a kernel's row counter
// count_row(row, x0, x1, h0, h1) (inlined into each kernel).
template <typename CountRow>
inline void histogram_walk(GrayView image, std::uint32_t* h0, std::uint32_t* h1, CountRow count_row) {
  for (int y = 0; y < image.height; ++y) count_row(image.row(y), 0, image.width > 0 ? image.width : 0, h0, h1);
}
template <typename CountRow>
inline void tile_histograms_walk(GrayView src, const int* rows, int n_rows, const int* col_end, int n_tiles,
                                 std::uint32_t* hists, CountRow count_row) {
  for (int r = 0; r < n_rows; ++r) {
    const std::uint8_t* row = src.row(rows[r]);
    int x0 = 0;
    std::uint32_t* h = hists;
    for (int t = 0; t < n_tiles; ++t, h += 256) {
      count_row(row, x0, col_end[t], h, h);
      x0 = col_end[t];
    }
  }
}
}  // namespace internal

// The fixed-point scale of the bilinear blend for tiles `tile_width` pixels wide. Horizontal
// weights are exact fractions of dx = 2*tw while they fit in a byte; for even tiles every fraction
// numerator is even, so dx = tw is exact up to 254 pixels; else fractions of 255 (exact_div 0).
// Vertical weights sum to w_total = round(2^shift / dx), so a blend of four LUT values v is
// (v * dx * w_total + 2^(shift-1)) >> shift when all four are equal.
struct BlendScale {
  int exact_div = 1;
  int dx = 0;
  int shift = 0;
  int w_total = 0;
};
BlendScale blend_scale(int tile_width);

// The plan (tile geometry, interpolation weights) and every buffer a frame needs. configure() is
// cheap when nothing changed and reuses capacity when the size shrinks, so one context can serve
// many pyramid levels or cells without allocating after the largest has been seen.
class ClaheContext {
 public:
  ClaheContext() = default;

  Status configure(int width, int height, const ClaheParams& params);

  // dst may be src itself (same data and stride) but must not overlap it otherwise. A `path` this
  // build lacks (kernel_path_compiled()) is kUnsupported.
  Status apply(GrayView src, MutableGrayView dst, KernelPath path = KernelPath::kAuto);

  // Two steps for callers that pick the clip limit from the image (the contrast-guided CLAHE):
  // count() builds the tile histograms of src, image_histogram() gives src's own histogram from
  // them (what the grid counted beyond the image taken out), set_clip_limit() changes the clip
  // only, and the next apply() on the same src (same data and stride) reuses the counts.
  Status count(GrayView src);
  void image_histogram(GrayView src, std::array<std::uint32_t, 256>& out) const;
  Status set_clip_limit(double clip_limit);
  // After count(src), src's pixels were replaced in place by lut[pixel]: the counts are carried
  // through the LUT (a histogram remaps, 256 bins a tile) instead of counting the pixels again.
  Status remap_counts(GrayView src, const std::array<std::uint8_t, 256>& lut);

  int width() const { return width_; }
  int height() const { return height_; }
  int tile_width() const { return tile_w_; }
  int tile_height() const { return tile_h_; }
  int clip_count() const { return clip_; }  // per-bin limit in pixels, 0 = none
  const ClaheParams& params() const { return params_; }
  // The 256-entry LUT of tile (tx, ty) computed by the last apply().
  const std::uint8_t* tile_lut(int tx, int ty) const {
    return luts_.data() + (static_cast<std::size_t>(ty) * static_cast<std::size_t>(params_.tiles_x) +
                           static_cast<std::size_t>(tx)) * 256u;
  }

  // Internals shared by the two kernels (clahe_ref.cpp, clahe_neon.cpp); not for other callers.
  struct RowPlan {
    std::uint16_t band;     // row-band index b: tile rows max(b-1,0) and min(b,tiles_y-1)
    std::uint16_t w_top;    // vertical weights, w_top + w_bottom = w_total_
    std::uint16_t w_bottom;
  };
  using TileHistograms = decltype(&internal::tile_histograms_ref);
  void count_tiles(GrayView src, TileHistograms histograms);
  void build_tile_luts(GrayView src);
  void build_tile_luts_neon(GrayView src);
  void interpolate_row_ref(const std::uint8_t* src, std::uint8_t* dst, int y, int x_begin, int x_end);
  void apply_ref(GrayView src, MutableGrayView dst);
  void apply_neon(GrayView src, MutableGrayView dst);

 private:
  void set_clip(double clip_limit);
  // The band table: entry (k, v) packs lut[top][left][v], lut[top][right][v], lut[bot][left][v],
  // lut[bot][right][v] (bytes 0..3) for tile-column pair k of row band `band`.
  void fill_band_quads_ref(int band);
  void fill_band_quads(int band);

  ClaheParams params_;
  bool configured_ = false;
  int width_ = 0;
  int height_ = 0;
  int tile_w_ = 0;
  int tile_h_ = 0;
  int area_ = 0;
  int clip_ = 0;
  std::uint32_t area_recip_ = 0;  // floor((2^32-1) / area_): LUT scaling without a division per bin
  int shift_ = 0;                 // K: the vertical blend is (h_top*w_top + h_bot*w_bottom) >> K
  int w_total_ = 0;

  // Histogram sources: per tile row, the image rows (reflected at the bottom); per tile column
  // the in-image span and reflected extra columns.
  std::vector<int> tile_rows_;         // tiles_y * tile_h_
  std::vector<int> col_end_;     // tiles_x: tile t spans [col_end_[t-1], col_end_[t]) in the image
  std::vector<int> col_extras_;  // reflected columns beyond the image, and per column
  std::vector<int> col_extra_offset_;  // their tile's offset in a tile row of tile_hist_ (256 * tile column)

  // Interpolation: per column the pair of tile columns k (left max(k-1,0), right min(k,tiles_x-1))
  // and the horizontal weights (their sum is Dx).
  std::vector<std::uint16_t> col_pair_;   // pair index k * 256: the pixel's offset in the band table
  struct ColumnRun {
    int x_begin, x_end;    // columns sharing one tile pair (NEON gather)
    int vec_end;           // x_begin + 8 * (NEON gather steps): may pass x_end, never width_
    std::uint16_t offset;  // their col_pair_ value
  };
  std::vector<ColumnRun> col_runs_;
  std::vector<std::uint8_t> w_lr_;  // per column the left and right weights, interleaved (one vld2)
  std::vector<RowPlan> row_plan_;

  std::vector<std::uint32_t> tile_hist_;  // tiles_y * tiles_x * 256
  const std::uint8_t* counted_ = nullptr;  // the source tile_hist_ holds the counts of, if any
  int counted_stride_ = 0;
  std::vector<std::uint8_t> luts_;   // tiles_y * tiles_x * 256
  std::vector<std::uint32_t> quads_;  // (tiles_x + 1) * 256: four LUT values per entry, one band
  int quad_band_ = -1;
  std::vector<std::uint32_t> row_quads_;  // one row's gathered quads
};

// One call with a caller-owned context: configure (no-op when unchanged) then apply.
Status clahe(ClaheContext& ctx, const ClaheParams& params, GrayView src, MutableGrayView dst,
             KernelPath path = KernelPath::kAuto);

}  // namespace ale::enhance
