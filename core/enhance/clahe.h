// Contrast-limited adaptive histogram equalisation in fixed point (spec section 3).
//
// Two interchangeable kernels share one plan: a portable scalar reference (clahe_ref.cpp, the
// specification) and an ARM NEON path (clahe_neon.cpp) that is bit-exact with it. apply()
// dispatches to NEON when the build has it, unless ALE_FORCE_REF=1 is set in the environment.
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

using ClahePath = KernelPath;

// True when this build contains the NEON kernel.
bool clahe_neon_compiled();
// The path kAuto resolves to: kNeon when compiled in and ALE_FORCE_REF is not "1".
ClahePath clahe_auto_path();

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

  // dst may be src itself (same data and stride) but must not overlap it otherwise.
  Status apply(GrayView src, MutableGrayView dst, ClahePath path = ClahePath::kAuto);

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
  void build_tile_luts(GrayView src);
  void build_tile_luts_neon(GrayView src);
  void interpolate_row_ref(const std::uint8_t* src, std::uint8_t* dst, int y, int x_begin, int x_end);
  void apply_ref(GrayView src, MutableGrayView dst);
  void apply_neon(GrayView src, MutableGrayView dst);

 private:
  void count_tiles(GrayView src);
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

// Counts row[x0..x1) into two histograms (alternate pixels; pass the same table twice for one).
// Per pixel a byte load and the counter's load, add and store: on 32-bit ARM in inline assembly,
// 8 pixels per loop test (4.25 instructions a pixel), because GCC 12 keeps eight extracted
// indices live at once and spills around every call's loop (about 25 instructions per call on top
// of 4.6 a pixel, and the tile histograms call this once per tile and row). Shared by the tile
// histograms here and the feature cells' single-tile CLAHE.
inline void count_row(const std::uint8_t* row, int x0, int x1, std::uint32_t* h0, std::uint32_t* h1) {
  const std::uint8_t* p = row + x0;
  const std::uint8_t* const end = row + x1;
  const std::uint8_t* const end8 = p + ((x1 - x0) & ~7);
#if defined(__arm__)
  if (p != end8) {
    std::uint32_t v, c;
#define ALE_COUNT(h)                                                                            \
  "ldrb %[v], [%[p]], #1\n\tldr %[c], [%[" h "], %[v], lsl #2]\n\tadd %[c], %[c], #1\n\t" \
  "str %[c], [%[" h "], %[v], lsl #2]\n\t"
    asm volatile("1:\n\t" ALE_COUNT("h0") ALE_COUNT("h1") ALE_COUNT("h0") ALE_COUNT("h1") ALE_COUNT("h0")
                     ALE_COUNT("h1") ALE_COUNT("h0") ALE_COUNT("h1") "cmp %[p], %[end8]\n\tbne 1b\n\t"
                 : [p] "+r"(p), [v] "=&r"(v), [c] "=&r"(c)
                 : [end8] "r"(end8), [h0] "r"(h0), [h1] "r"(h1)
                 : "cc", "memory");
#undef ALE_COUNT
  }
#else
  for (; p != end8; p += 8) {
    ++h0[p[0]];
    ++h1[p[1]];
    ++h0[p[2]];
    ++h1[p[3]];
    ++h0[p[4]];
    ++h1[p[5]];
    ++h0[p[6]];
    ++h1[p[7]];
  }
#endif
  for (; p != end; ++p) ++h0[*p];
}

// One call with a caller-owned context: configure (no-op when unchanged) then apply.
Status clahe(ClaheContext& ctx, const ClaheParams& params, GrayView src, MutableGrayView dst,
             ClahePath path = ClahePath::kAuto);

}  // namespace ale::enhance
