// The ORB front end (spec section 6): image pyramid, per-cell FAST-9 with the ALE retry ladder,
// quadtree distribution, orientation by intensity centroid and 256-bit rotated BRIEF.
//
// Three modes, chosen by configuration:
// - kBaseline: ORB-SLAM3's extractor. No enhancement; per cell FAST at t_high, and where a cell
//   yields nothing, FAST at t_low.
// - kClahe: "CLAHE everywhere": fixed-parameter CLAHE on every pyramid level, then kBaseline's cells.
// - kAle: the frame is graded (with hysteresis, core/enhance); a pre-LUT is applied at level 0
//   (gamma for extremely dark frames, the negative for bright ones, gamma of the negative when
//   that is extremely dark); the pyramid is built from it; each level gets the contrast-guided
//   CLAHE with its own scale (spec section 5) when `level_enhance` says so; bright frames are
//   inverted back. Per cell: FAST at t_high; else the cell (with a margin of the FAST radius)
//   contrast-guided-CLAHE-enhanced and FAST at t_higher; else FAST at t_low. The level CLAHE only
//   decides where corners are found: the cell retry, t_low, the quadtree's ranking, orientation
//   and descriptors use the level before it (the "plain" level: globally mapped only, so BRIEF
//   bits and FAST scores compare with those of un-enhanced frames; docs/features.md measures why).
//   For a normal frame with level_enhance = kNonNormalFrames this is kBaseline plus the cell retry.
//
// Nothing is allocated per frame once a frame of a given size has been seen (the first frame of a
// new size allocates the pyramid and scratch buffers).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/base/frame_state.h"
#include "core/base/image.h"
#include "core/base/status.h"
#include "core/enhance/clahe.h"
#include "core/enhance/grading.h"
#include "core/enhance/params.h"
#include "core/enhance/policy.h"
#include "core/features/blur.h"
#include "core/features/brief.h"
#include "core/features/cell_clahe.h"
#include "core/features/fast.h"
#include "core/features/pyramid.h"
#include "core/features/quadtree.h"

namespace ale::features {

enum class ExtractorMode { kAle, kBaseline, kClahe };
const char* to_string(ExtractorMode m);  // "ale", "baseline", "clahe"
// Parses "ale" | "baseline" | "clahe".
Result<ExtractorMode> parse_extractor_mode(const std::string& s);

constexpr int kMaxLevels = 16;
// Keypoints keep this many pixels from a level's border (ORB-SLAM's EDGE_THRESHOLD): room for the
// orientation patch and rotated descriptor samples.
constexpr int kEdgePx = 19;

struct ExtractorConfig {
  ExtractorMode mode = ExtractorMode::kAle;
  int num_features = 1000;    // budget over all levels
  int num_levels = 8;         // 1..kMaxLevels
  double scale_factor = 1.2;  // > 1
  int cell_size_px = 30;      // FAST grid cell edge, >= 8
  int t_high = 20;            // ORB-SLAM3 iniThFAST
  int t_higher = 30;          // ALE: threshold after the cell CLAHE (> t_high; docs/features.md)
  int t_low = 7;              // ORB-SLAM3 minThFAST
  bool cell_retry = true;     // ALE: the CLAHE step of the per-cell ladder
  // ALE: when the per-level CLAHE runs, and the enhancement policy's parameters (core/enhance/policy.h).
  enhance::LevelEnhance level_enhance = enhance::LevelEnhance::kNonNormalFrames;
  enhance::EnhanceParams enhance = enhance::feature_level_params();
  enhance::LevelClaheParams cell_clahe;    // ALE: the per-cell CLAHE (one tile per cell)
  enhance::ClaheParams clahe_everywhere{8, 8, 2.0};  // kClahe: CLAHE on every level
};

// kInvalidArgument naming the first field out of range.
Status validate(const ExtractorConfig& c);

struct Keypoint {
  float x = 0.0f;  // level-0 pixel coordinates
  float y = 0.0f;
  float angle_deg = 0.0f;  // intensity-centroid orientation, [0, 360)
  float size = 0.0f;       // patch diameter at level 0: 31 * scale^level
  int level = 0;
  int score = 0;  // FAST score (fast.h) on the plain level (orb.h top; the level image in other modes)
  std::int16_t lx = 0;  // integer coordinates in the level image
  std::int16_t ly = 0;
};

// Where each level's keypoints came from, before distribution.
struct LevelStats {
  int width = 0;
  int height = 0;
  int cells = 0;
  int cells_high = 0;     // cells that had corners at t_high
  int cells_retry = 0;    // cells rescued by the CLAHE retry at t_higher
  int cells_low = 0;      // cells rescued by t_low
  int cells_skipped = 0;  // cells whose retry was skipped because it could not find a corner
  int cells_empty = 0;
  int candidates = 0;     // corners after NMS, all steps
  int budget = 0;
  int kept = 0;           // after the quadtree
  double clahe_clip = 0.0;  // level CLAHE clip limit, 0 when none ran
};

struct ExtractionStats {
  BrightnessClass brightness = BrightnessClass::kNormal;  // ALE grading (kNormal in other modes)
  double mean = 0.0;
  double sigma = 0.0;  // of the level-0 image before enhancement (ALE mode)
  double gamma = 1.0;
  bool negative = false;
  int levels = 0;
  std::array<LevelStats, kMaxLevels> level{};
  int total = 0;
};

class OrbExtractor {
 public:
  OrbExtractor() = default;
  // kInvalidArgument naming the bad field; the previous configuration stays in force then.
  Status configure(const ExtractorConfig& config);
  const ExtractorConfig& config() const { return config_; }

