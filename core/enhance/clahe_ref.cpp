// The plan and the portable scalar CLAHE: this file is the specification the NEON kernel must
// reproduce bit for bit (see clahe.h for the arithmetic and how it relates to OpenCV's).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "core/enhance/clahe.h"
#include "core/enhance/kernels.h"

namespace ale::enhance {
namespace {

// Index of the source pixel that an extended coordinate p reads under reflection without
// repeating the edge (…c b | a b c … d e | d c …), for any p, even far outside [0, len).
int reflect101(int p, int len) {
  if (len == 1) return 0;
  while (p < 0 || p >= len) {
    if (p < 0) p = -p;
    if (p >= len) p = 2 * (len - 1) - p;
  }
  return p;
}

int floor_div(int a, int b) {  // b > 0
  int q = a / b;
  if ((a % b != 0) && (a < 0)) --q;
  return q;
}

// Pixel i of n sits at i/tile - 0.5 in tile-centre coordinates (OpenCV's convention): 2i - tile =
// 2 tile * t + frac with frac in [0, 2 tile). Calls f(i, t, frac) for every i, stepping frac by 2
// (no division per pixel).
template <typename F>
void walk_tile_centres(int n, int tile, F f) {
  int t = floor_div(-tile, 2 * tile);
  int frac = -tile - t * 2 * tile;
  for (int i = 0; i < n; ++i, frac += 2) {
    if (frac >= 2 * tile) {
      frac -= 2 * tile;
      ++t;
    }
    f(i, t, frac);
  }
}

int floor_log2(int v) {
  int r = 0;
  while (v > 1) {
    v >>= 1;
    ++r;
  }
  return r;
}

}  // namespace

BlendScale blend_scale(int tile_width) {
  BlendScale b;
  const int tw = tile_width;
  b.exact_div = 2 * tw <= 255 ? 1 : (tw % 2 == 0 && tw <= 254 ? 2 : 0);
  b.dx = b.exact_div != 0 ? 2 * tw / b.exact_div : 255;
  b.shift = 15 + floor_log2(b.dx);
  b.w_total = static_cast<int>(((1LL << b.shift) + b.dx / 2) / b.dx);
  return b;
}

Status ClaheContext::configure(int width, int height, const ClaheParams& params) {
  if (configured_ && width == width_ && height == height_ && params.tiles_x == params_.tiles_x &&
      params.tiles_y == params_.tiles_y) {
    if (params.clip_limit != params_.clip_limit) return set_clip_limit(params.clip_limit);
    return {};
  }
  if (width <= 0 || height <= 0)
    return invalid_argument("clahe: image size " + std::to_string(width) + "x" + std::to_string(height) +
                            " is empty");
  if (params.tiles_x < 1 || params.tiles_x > 254 || params.tiles_y < 1 || params.tiles_y > 254)
    return invalid_argument("clahe: tile grid " + std::to_string(params.tiles_x) + "x" +
                            std::to_string(params.tiles_y) + " outside 1..254");
  if (!std::isfinite(params.clip_limit))
    return invalid_argument("clahe: clip_limit is not a finite number");

  const bool divides = width % params.tiles_x == 0 && height % params.tiles_y == 0;
  const int tw = width / params.tiles_x + (divides ? 0 : 1);
  const int th = height / params.tiles_y + (divides ? 0 : 1);
  const long long area = static_cast<long long>(tw) * th;
  // 255 * area + area/2 must stay below 2^32 for the LUT scaling.
  if (area >= (1LL << 24))
    return invalid_argument("clahe: tile of " + std::to_string(tw) + "x" + std::to_string(th) +
                            " pixels is too large (at most 2^24 pixels per tile)");

  configured_ = false;
  params_ = params;
  width_ = width;
  height_ = height;
  tile_w_ = tw;
  tile_h_ = th;
  area_ = static_cast<int>(area);
  set_clip(params.clip_limit);
  area_recip_ = 0xFFFFFFFFu / static_cast<std::uint32_t>(area_);  // fits 32 bits even for area 1

  const int tx_n = params.tiles_x;
  const int ty_n = params.tiles_y;

  tile_rows_.resize(static_cast<std::size_t>(ty_n) * static_cast<std::size_t>(th));
  for (int i = 0; i < ty_n * th; ++i) tile_rows_[static_cast<std::size_t>(i)] = reflect101(i, height);

  col_end_.resize(static_cast<std::size_t>(tx_n));
  col_extras_.clear();
  col_extra_offset_.clear();
  for (int t = 0; t < tx_n; ++t) {
    const int x0 = t * tw;
    const int x1 = x0 + tw;
    col_end_[static_cast<std::size_t>(t)] = std::min(x1, width);
    for (int x = std::max(x0, width); x < x1; ++x) {
      col_extras_.push_back(reflect101(x, width));
      col_extra_offset_.push_back(t * 256);
    }
  }

  const BlendScale scale = blend_scale(tw);
  const int exact_div = scale.exact_div;
  const int dx = scale.dx;
  shift_ = scale.shift;
  w_total_ = scale.w_total;

  col_pair_.resize(static_cast<std::size_t>(width));
  w_lr_.resize(2 * static_cast<std::size_t>(width));
  walk_tile_centres(width, tw, [&](int x, int t1, int frac) {
    const auto xi = static_cast<std::size_t>(x);
    col_pair_[xi] = static_cast<std::uint16_t>((t1 + 1) * 256);
    const int wr = exact_div == 1 ? frac : exact_div == 2 ? frac / 2 : (frac * 255 + tw) / (2 * tw);
    w_lr_[2 * xi] = static_cast<std::uint8_t>(dx - wr);
    w_lr_[2 * xi + 1] = static_cast<std::uint8_t>(wr);
  });

  col_runs_.clear();
  for (int x = 0; x < width; ++x) {
    const std::uint16_t off = col_pair_[static_cast<std::size_t>(x)];
    if (col_runs_.empty() || col_runs_.back().offset != off)
      col_runs_.push_back({x, x + 1, 0, off});
    else
      col_runs_.back().x_end = x + 1;
  }
  // The NEON gather's last step of a run may overrun into the next run's columns (which that
  // run rewrites), but not past the row.
  for (ColumnRun& run : col_runs_) {
    const int len = run.x_end - run.x_begin;
    run.vec_end = run.x_begin + (run.x_begin + ((len + 7) & ~7) <= width ? (len + 7) & ~7 : len & ~7);
  }

  row_plan_.resize(static_cast<std::size_t>(height));
  // Rows likewise; frac * w_total (w_total <= 2^15) fits 32 bits for tiles below 2^15 rows, so
  // the 64-bit division (a library call on ARM) is left to taller tiles.
  walk_tile_centres(height, th, [&](int y, int band, int row_frac) {
    const auto wb = th < (1 << 15) ? static_cast<int>((static_cast<std::uint32_t>(row_frac) *
                                                            static_cast<std::uint32_t>(w_total_) +
                                                        static_cast<std::uint32_t>(th)) /
                                                       (2u * static_cast<std::uint32_t>(th)))
                                   : static_cast<int>((static_cast<long long>(row_frac) * w_total_ + th) / (2LL * th));
    row_plan_[static_cast<std::size_t>(y)] = {static_cast<std::uint16_t>(band + 1),
                                             static_cast<std::uint16_t>(w_total_ - wb),
                                             static_cast<std::uint16_t>(wb)};
  });

  tile_hist_.resize(static_cast<std::size_t>(tx_n) * static_cast<std::size_t>(ty_n) * 256u);
  counted_ = nullptr;
  luts_.resize(static_cast<std::size_t>(tx_n) * static_cast<std::size_t>(ty_n) * 256u);
  quads_.resize((static_cast<std::size_t>(tx_n) + 1) * 256u);
  row_quads_.resize(static_cast<std::size_t>(width));
  quad_band_ = -1;
  configured_ = true;
  return {};
}

void ClaheContext::set_clip(double clip_limit) {
  params_.clip_limit = clip_limit;
  clip_ = 0;
  if (clip_limit > 0.0) {
    const double limit = clip_limit * static_cast<double>(area_) / 256.0;
    clip_ = limit >= static_cast<double>(area_) ? area_ : std::max(static_cast<int>(limit), 1);
  }
}

Status ClaheContext::set_clip_limit(double clip_limit) {
  if (!configured_) return invalid_argument("clahe: set_clip_limit() before configure()");
  if (!std::isfinite(clip_limit)) return invalid_argument("clahe: clip_limit is not a finite number");
  set_clip(clip_limit);
  return {};
}

namespace internal {

namespace {

// row[x0..x1) into two histograms, alternate pixels of each group of 8 (the rest into h0).
// A lambda, so that the walks in clahe.h inline it.
const auto count_row = [](const std::uint8_t* row, int x0, int x1, std::uint32_t* h0, std::uint32_t* h1) {
  const std::uint8_t* p = row + x0;
  const std::uint8_t* const end = row + x1;
  for (const std::uint8_t* const end8 = p + ((x1 - x0) & ~7); p != end8; p += 8) {
    ++h0[p[0]];
    ++h1[p[1]];
    ++h0[p[2]];
    ++h1[p[3]];
    ++h0[p[4]];
    ++h1[p[5]];
    ++h0[p[6]];
    ++h1[p[7]];
  }
  for (; p != end; ++p) ++h0[*p];
};

}  // namespace

void histogram_ref(GrayView image, std::uint32_t* h0, std::uint32_t* h1) { histogram_walk(image, h0, h1, count_row); }

void tile_histograms_ref(GrayView src, const int* rows, int n_rows, const int* col_end, int n_tiles,
                         std::uint32_t* hists) {
  tile_histograms_walk(src, rows, n_rows, col_end, n_tiles, hists, count_row);
}

int min_gap_ref(const std::uint8_t* lut, int lo, int hi, int first, int threshold) {
  // Two pointers over the monotonic table: for each v the first u with lut[u] - lut[v] > threshold.
  // (No gap below `first` can qualify, so it needs no special case here.)
  (void)first;
  int best = 256;
  int u = lo;
  for (int v = lo; v <= hi; ++v) {
    if (u < v) u = v;
    while (u <= hi && lut[u] - lut[v] <= threshold) ++u;
    if (u > hi) break;  // later v only have smaller rises left
    best = std::min(best, u - v);
  }
  return best;
}

}  // namespace internal

// Every tile's histogram of the grid laid over the image extended by reflection: each band of
// tile rows by the histogram kernel, then the reflected columns.
void ClaheContext::count_tiles(GrayView src, TileHistograms histograms) {
  std::fill(tile_hist_.begin(), tile_hist_.end(), 0u);
  const int tx_n = params_.tiles_x;
  const int* const extras = col_extras_.data();
  const int* const extra_offset = col_extra_offset_.data();
  const int n_extras = static_cast<int>(col_extras_.size());
  for (int ty = 0; ty < params_.tiles_y; ++ty) {
    const int* rows = tile_rows_.data() + static_cast<std::size_t>(ty) * static_cast<std::size_t>(tile_h_);
    std::uint32_t* tile_row = tile_hist_.data() + static_cast<std::size_t>(ty) * static_cast<std::size_t>(tx_n) * 256u;
    histograms(src, rows, tile_h_, col_end_.data(), tx_n, tile_row);
    if (n_extras == 0) continue;
    for (int r = 0; r < tile_h_; ++r) {
      const std::uint8_t* row = src.row(rows[r]);
      for (int e = 0; e < n_extras; ++e) ++tile_row[extra_offset[e] + row[extras[e]]];
    }
  }
}

Status ClaheContext::count(GrayView src) {
  if (!configured_) return invalid_argument("clahe: count() before configure()");
  ALE_RETURN_IF_ERROR(check_view(src, "clahe source"));
  if (src.width != width_ || src.height != height_)
    return invalid_argument("clahe: configured for " + std::to_string(width_) + "x" + std::to_string(height_) +
                            ", got " + std::to_string(src.width) + "x" + std::to_string(src.height));
  count_tiles(src, kernels().tile_histograms);
  counted_ = src.data;
  counted_stride_ = src.stride;
  return {};
}

Status ClaheContext::remap_counts(GrayView src, const std::array<std::uint8_t, 256>& lut) {
  if (counted_ == nullptr || counted_ != src.data || counted_stride_ != src.stride)
    return invalid_argument("clahe: remap_counts() without count() of the same source");
  const std::size_t tiles = static_cast<std::size_t>(params_.tiles_x) * static_cast<std::size_t>(params_.tiles_y);
  std::array<std::uint32_t, 256> mapped;
  for (std::size_t t = 0; t < tiles; ++t) {
    std::uint32_t* const h = tile_hist_.data() + t * 256u;
    mapped.fill(0);
    for (std::size_t v = 0; v < 256; ++v) mapped[lut[v]] += h[v];
    std::copy(mapped.begin(), mapped.end(), h);
  }
  return {};
}

void ClaheContext::image_histogram(GrayView src, std::array<std::uint32_t, 256>& out) const {
  out.fill(0);
  const std::size_t tiles = static_cast<std::size_t>(params_.tiles_x) * static_cast<std::size_t>(params_.tiles_y);
  for (std::size_t t = 0; t < tiles; ++t) {
    const std::uint32_t* h = tile_hist_.data() + t * 256u;
    for (std::size_t v = 0; v < 256; ++v) out[v] += h[v];
  }
  // The grid also counted the reflected columns of every row and whole reflected rows.
  const int counted_rows = params_.tiles_y * tile_h_;
  for (int r = 0; r < counted_rows; ++r) {
    const std::uint8_t* row = src.row(tile_rows_[static_cast<std::size_t>(r)]);
    if (r >= height_)
      for (int x = 0; x < width_; ++x) --out[row[x]];
    for (const int x : col_extras_) --out[row[x]];
  }
}

void ClaheContext::build_tile_luts(GrayView src) {
  const int tx_n = params_.tiles_x;
  const auto clip = static_cast<std::uint32_t>(clip_);
  const auto area = static_cast<std::uint32_t>(area_);
  const std::uint32_t recip = area_recip_;
  if (counted_ != src.data || counted_stride_ != src.stride) count_tiles(src, &internal::tile_histograms_ref);
  counted_ = nullptr;  // the tables below clip the histograms in place
  for (int ty = 0; ty < params_.tiles_y; ++ty) {
    for (int tx = 0; tx < tx_n; ++tx) {
      std::uint32_t* h = tile_hist_.data() + (static_cast<std::size_t>(ty) * static_cast<std::size_t>(tx_n) +
                                              static_cast<std::size_t>(tx)) * 256u;
      if (clip > 0) {
        std::uint32_t clipped = 0;
        for (int i = 0; i < 256; ++i) {
          if (h[i] > clip) {
            clipped += h[i] - clip;
            h[i] = clip;
          }
        }
        const std::uint32_t batch = clipped / 256u;
        std::uint32_t residual = clipped % 256u;
        for (int i = 0; i < 256; ++i) h[i] += batch;
        if (residual != 0) {
          const std::uint32_t step = std::max(256u / residual, 1u);
          for (std::uint32_t i = 0; i < 256u && residual > 0; i += step, --residual) ++h[i];
        }
      }
      // lut[i] = round_half_up(255 * cdf(i) / area); the division is a 32x32->64 multiply by
      // floor((2^32-1)/area), which is low by at most one, and one correction. area < 2^24 keeps
      // n below 2^32.
      std::uint8_t* lut = luts_.data() + (static_cast<std::size_t>(ty) * static_cast<std::size_t>(tx_n) +
                                          static_cast<std::size_t>(tx)) * 256u;
      std::uint32_t cum = 0;
      for (int i = 0; i < 256; ++i) {
        cum += h[i];
        const std::uint32_t n = cum * 255u + area / 2u;
        auto q = static_cast<std::uint32_t>((std::uint64_t{n} * recip) >> 32);
        if (n - q * area >= area) ++q;
        lut[i] = static_cast<std::uint8_t>(q > 255u ? 255u : q);
      }
    }
  }
}

void ClaheContext::fill_band_quads_ref(int band) {
  const int tx_n = params_.tiles_x;
  const int ty_n = params_.tiles_y;
  const std::size_t lut_row = static_cast<std::size_t>(tx_n) * 256u;
  const std::uint8_t* top = luts_.data() + static_cast<std::size_t>(std::max(band - 1, 0)) * lut_row;
  const std::uint8_t* bot = luts_.data() + static_cast<std::size_t>(std::min(band, ty_n - 1)) * lut_row;
  std::uint32_t* out = quads_.data();
  for (int k = 0; k <= tx_n; ++k) {
    const std::size_t left = static_cast<std::size_t>(std::max(k - 1, 0)) * 256u;
    const std::size_t right = static_cast<std::size_t>(std::min(k, tx_n - 1)) * 256u;
    for (std::size_t v = 0; v < 256; ++v) {
      *out++ = std::uint32_t{top[left + v]} | std::uint32_t{top[right + v]} << 8 |
               std::uint32_t{bot[left + v]} << 16 | std::uint32_t{bot[right + v]} << 24;
    }
  }
  quad_band_ = band;
}

// Needs the band table of row y (fill_band_quads*). Per pixel: the four LUT values of the
// surrounding tiles, a horizontal blend per tile row in 16 bits, a vertical blend in 32 bits and
// one rounding shift.
void ClaheContext::interpolate_row_ref(const std::uint8_t* src, std::uint8_t* dst, int y, int x_begin,
                                       int x_end) {
  const RowPlan rp = row_plan_[static_cast<std::size_t>(y)];
  const std::uint32_t wt = rp.w_top;
  const std::uint32_t wb = rp.w_bottom;
  const std::uint32_t round = 1u << (shift_ - 1);
  const int shift = shift_;
  const std::uint32_t* quads = quads_.data();
  const std::uint16_t* pair = col_pair_.data();
  // Gather first, blend in a second loop without table look-ups, which compilers vectorise.
  std::uint32_t* gathered = row_quads_.data();
  for (int x = x_begin; x < x_end; ++x) gathered[x] = quads[pair[x] + src[x]];
  const std::uint8_t* w_lr = w_lr_.data();
  for (int x = x_begin; x < x_end; ++x) {
    const std::uint32_t q = gathered[x];
    const auto wl = static_cast<std::uint16_t>(w_lr[2 * x]);
    const auto wr = static_cast<std::uint16_t>(w_lr[2 * x + 1]);
    const auto h_top = static_cast<std::uint16_t>((q & 0xFFu) * wl + ((q >> 8) & 0xFFu) * wr);
    const auto h_bot = static_cast<std::uint16_t>(((q >> 16) & 0xFFu) * wl + (q >> 24) * wr);
    const std::uint32_t out = (std::uint32_t{h_top} * wt + std::uint32_t{h_bot} * wb + round) >> shift;
    dst[x] = static_cast<std::uint8_t>(out > 255u ? 255u : out);
  }
}

void ClaheContext::apply_ref(GrayView src, MutableGrayView dst) {
  build_tile_luts(src);
  quad_band_ = -1;
  for (int y = 0; y < height_; ++y) {
    const int band = row_plan_[static_cast<std::size_t>(y)].band;
    if (band != quad_band_) fill_band_quads_ref(band);
    interpolate_row_ref(src.row(y), dst.row(y), y, 0, width_);
  }
}

}  // namespace ale::enhance
