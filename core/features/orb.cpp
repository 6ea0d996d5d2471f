#include "core/features/orb.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "core/enhance/gamma.h"
#include "core/enhance/level_clahe.h"
#include "core/features/blur.h"
#include "core/features/score_map.h"

namespace ale::features {

namespace {

Status range_error(const char* key, const std::string& why) {
  return invalid_argument(std::string("features.") + key + ": " + why);
}

}  // namespace

const char* to_string(ExtractorMode m) {
  switch (m) {
    case ExtractorMode::kAle: return "ale";
    case ExtractorMode::kBaseline: return "baseline";
    case ExtractorMode::kClahe: return "clahe";
  }
  return "?";
}

Result<ExtractorMode> parse_extractor_mode(const std::string& s) {
  if (s == "ale") return ExtractorMode::kAle;
  if (s == "baseline") return ExtractorMode::kBaseline;
  if (s == "clahe") return ExtractorMode::kClahe;
  return invalid_argument("features.mode: '" + s + "' is not one of ale, baseline, clahe");
}

Status validate(const ExtractorConfig& c) {
  if (c.num_features < 1 || c.num_features > 100000) return range_error("num_features", "must be 1..100000");
  if (c.num_levels < 1 || c.num_levels > kMaxLevels)
    return range_error("num_levels", "must be 1.." + std::to_string(kMaxLevels));
  if (!(c.scale_factor > 1.0 && c.scale_factor <= 4.0)) return range_error("scale_factor", "must be in (1, 4]");
  if (c.cell_size_px < 8 || c.cell_size_px > 1000) return range_error("cell_size_px", "must be 8..1000");
  if (c.t_low < 1 || c.t_low > 254) return range_error("t_low", "must be 1..254");
  if (c.t_high < c.t_low || c.t_high > 254) return range_error("t_high", "must be t_low..254");
  if (c.t_higher <= c.t_high || c.t_higher > 254) return range_error("t_higher", "must be t_high+1..254");
  if (c.clahe_everywhere.tiles_x < 1 || c.clahe_everywhere.tiles_y < 1 || c.clahe_everywhere.tiles_x > 254 ||
      c.clahe_everywhere.tiles_y > 254)
    return range_error("clahe_everywhere", "tiles must be 1..254");
  enhance::EnhanceParams cell = c.enhance;
  cell.clahe = c.cell_clahe;
  ALE_RETURN_IF_ERROR(enhance::validate(c.enhance));
  ALE_RETURN_IF_ERROR(enhance::validate(cell));
  return {};
}

Status OrbExtractor::configure(const ExtractorConfig& config) {
  ALE_RETURN_IF_ERROR(validate(config));
  config_ = config;
  ALE_RETURN_IF_ERROR(policy_.configure(config_.enhance, config_.level_enhance));
  const int levels = config_.num_levels;
  scales_[0] = 1.0;
  for (int l = 1; l < levels; ++l) scales_[static_cast<std::size_t>(l)] = scales_[static_cast<std::size_t>(l - 1)] * config_.scale_factor;
  // ORB-SLAM's split: a geometric series over the levels, the last level takes the rest.
  const double factor = 1.0 / config_.scale_factor;
  double per_level = config_.num_features * (1.0 - factor) / (1.0 - std::pow(factor, levels));
  int sum = 0;
  for (int l = 0; l < levels - 1; ++l) {
    budgets_[static_cast<std::size_t>(l)] = static_cast<int>(std::lround(per_level));
    sum += budgets_[static_cast<std::size_t>(l)];
    per_level *= factor;
  }
  budgets_[static_cast<std::size_t>(levels - 1)] = std::max(config_.num_features - sum, 0);
  pattern_ = make_brief_pattern();
  width_ = height_ = 0;  // re-plan the buffers on the next frame
  configured_ = true;
  return {};
}

Status OrbExtractor::allocate(int width, int height) {
  const int levels = config_.num_levels;
  stride_ = aligned_stride(width);
  std::size_t offset = 0;
  for (int l = 0; l < levels; ++l) {
    const double s = scales_[static_cast<std::size_t>(l)];
    const int w = static_cast<int>(std::lround(width / s));
    const int h = static_cast<int>(std::lround(height / s));
    level_w_[static_cast<std::size_t>(l)] = w;
    level_h_[static_cast<std::size_t>(l)] = h;
    level_offset_[static_cast<std::size_t>(l)] = offset;
    offset += static_cast<std::size_t>(h) * static_cast<std::size_t>(stride_);
    if (l > 0)
      plan_resize(level_w_[static_cast<std::size_t>(l - 1)], level_h_[static_cast<std::size_t>(l - 1)], w, h,
                  resize_plans_[static_cast<std::size_t>(l)]);
  }
  pyramid_.assign(offset, 0);
  blurred_.assign(offset, 0);
  enhanced_.assign(config_.mode == ExtractorMode::kAle ? offset : 0, 0);
  // Scores stay 0 outside each level's detection area, which non-maximum suppression relies on.
  scores_.assign(offset, 0);
  // Cells are at most twice cell_size_px (the area is split into whole cells).
  const int cell_edge = 2 * config_.cell_size_px + 2 * kFastRadius;
  cell_pixels_.assign(static_cast<std::size_t>(cell_edge * cell_edge), 0);
  cell_scores_.assign(static_cast<std::size_t>(cell_edge * cell_edge), 0);
  rotated_.build(pattern_, stride_);
  param_bounds_ = {};  // cell sizes follow the frame size
  width_ = width;
  height_ = height;
  return {};
}

GrayView OrbExtractor::level_image(int level) const {
  const std::size_t l = static_cast<std::size_t>(level);
  if (!has_enhanced_[l]) return plain_image(level);
  return {enhanced_.data() + level_offset_[l], level_w_[l], level_h_[l], stride_};
}

GrayView OrbExtractor::plain_image(int level) const {
  const std::size_t l = static_cast<std::size_t>(level);
  return {pyramid_.data() + level_offset_[l], level_w_[l], level_h_[l], stride_};
}

// The FAST score of each corner on `image` instead of the one it was detected with.
static void rescore(GrayView image, std::vector<FastCorner>& corners, std::size_t from) {
  for (std::size_t i = from; i < corners.size(); ++i) {
    FastCorner& c = corners[i];
    c.score = static_cast<std::uint8_t>(fast9_score(image.data + c.y * image.stride + c.x, image.stride));
  }
}

Status OrbExtractor::enhance_pyramid() {
  const int levels = config_.num_levels;
  const auto level_view = [&](int l) {
    const std::size_t i = static_cast<std::size_t>(l);
    return MutableGrayView{pyramid_.data() + level_offset_[i], level_w_[i], level_h_[i], stride_};
  };
  bool level_clahe = false;
  enhance::FramePlan plan;
  enhance::FrameStats level0_stats;  // of level 0 after the pre-LUT, for its level CLAHE
  if (config_.mode == ExtractorMode::kAle) {
    MutableGrayView l0 = level_view(0);
    // Grading needs the mean alone; the histogram only where a LUT or the level CLAHE follows.
    const enhance::Moments moments = enhance::compute_moments(l0);
    stats_.mean = moments.mean;
    stats_.sigma = moments.sigma;
    plan = policy_.grade(moments.mean);
    stats_.brightness = plan.brightness;
    level_clahe = plan.clahe;
    // With the level CLAHE, level 0's tile histograms give its histogram (one pass, not two); they
    // follow the pre-LUT below and its CLAHE reuses them.
    if (plan.needs_histogram && level_clahe)
      ALE_RETURN_IF_ERROR(
          enhance::count_level(level_clahe_, config_.enhance.clahe, 1.0 / scales_[0], l0, stats_scratch_));
    else if (plan.needs_histogram)
      enhance::compute_stats(l0, stats_scratch_);
    policy_.global_lut(stats_scratch_, plan);
    stats_.negative = plan.negative;
    stats_.gamma = plan.gamma;
    if (plan.has_pre) ALE_RETURN_IF_ERROR(enhance::apply_lut(l0, l0, plan.pre));
    if (plan.has_pre && level_clahe) ALE_RETURN_IF_ERROR(level_clahe_.remap_counts(l0, plan.pre));
    if (level_clahe) {
      if (plan.has_pre)
        enhance::remap_stats(stats_scratch_, plan.pre, level0_stats);
      else
        level0_stats = stats_scratch_;
    }
  }
  const bool has_post = plan.has_post;
  const enhance::Lut& post = plan.post;
  // ORB-SLAM's pyramid: each level resized (bilinear) from the one above.
  for (int l = 1; l < levels; ++l)
    resize_bilinear(level_view(l - 1), level_view(l), resize_plans_[static_cast<std::size_t>(l)], resize_row_);
  for (int l = 0; l < levels; ++l) {
    MutableGrayView v = level_view(l);
    LevelStats& ls = stats_.level[static_cast<std::size_t>(l)];
    has_enhanced_[static_cast<std::size_t>(l)] = false;
    if (config_.mode == ExtractorMode::kClahe) {
      ALE_RETURN_IF_ERROR(enhance::clahe(level_clahe_, config_.clahe_everywhere, v, v));
      ls.clahe_clip = config_.clahe_everywhere.clip_limit;
    } else if (level_clahe) {
      // Into its own buffer: the level before its CLAHE stays in the pyramid, because tile-local
      // mappings change BRIEF comparisons and FAST scores, the global pre-LUT (monotonic once
      // inverted back) does not.
      MutableGrayView enhanced{enhanced_.data() + level_offset_[static_cast<std::size_t>(l)], v.width, v.height,
                               stride_};
      enhance::LevelClaheSettings used;
      const double scale = 1.0 / scales_[static_cast<std::size_t>(l)];
      if (l == 0)  // its statistics are known from grading (remapped through the pre-LUT)
        ALE_RETURN_IF_ERROR(enhance::contrast_guided_clahe(level_clahe_, config_.enhance.clahe, scale, level0_stats,
                                                           v, enhanced, &used));
      else
        ALE_RETURN_IF_ERROR(
            enhance::contrast_guided_clahe(level_clahe_, config_.enhance.clahe, scale, v, enhanced, &used));
      ls.clahe_clip = used.clahe.clip_limit;
      if (has_post) ALE_RETURN_IF_ERROR(enhance::apply_lut(enhanced, enhanced, post));
      has_enhanced_[static_cast<std::size_t>(l)] = true;
    }
    if (has_post) ALE_RETURN_IF_ERROR(enhance::apply_lut(v, v, post));
  }
  return {};
}

// CellClahe::param_needed_score for a cell of w x h at `level`, remembered: it depends on the
// cell's size alone, and a level's cells have at most four sizes (the last column and row are
// narrower).
int OrbExtractor::param_needed_score(int level, int w, int h) {
  auto& slots = param_bounds_[static_cast<std::size_t>(level)];
  for (const ParamBound& b : slots)
    if (b.w == w && b.h == h) return b.value;
  const int value = CellClahe::param_needed_score(config_.cell_clahe, 1.0 / scales_[static_cast<std::size_t>(level)],
                                                  w, h, config_.t_higher);
  for (ParamBound& b : slots)
    if (b.w == 0) {
      b = {w, h, value};
      break;
    }
  return value;
}

// ALE's CLAHE retry of an empty cell, after its t_low pass (cell_raw_, largest score `best`):
// the cell with a margin of the FAST radius, CLAHE-enhanced, then FAST at the stricter t_higher
// so that noise lifted by the enhancement does not come through. Appends its corners to `out`
// (and sets `rescued`) when it finds any.
Status OrbExtractor::retry_cell(int level, PixelRect cell, int best, std::vector<FastCorner>& out, LevelStats& ls,
                                bool& rescued) {
  rescued = false;
  const std::size_t li = static_cast<std::size_t>(level);
  const GrayView plain = plain_image(level);
  const int m = kFastRadius;
  const int w = cell.width + 2 * m;
  const int h = cell.height + 2 * m;
  // The plain cell: CLAHE over the level CLAHE would enhance twice.
  const GrayView src = plain.sub(cell.x - m, cell.y - m, w, h);
  const double scale = 1.0 / scales_[li];
  // A corner at t_higher on the enhanced cell is one at some score on the original
  // (cell_clahe.h), so the t_low pass tells whether the retry can find anything: first by bounds
  // from the parameters and from the cell's spread, then by the cell's exact table.
  bool planned = false;
  int needed = -1;  // the raw score retry corners need, -1 when unknown
  bool possible = best >= param_needed_score(level, w, h);
  enhance::Moments moments;
  if (possible) {
    moments = CellClahe::moments(src);  // for the quick bound and the plan alike
    possible = best >= CellClahe::quick_needed_score(config_.cell_clahe, scale, w, h, moments, config_.t_higher);
  }
  if (possible) {
    ALE_RETURN_IF_ERROR(cell_clahe_.plan(config_.cell_clahe, scale, src, moments));
    planned = true;
    if (cell_clahe_.last_was_single_tile()) needed = cell_clahe_.min_raw_gap(config_.t_higher) - 1;
    possible = best >= needed;
  }
  if (!possible) ++ls.cells_skipped;
  if (!possible && !retry_bound_off_) return {};
  if (!planned) ALE_RETURN_IF_ERROR(cell_clahe_.plan(config_.cell_clahe, scale, src));
  const MutableGrayView cell_scores{cell_scores_.data(), w, h, w};
  std::fill(cell_scores_.begin(), cell_scores_.begin() + w * h, std::uint8_t{0});
  retry_raw_.clear();
  if (needed >= config_.t_low && !retry_bound_off_) {
    // Every corner of the enhanced cell reaches `needed` on the original, so the t_low pass
    // listed them all (row-major, as a full pass would): score just those on the table.
    const int ox = cell.x - m, oy = cell.y - m;
    for (const FastCorner& c : cell_raw_) {
      if (c.score < needed) continue;
      const int lx = c.x - ox, ly = c.y - oy;
      const int s = cell_clahe_.mapped_score(src, lx, ly);
      if (s < config_.t_higher) continue;
      cell_scores.row(ly)[lx] = static_cast<std::uint8_t>(s);
      retry_raw_.push_back({static_cast<std::int16_t>(lx), static_cast<std::int16_t>(ly), static_cast<std::uint8_t>(s)});
    }
  } else {
    const MutableGrayView dst{cell_pixels_.data(), w, h, w};
    if (cell_clahe_.last_was_single_tile())
      cell_clahe_.map(src, dst);
    else
      ALE_RETURN_IF_ERROR(cell_clahe_.apply(config_.cell_clahe, scale, src, dst));
    fast9_score_map(dst, {m, m, cell.width, cell.height}, config_.t_higher, cell_scores, retry_raw_);
  }
  const std::size_t before = out.size();
  fast9_nonmax(cell_scores, retry_raw_, out);
  if (out.size() == before) return {};
  for (std::size_t i = before; i < out.size(); ++i) {
    out[i].x = static_cast<std::int16_t>(out[i].x + cell.x - m);
    out[i].y = static_cast<std::int16_t>(out[i].y + cell.y - m);
  }
  // Scores of the enhanced cell would outrank real corners of other cells in the quadtree.
  rescore(plain, out, before);
  ++ls.cells_retry;
  rescued = true;
  return {};
}

Status OrbExtractor::detect_cell(int level, PixelRect cell, std::vector<FastCorner>& out, LevelStats& ls) {
  const std::size_t li = static_cast<std::size_t>(level);
  const MutableGrayView scores{scores_.data() + level_offset_[li], level_w_[li], level_h_[li], stride_};
  // Spec: t_low "on the original cell" (on the level CLAHE it would mostly find amplified noise).
  // It runs first even in ALE mode: the retry's bounds need its corners (cell_raw_, before
  // suppression), and a failed retry needs them anyway.
  cell_raw_.clear();
  fast9_score_map(plain_image(level), cell, config_.t_low, scores, cell_raw_);
  if (config_.mode == ExtractorMode::kAle && config_.cell_retry) {
    int best = 0;
    for (const FastCorner& c : cell_raw_) best = std::max(best, static_cast<int>(c.score));
    bool rescued = false;
    ALE_RETURN_IF_ERROR(retry_cell(level, cell, best, out, ls, rescued));
    if (rescued) return {};
  }
  const std::size_t before = out.size();
  fast9_nonmax(scores, cell_raw_, out);
  if (out.size() > before)
    ++ls.cells_low;
  else
    ++ls.cells_empty;
  return {};
}

Status OrbExtractor::detect_level(int level, std::vector<FastCorner>& out) {
  const std::size_t li = static_cast<std::size_t>(level);
  LevelStats& ls = stats_.level[li];
  const GrayView img = level_image(level);
  const MutableGrayView scores{scores_.data() + level_offset_[li], level_w_[li], level_h_[li], stride_};
  const PixelRect area{kEdgePx, kEdgePx, img.width - 2 * kEdgePx, img.height - 2 * kEdgePx};
  out.clear();
  if (area.width < 1 || area.height < 1) return {};
  const int cols = std::max(1, area.width / config_.cell_size_px);
  const int rows = std::max(1, area.height / config_.cell_size_px);
  const int cell_w = (area.width + cols - 1) / cols;
  const int cell_h = (area.height + rows - 1) / rows;
  ls.cells = cols * rows;

  // One pass at t_high over the whole area gives every cell's first step at once.
  raw_.clear();
  fast9_score_map(img, area, config_.t_high, scores, raw_);
  fast9_nonmax(scores, raw_, out);
  // The quadtree keeps the strongest corner per node: strongest in the plain level, so the level
  // CLAHE decides where corners are found but not which one wins.
  if (has_enhanced_[li]) rescore(plain_image(level), out, 0);
  cell_counts_.assign(static_cast<std::size_t>(cols * rows), 0);
  for (const FastCorner& c : out)
    ++cell_counts_[static_cast<std::size_t>(((c.y - area.y) / cell_h) * cols + (c.x - area.x) / cell_w)];
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      if (cell_counts_[static_cast<std::size_t>(r * cols + c)] > 0) {
        ++ls.cells_high;
        continue;
      }
      PixelRect cell{area.x + c * cell_w, area.y + r * cell_h, cell_w, cell_h};
      cell.width = std::min(cell.width, area.x + area.width - cell.x);
      cell.height = std::min(cell.height, area.y + area.height - cell.y);
      if (cell.width <= 0 || cell.height <= 0) continue;
      ALE_RETURN_IF_ERROR(detect_cell(level, cell, out, ls));
    }
  }
  ls.candidates = static_cast<int>(out.size());
  return {};
}