  // Keypoints and their descriptors (same order). `image` is 8-bit grey, at least 2 * kEdgePx + 1
  // pixels in each direction.
  Status extract(GrayView image, std::vector<Keypoint>& keypoints, std::vector<Descriptor>& descriptors);

  const ExtractionStats& stats() const { return stats_; }
  // The image FAST ran on at `level` (after enhancement) from the last extract().
  GrayView level_image(int level) const;
  // `level` before the level CLAHE (ALE mode; level_image() when no level CLAHE ran): the image
  // for the cell retry, t_low, ranking, orientation and descriptors.
  GrayView plain_image(int level) const;
  double level_scale(int level) const { return scales_[static_cast<std::size_t>(level)]; }
  // Forgets the brightness class held by the grader (a new sequence starts).
  void reset() { policy_.reset(); }
  // Tests only: run every cell retry even where the bound says it cannot find a corner, to check
  // that skipping changes nothing.
  void set_retry_bound_for_test(bool on) { retry_bound_off_ = !on; }

 private:
  Status allocate(int width, int height);
  Status enhance_pyramid();
  Status detect_level(int level, std::vector<FastCorner>& out);
  Status detect_cell(int level, PixelRect cell, std::vector<FastCorner>& out, LevelStats& ls);
  Status retry_cell(int level, PixelRect cell, int best, std::vector<FastCorner>& out, LevelStats& ls, bool& rescued);
  int param_needed_score(int level, int w, int h);

  ExtractorConfig config_;
  bool configured_ = false;
  std::array<double, kMaxLevels> scales_{};
  std::array<int, kMaxLevels> budgets_{};

  // Pyramid buffers: every level shares one stride so one table of rotated sample offsets serves all.
  int width_ = 0;
  int height_ = 0;
  int stride_ = 0;
  std::array<int, kMaxLevels> level_w_{}, level_h_{};
  std::array<std::size_t, kMaxLevels> level_offset_{};
  std::vector<std::uint8_t> pyramid_;
  std::vector<std::uint8_t> blurred_;
  std::vector<std::uint8_t> enhanced_;    // levels after the level CLAHE (ALE); the pyramid keeps them before it
  std::array<bool, kMaxLevels> has_enhanced_{};
  std::vector<std::uint8_t> scores_;
  BlurScratch blur_scratch_;
  std::array<ResizePlan, kMaxLevels> resize_plans_;  // level l from level l - 1 (l >= 1)
  std::vector<std::uint16_t> resize_row_;

  enhance::EnhancePolicy policy_;
  enhance::FrameStats stats_scratch_;
  enhance::ClaheContext level_clahe_;
  CellClahe cell_clahe_;
  std::vector<std::uint8_t> cell_pixels_;
  std::vector<std::uint8_t> cell_scores_;

  std::vector<FastCorner> raw_;
  std::vector<FastCorner> kept_;
  std::vector<FastCorner> cell_raw_;
  std::vector<FastCorner> retry_raw_;
  bool retry_bound_off_ = false;
  struct ParamBound {
    int w = 0, h = 0, value = 0;  // w == 0: free
  };
  std::array<std::array<ParamBound, 4>, kMaxLevels> param_bounds_{};
  std::vector<int> cell_counts_;
  QuadtreeScratch quadtree_;
  BriefPattern pattern_;
  RotatedPattern rotated_;
  ExtractionStats stats_;
};

}  // namespace ale::features
