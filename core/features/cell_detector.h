// The cell-detection stage of the frame path: per level, FAST-9 at t_high over the whole area;
// per cell without a corner, ALE's CLAHE retry at t_higher (the cell, with a margin of the FAST
// radius, enhanced by the contrast-guided cell CLAHE), else FAST at t_low on the plain level.
// Corners come out scored on the plain level (orb.h top). Its scratch (score maps, cell buffers,
// the cell CLAHE, the retry bounds) is its own; nothing is allocated per frame after the first
// frame of a size.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/base/image.h"
#include "core/base/status.h"
#include "core/features/cell_clahe.h"
#include "core/features/fast.h"
#include "core/features/frame_pyramid.h"
#include "core/features/orb.h"

namespace ale::features {

class CellDetector {
 public:
  // `config` is valid (validate(ExtractorConfig)).
  void configure(const ExtractorConfig& config);
  // Sizes the scratch for `pyramid`'s planned frame size.
  void plan(const FramePyramid& pyramid);
  // The corners of `level` (after non-maximum suppression, before distribution) into `out`;
  // fills the cell counts of `ls`.
  Status detect_level(const FramePyramid& pyramid, int level, std::vector<FastCorner>& out, LevelStats& ls);
  // Whether this frame's empty cells get the CLAHE retry (ALE, by the frame's grade).
  void set_frame_retry(bool on) { frame_retry_ = on; }
  // The plain-level FAST score every candidate of this frame needs (0: none).
  void set_frame_gate(int min_score) { gate_ = min_score; }
  // Tests only: run every cell retry even where the bound says it cannot find a corner.
  void set_retry_bound(bool on) { retry_bound_off_ = !on; }

 private:
  Status detect_cell(const FramePyramid& pyramid, int level, PixelRect cell, std::vector<FastCorner>& out,
                     LevelStats& ls);
  Status retry_cell(const FramePyramid& pyramid, int level, PixelRect cell, int best, std::vector<FastCorner>& out,
                    LevelStats& ls, bool& rescued);
  int param_needed_score(const FramePyramid& pyramid, int level, int w, int h);
  MutableGrayView scores(const FramePyramid& pyramid, int level) {
    const GrayView plain = pyramid.plain(level);
    return {scores_.data() + pyramid.offset(level), plain.width, plain.height, stride_};
  }

  ExtractorConfig config_;
  int width_ = 0;  // the planned frame size
  int height_ = 0;
  int stride_ = 0;
  std::vector<std::uint8_t> scores_;  // one score map per level, at the pyramid's offsets
  CellClahe cell_clahe_;
  std::vector<std::uint8_t> cell_pixels_;
  std::vector<std::uint8_t> cell_scores_;
  std::vector<FastCorner> raw_;
  std::vector<FastCorner> cell_raw_;
  std::vector<FastCorner> retry_raw_;
  std::vector<int> cell_counts_;
  bool retry_bound_off_ = false;
  bool frame_retry_ = false;
  int gate_ = 0;
  std::vector<FastCorner> gated_;  // this level's candidates below the gate
  struct ParamBound {
    int w = 0, h = 0, value = 0;  // w == 0: free
  };
  std::array<std::array<ParamBound, 4>, kMaxLevels> param_bounds_{};
};

}  // namespace ale::features