Status OrbExtractor::extract(GrayView image, std::vector<Keypoint>& keypoints, std::vector<Descriptor>& descriptors) {
  keypoints.clear();
  descriptors.clear();
  if (!configured_) return invalid_argument("features: extract() before configure()");
  ALE_RETURN_IF_ERROR(check_view(image, "features image"));
  if (image.width < 2 * kEdgePx + 1 || image.height < 2 * kEdgePx + 1 || image.width > 32767 ||
      image.height > 32767)
    return invalid_argument("features: image " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                            " must be " + std::to_string(2 * kEdgePx + 1) + "..32767 pixels in each direction");
  if (image.width != width_ || image.height != height_) ALE_RETURN_IF_ERROR(allocate(image.width, image.height));

  stats_ = ExtractionStats{};
  stats_.levels = config_.num_levels;
  copy_pixels(image, MutableGrayView{pyramid_.data(), width_, height_, stride_});
  ALE_RETURN_IF_ERROR(enhance_pyramid());

  for (int l = 0; l < config_.num_levels; ++l) {
    const std::size_t li = static_cast<std::size_t>(l);
    LevelStats& ls = stats_.level[li];
    const GrayView img = level_image(l);
    ls.width = img.width;
    ls.height = img.height;
    ls.budget = budgets_[li];
    ALE_RETURN_IF_ERROR(detect_level(l, kept_));
    raw_.clear();
    distribute_quadtree(kept_, {kEdgePx, kEdgePx, img.width - 2 * kEdgePx, img.height - 2 * kEdgePx}, budgets_[li],
                        quadtree_, raw_);
    ls.kept = static_cast<int>(raw_.size());
    if (raw_.empty()) continue;
    // Descriptors on the smoothed level (ORB-SLAM: 7x7 Gaussian, sigma 2; blur.h).
    const GrayView plain = plain_image(l);
    // Only around the kept corners: descriptors read nothing else (their rotated samples stay
    // within kPatchRadius), and most of a level is not near one.
    gaussian7_patches(plain, MutableGrayView{blurred_.data() + level_offset_[li], img.width, img.height, stride_},
                      raw_, kPatchRadius, blur_scratch_);
    const GrayView smoothed{blurred_.data() + level_offset_[li], img.width, img.height, stride_};
    const float scale = static_cast<float>(scales_[li]);
    for (const FastCorner& c : raw_) {
      Keypoint kp;
      kp.lx = c.x;
      kp.ly = c.y;
      kp.x = static_cast<float>(c.x) * scale;
      kp.y = static_cast<float>(c.y) * scale;
      kp.level = l;
      kp.score = c.score;
      kp.size = 31.0f * scale;
      kp.angle_deg = ic_angle_deg(plain, c.x, c.y);
      keypoints.push_back(kp);
      descriptors.emplace_back();
      describe(smoothed, c.x, c.y, rotated_, angle_bin(kp.angle_deg), descriptors.back());
    }
  }
  stats_.total = static_cast<int>(keypoints.size());
  return {};
}

}  // namespace ale::features
