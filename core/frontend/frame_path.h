// The per-frame path: one owner that runs the stages in order and times each into the frame's
// record (core/base/frame_record.h). Today the ORB front end's stages, each its own unit with its
// own scratch:
//
//   grade       grade and global LUT (ALE: policy, gamma / negative on level 0; he, gamma: their LUT)  grade_stage.h
//   pyramid     ORB-SLAM's pyramid from level 0                                    features/frame_pyramid.h
//   enhance     per-level enhancement (ALE: contrast-guided CLAHE; or CLAHE everywhere)  level_enhance_stage.h
//   detect      cell detection: t_high, the CLAHE retry at t_higher, t_low         features/cell_detector.h
//   distribute  quadtree distribution to each level's budget                       features/quadtree.h
//   describe    orientation and rotated BRIEF                                      features/describer.h
//
// followed by the stages appended with append_stage() (the SLAM core's tracking and mapping), which
// see the front end's output. The modes and the ladder: core/features/orb.h. Nothing is allocated
// per frame once a frame of a given size has been seen. Each stage also runs between two probes
// of the ARM instruction counter (core/base/stage_probe.h): slot i + 1 for stage i.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/base/frame_record.h"
#include "core/base/image.h"
#include "core/base/status.h"
#include "core/enhance/grading.h"
#include "core/enhance/policy.h"
#include "core/features/brief.h"
#include "core/features/cell_detector.h"
#include "core/features/describer.h"
#include "core/features/fast.h"
#include "core/features/frame_pyramid.h"
#include "core/features/orb.h"
#include "core/features/quadtree.h"
#include "core/frontend/grade_stage.h"
#include "core/frontend/level_enhance_stage.h"

namespace ale::frontend {

// Which frame this is: what the appended stages (tracking) need beyond the pixels.
struct FrameId {
  std::int64_t timestamp_ns = 0;  // capture time
  std::uint64_t sequence = 0;     // capture order
};

// What a stage after the front end sees of the frame.
struct FrameOutput {
  FrameId id;
  GrayView image;  // the frame as it came
  const std::vector<features::Keypoint>& keypoints;
  const std::vector<features::Descriptor>& descriptors;
  const features::ExtractionStats& stats;
};

// A stage appended to the path (e.g. the SLAM core's tracking).
class FrameStage {
 public:
  virtual ~FrameStage() = default;
  virtual const char* name() const = 0;  // a string literal: it goes into the frame's record
  virtual Status run(const FrameOutput& frame) = 0;
};

class FramePath {
 public:
  // The front end's stages, in order (the names in timings()).
  static constexpr std::array<const char*, 6> kFrontEndStages = {"grade",  "pyramid",    "enhance",
                                                                 "detect", "distribute", "describe"};

  FramePath() = default;
  // kInvalidArgument naming the bad field; the previous configuration stays in force then.
  Status configure(const features::ExtractorConfig& config);
  const features::ExtractorConfig& config() const { return config_; }
  // Changes the enhancement parameters (config().enhance: grading thresholds, gamma, level CLAHE)
  // of a configured path from the next frame on, keeping the held brightness class and every
  // buffer (the CLAHE grids are planned per frame). kInvalidArgument naming the bad field; the
  // previous parameters stay in force then.
  Status set_enhance(const enhance::EnhanceParams& params);
  // Runs `stage` after the front end's stages and those appended before; the path does not own it.
  // kInvalidArgument when the record has no room left (kMaxFrameStages in all).
  Status append_stage(FrameStage& stage);
  // The clock the stages are timed with (steady_clock_ns by default).
  void set_clock(MonotonicClock clock) { clock_ = clock; }

  // Runs every stage on `image` (8-bit grey, at least 2 * kEdgePx + 1 pixels in each direction):
  // keypoints and their descriptors (same order), then the appended stages.
  Status extract(GrayView image, std::vector<features::Keypoint>& keypoints,
                 std::vector<features::Descriptor>& descriptors) {
    return extract(FrameId{}, image, keypoints, descriptors);
  }
  // The same, telling the appended stages which frame it is.
  Status extract(const FrameId& id, GrayView image, std::vector<features::Keypoint>& keypoints,
                 std::vector<features::Descriptor>& descriptors);

  const features::ExtractionStats& stats() const { return stats_; }
  // Each stage's time in the last extract().
  const FrameTimings& timings() const { return timings_; }
  // The image FAST ran on at `level` (after enhancement) from the last extract().
  GrayView level_image(int level) const { return pyramid_.image(level); }
  // `level` before the level CLAHE (ALE mode; level_image() when no level CLAHE ran): the image
  // for the cell retry, t_low, ranking, orientation and descriptors.
  GrayView plain_image(int level) const { return pyramid_.plain(level); }
  double level_scale(int level) const { return pyramid_.scale(level); }
  // Forgets the brightness class held by the grader (a new sequence starts).
  void reset() { grade_.reset(); }
  // Tests only: run every cell retry even where the bound says it cannot find a corner, to check
  // that skipping changes nothing.
  void set_retry_bound_for_test(bool on) { detector_.set_retry_bound(on); }

 private:
  features::ExtractorConfig config_;
  bool configured_ = false;
  std::array<int, features::kMaxLevels> budgets_{};
  MonotonicClock clock_ = steady_clock_ns;
  std::vector<FrameStage*> appended_;

  GradeStage grade_;
  features::FramePyramid pyramid_;
  LevelEnhanceStage level_enhance_;
  features::CellDetector detector_;
  features::QuadtreeScratch quadtree_;
  features::Describer describer_;

  enhance::FramePlan plan_;  // ALE only: the grade stage fills it on every frame
  enhance::FrameStats level0_stats_;
  std::array<std::vector<features::FastCorner>, features::kMaxLevels> candidates_;
  std::array<std::vector<features::FastCorner>, features::kMaxLevels> kept_;
  features::ExtractionStats stats_;
  FrameTimings timings_;
};

}  // namespace ale::frontend
