// The ORB front end (spec section 6): its configuration, keypoints and per-frame figures. It runs
// as stages of the frame path (core/frontend/frame_path.h): grade and global LUT, pyramid
// (frame_pyramid.h), per-level enhancement, cell detection (cell_detector.h), quadtree
// distribution (quadtree.h), orientation and description (describer.h).
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
// - kHe, kGamma: the article's whole-pipeline comparisons: one global LUT on every frame before
//   the pyramid (histogram equalisation; the CDF-driven gamma alone), then kBaseline's cells on
//   the mapped image.
//
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "core/base/config_table.h"
#include "core/base/frame_state.h"
#include "core/base/status.h"
#include "core/enhance/clahe.h"
#include "core/enhance/params.h"
#include "core/enhance/policy.h"
#include "core/features/frame_pyramid.h"

namespace ale::features {

enum class ExtractorMode { kAle, kBaseline, kClahe, kHe, kGamma };
const char* to_string(ExtractorMode m);  // "ale", "baseline", "clahe", "he", "gamma"
// Parses "ale" | "baseline" (or "off": the enhancement switched off) | "clahe" | "he" | "gamma".
Result<ExtractorMode> parse_extractor_mode(const std::string& s);

// Keypoints keep this many pixels from a level's border (ORB-SLAM's EDGE_THRESHOLD): room for the
// orientation patch and rotated descriptor samples.
constexpr int kEdgePx = 19;

struct ExtractorConfig {
  ExtractorMode mode = ExtractorMode::kAle;  // not a features.* key: the daemon sets it from enhancement.mode
  int num_features = 1000;    // budget over all levels
  int num_levels = 8;         // 1..kMaxLevels
  double scale_factor = 1.2;  // > 1
  int cell_size_px = 30;      // FAST grid cell edge, >= 8
  int t_high = 20;            // ORB-SLAM3 iniThFAST
  int t_higher = 30;          // ALE: threshold after the cell CLAHE (> t_high; docs/features.md)
  int t_low = 7;              // ORB-SLAM3 minThFAST
  bool cell_retry = true;     // ALE: the CLAHE step of the per-cell ladder
  // ALE: the cell retry also on frames graded normal (the article's recipe). Off, a frame graded
  // normal gets exactly the baseline's output (with level_enhance = kNonNormalFrames).
  bool retry_normal_frames = false;
  // ALE, frames not graded normal: every candidate needs a FAST score on the plain level of at
  // least noise_gate times the frame's noise sigma (enhance::estimate_noise_sigma on plain level
  // 0), so that corners lifted out of amplified noise do not take the budget; those below join
  // only a level whose other candidates are fewer than its budget. 0: off.
  double noise_gate = 2.0;
  // ALE: a frame graded bright whose sigma (grey levels) reaches this keeps its contrast and is
  // treated as normal (no negative path); 0: every bright frame takes the negative path.
  double bright_min_sigma = 25.0;
  // ALE: a 3x3 binomial on level 0 before the histogram, CLAHE and detection (the pyramid and the
  // descriptors follow from it), on frames graded extremely dark (1) or on every frame not graded
  // normal (2); 0: off. Default 1: 2 lowers the webcam test's matching score below the
  // baseline's (0.00979 vs 0.01036). The noise estimates that gate detection and limit the gamma
  // are the unfiltered estimate times the filter's noise gain (enhance::kBinomial3NoiseGain).
  // docs/features.md, "Denoising before detection".
  int denoise = 1;
  // ALE: when the per-level CLAHE runs, and the enhancement policy's parameters (core/enhance/policy.h).
  enhance::LevelEnhance level_enhance = enhance::LevelEnhance::kNonNormalFrames;
  enhance::EnhanceParams enhance = enhance::feature_level_params();
  enhance::LevelClaheParams cell_clahe;    // ALE: the per-cell CLAHE (one tile per cell)
  enhance::ClaheParams clahe_everywhere{8, 8, 2.0};  // kClahe: CLAHE on every level
};

// ALE as the article describes it (the front end before issue 13's changes): the cell retry on
// every frame and none of the later noise-aware steps. For comparisons (ale-features --match-report,
// the light-level test).
inline ExtractorConfig article_config() {
  ExtractorConfig c;
  c.retry_normal_frames = true;
  c.noise_gate = 0.0;
  c.bright_min_sigma = 0.0;
  c.enhance.gamma.target_mean = 0.0;  // the CDF rule
  c.enhance.gamma.noise_max = 0.0;
  c.denoise = 0;  // the article filters nothing before its CLAHE (our addition, issue 13)
  return c;
}

// The configuration table of ExtractorConfig (core/base/config_table.h): keys are the members'
// paths ("num_features", "enhance.clahe.clip_base", "cell_clahe.tile_min", ...).
const ConfigTable& extractor_config_table();
// kInvalidArgument "<key>: <why>" for the first field out of range (by the table) or inconsistent.
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
  double raw_noise_sigma = 0.0;  // ALE, frames not graded normal: the noise estimate before the global LUT
  double noise_sigma = 0.0;  // ALE with noise_gate: the estimate on plain level 0
  double denoised_estimate = 0.0;  // ALE with denoise: the Laplacian estimate on the filtered level 0 (0: not filtered)
  int noise_gate_score = 0;  // the plain-level score candidates needed (0: no gate)
  int levels = 0;
  std::array<LevelStats, kMaxLevels> level{};
  int total = 0;
};

}  // namespace ale::features
