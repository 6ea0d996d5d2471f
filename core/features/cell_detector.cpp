#include "core/features/cell_detector.h"

#include <algorithm>

#include "core/features/kernels.h"
#include "core/features/score_map.h"

namespace ale::features {

void CellDetector::configure(const ExtractorConfig& config) {
  config_ = config;
  width_ = height_ = 0;  // re-plan the buffers on the next frame
}

void CellDetector::plan(const FramePyramid& pyramid) {
  if (width_ == pyramid.width() && height_ == pyramid.height()) return;
  width_ = pyramid.width();
  height_ = pyramid.height();
  stride_ = pyramid.stride();
  // Scores stay 0 outside each level's detection area, which non-maximum suppression relies on.
  scores_.assign(pyramid.size(), 0);
  // Cells are at most twice cell_size_px (the area is split into whole cells).
  const int cell_edge = 2 * config_.cell_size_px + 2 * kFastRadius;
  cell_pixels_.assign(static_cast<std::size_t>(cell_edge * cell_edge), 0);
  cell_scores_.assign(static_cast<std::size_t>(cell_edge * cell_edge), 0);
  param_bounds_ = {};  // cell sizes follow the frame size
}

namespace {

// The FAST score of each corner on `image` instead of the one it was detected with.
void rescore(GrayView image, std::vector<FastCorner>& corners, std::size_t from) {
  const auto score = kernels().fast9_score;  // fast9_score() without its per-call wrapper
  for (std::size_t i = from; i < corners.size(); ++i) {
    FastCorner& c = corners[i];
    c.score = static_cast<std::uint8_t>(score(image.data + c.y * image.stride + c.x, image.stride));
  }
}

// Moves the corners from `from` on whose (plain-level) score is below `gate` to `gated` (drops
// them when null).
void erase_below(std::vector<FastCorner>& corners, std::size_t from, int gate, std::vector<FastCorner>* gated) {
  if (gate <= 0) return;
  const auto below = [gate](const FastCorner& c) { return c.score < gate; };
  if (gated != nullptr)
    for (std::size_t i = from; i < corners.size(); ++i)
      if (below(corners[i])) gated->push_back(corners[i]);
  corners.erase(std::remove_if(corners.begin() + static_cast<std::ptrdiff_t>(from), corners.end(), below),
                corners.end());
}

}  // namespace

// CellClahe::param_needed_score for a cell of w x h at `level`, remembered: it depends on the
// cell's size alone, and a level's cells have at most four sizes (the last column and row are
// narrower).
int CellDetector::param_needed_score(const FramePyramid& pyramid, int level, int w, int h) {
  auto& slots = param_bounds_[static_cast<std::size_t>(level)];
  for (const ParamBound& b : slots)
    if (b.w == w && b.h == h) return b.value;
  const int value = CellClahe::param_needed_score(config_.cell_clahe, 1.0 / pyramid.scale(level),
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
Status CellDetector::retry_cell(const FramePyramid& pyramid, int level, PixelRect cell, int best,
                                std::vector<FastCorner>& out, LevelStats& ls, bool& rescued) {
  rescued = false;
  const GrayView plain = pyramid.plain(level);
  const int m = kFastRadius;
  const int w = cell.width + 2 * m;
  const int h = cell.height + 2 * m;
  // The plain cell: CLAHE over the level CLAHE would enhance twice.
  const GrayView src = plain.sub(cell.x - m, cell.y - m, w, h);
  const double scale = 1.0 / pyramid.scale(level);
  // A corner at t_higher on the enhanced cell is one at some score on the original
  // (cell_clahe.h), so the t_low pass tells whether the retry can find anything: first by bounds
  // from the parameters and from the cell's spread, then by the cell's exact table.
  bool planned = false;
  int needed = -1;  // the raw score retry corners need, -1 when unknown
  bool possible = best >= param_needed_score(pyramid, level, w, h);
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
  // Dropped, not kept as gated: the t_low pass that follows lists the same pixels of the plain
  // cell, and a corner twice in the quadtree's input is a node it can never split.
  erase_below(out, before, gate_, nullptr);
  if (out.size() == before) return {};
  ++ls.cells_retry;
  rescued = true;
  return {};
}

Status CellDetector::detect_cell(const FramePyramid& pyramid, int level, PixelRect cell, std::vector<FastCorner>& out,
                                 LevelStats& ls) {
  const MutableGrayView level_scores = scores(pyramid, level);
  // Spec: t_low "on the original cell" (on the level CLAHE it would mostly find amplified noise).
  // It runs first even in ALE mode: the retry's bounds need its corners (cell_raw_, before
  // suppression), and a failed retry needs them anyway.
  cell_raw_.clear();
  fast9_score_map(pyramid.plain(level), cell, config_.t_low, level_scores, cell_raw_);
  if (frame_retry_) {
    int best = 0;
    for (const FastCorner& c : cell_raw_) best = std::max(best, static_cast<int>(c.score));
    bool rescued = false;
    ALE_RETURN_IF_ERROR(retry_cell(pyramid, level, cell, best, out, ls, rescued));
    if (rescued) return {};
  }
  const std::size_t before = out.size();
  fast9_nonmax(level_scores, cell_raw_, out);
  erase_below(out, before, gate_, &gated_);
  if (out.size() > before)
    ++ls.cells_low;
  else
    ++ls.cells_empty;
  return {};
}

Status CellDetector::detect_level(const FramePyramid& pyramid, int level, std::vector<FastCorner>& out,
                                  LevelStats& ls) {
  const GrayView img = pyramid.image(level);
  const MutableGrayView level_scores = scores(pyramid, level);
  const PixelRect area{kEdgePx, kEdgePx, img.width - 2 * kEdgePx, img.height - 2 * kEdgePx};
  out.clear();
  gated_.clear();
  if (area.width < 1 || area.height < 1) return {};
  const int cols = std::max(1, area.width / config_.cell_size_px);
  const int rows = std::max(1, area.height / config_.cell_size_px);
  const int cell_w = (area.width + cols - 1) / cols;
  const int cell_h = (area.height + rows - 1) / rows;
  ls.cells = cols * rows;

  // One pass at t_high over the whole area gives every cell's first step at once.
  raw_.clear();
  fast9_score_map(img, area, config_.t_high, level_scores, raw_);
  fast9_nonmax(level_scores, raw_, out);
  // The quadtree keeps the strongest corner per node: strongest in the plain level, so the level
  // CLAHE decides where corners are found but not which one wins.
  if (pyramid.has_enhanced(level)) rescore(pyramid.plain(level), out, 0);
  erase_below(out, 0, gate_, &gated_);
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
      ALE_RETURN_IF_ERROR(detect_cell(pyramid, level, cell, out, ls));
    }
  }
  // Gated corners only join a level whose other corners cannot fill its budget, and then compete
  // in the quadtree, where a node keeps its strongest: noise must not push real corners out, but a
  // level with too few real ones keeps its count.
  if (out.size() < static_cast<std::size_t>(std::max(ls.budget, 0)) && !gated_.empty()) {
    out.insert(out.end(), gated_.begin(), gated_.end());
    // A cell whose t_high corners were all gated had its t_low pass list them again: one entry
    // per pixel (the first, by the order below), since the quadtree cannot split a node holding
    // two corners at one place.
    std::stable_sort(out.begin(), out.end(),
                     [](const FastCorner& a, const FastCorner& b) { return a.y != b.y ? a.y < b.y : a.x < b.x; });
    out.erase(std::unique(out.begin(), out.end(),
                          [](const FastCorner& a, const FastCorner& b) { return a.x == b.x && a.y == b.y; }),
              out.end());
  }
  ls.candidates = static_cast<int>(out.size());
  return {};
}

}  // namespace ale::features
