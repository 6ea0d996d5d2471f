// The per-frame log of `ale-slamd --frame-log FILE.csv`: one row type and one column table for
// the daemon that writes it and ale-eval (app/tools/lib/eval/frame_log.h) that reads it.
//
//   #timestamp_ns,sequence,state,brightness,mean,sigma,gamma,clip,negative,features,inliers,frame_time_ms,
//    map_id,keyframes,landmarks,frontend_ms,tracking_ms,mapping_ms,place_ms,loops,loop_ms,merges,merges_refused
//
// The header line comes first and names the columns, so a reader finds them by name. state is a
// TrackingState name, brightness a BrightnessClass name (frame_state.h). The SLAM core's columns
// (from map_id on) came later, then place_ms, then loops and loop_ms, then merges and
// merges_refused: a reader accepts logs without them (they read as 0).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "core/base/frame_state.h"
#include "core/base/status.h"
#include "core/base/text_file.h"

namespace ale {

struct FrameLogRow {
  std::uint64_t timestamp_ns = 0;
  std::uint64_t sequence = 0;
  TrackingState state = TrackingState::kNotInitialized;
  BrightnessClass brightness = BrightnessClass::kNormal;
  double mean = 0.0;   // mean intensity before enhancement, 0..255
  double sigma = 0.0;  // its standard deviation
  double gamma = 1.0;
  double clip = 0.0;   // level-0 CLAHE clip limit, 0 when none ran
  bool negative = false;
  int features = 0;
  int inliers = 0;
  double frame_time_ms = 0.0;
  std::uint64_t map_id = 0;  // a change starts a new trajectory segment (tracking was lost for good)
  int keyframes = 0;         // in the map after the frame
  int landmarks = 0;
  double frontend_ms = 0.0;  // the front end's stages (grade .. describe)
  double tracking_ms = 0.0;  // the SLAM core's `track` stage
  double mapping_ms = 0.0;   // its `map_ba` and `map` stages (keyframe insertion, local mapping)
  // Place recognition (SlamReport::place_ns): a part of tracking_ms and mapping_ms, not added to them.
  double place_ms = 0.0;
  // Loop closing: loops closed since start (SlamReport::loops_closed; a frame whose count is above
  // its predecessor's is the one a loop was closed on) and its time in this frame
  // (SlamReport::loop_ns: the lookup of the keyframe before, the correction when one was closed; a
  // part of mapping_ms, not added to it).
  int loops = 0;
  double loop_ms = 0.0;
  // Map merging: maps joined since start (SlamReport::merges; a frame whose count is above its
  // predecessor's is the one the current map moved into an older one, its map_id the older map's
  // from then on) and verified places of another map not joined (SlamReport::merges_refused).
  int merges = 0;
  int merges_refused = 0;

  double t_s() const { return static_cast<double>(timestamp_ns) / 1e9; }
};

// What a column holds, which says how it is written and what a reader accepts.
enum class FrameLogKind {
  kCount,       // a whole number >= 0 (64 bits)
  kSmallCount,  // a whole number >= 0 that fits an int
  kFlag,        // 0 or 1
  kNumber,      // a finite number, written with `decimals` digits after the point
  kTime,        // a finite number >= 0, written with `decimals` digits
  kState,       // a TrackingState name
  kBrightness,  // a BrightnessClass name
};

enum class FrameLogColumn : std::size_t {
  kTimestampNs, kSequence, kState, kBrightness, kMean, kSigma, kGamma, kClip, kNegative, kFeatures, kInliers,
  kFrameTimeMs, kMapId, kKeyframes, kLandmarks, kFrontendMs, kTrackingMs, kMappingMs, kPlaceMs, kLoops, kLoopMs, kMerges,
  kMergesRefused, kCount
};
constexpr std::size_t kFrameLogColumns = static_cast<std::size_t>(FrameLogColumn::kCount);

struct FrameLogColumnInfo {
  const char* name;
  FrameLogKind kind;
  int decimals;           // kNumber and kTime
  bool optional = false;  // a reader accepts logs without it (added after the first logs)
};

// In file order; the header is these names joined by commas after a '#'.
constexpr std::array<FrameLogColumnInfo, kFrameLogColumns> kFrameLogTable = {{
    {"timestamp_ns", FrameLogKind::kCount, 0},
    {"sequence", FrameLogKind::kCount, 0},
    {"state", FrameLogKind::kState, 0},
    {"brightness", FrameLogKind::kBrightness, 0},
    {"mean", FrameLogKind::kNumber, 2},
    {"sigma", FrameLogKind::kNumber, 2},
    {"gamma", FrameLogKind::kNumber, 4},
    {"clip", FrameLogKind::kNumber, 3},
    {"negative", FrameLogKind::kFlag, 0},
    {"features", FrameLogKind::kSmallCount, 0},
    {"inliers", FrameLogKind::kSmallCount, 0},
    {"frame_time_ms", FrameLogKind::kTime, 3},
    {"map_id", FrameLogKind::kCount, 0, true},
    {"keyframes", FrameLogKind::kSmallCount, 0, true},
    {"landmarks", FrameLogKind::kSmallCount, 0, true},
    {"frontend_ms", FrameLogKind::kTime, 3, true},
    {"tracking_ms", FrameLogKind::kTime, 3, true},
    {"mapping_ms", FrameLogKind::kTime, 3, true},
    {"place_ms", FrameLogKind::kTime, 3, true},
    {"loops", FrameLogKind::kSmallCount, 0, true},
    {"loop_ms", FrameLogKind::kTime, 3, true},
    {"merges", FrameLogKind::kSmallCount, 0, true},
    {"merges_refused", FrameLogKind::kSmallCount, 0, true},
}};

// "#timestamp_ns,sequence,...,frame_time_ms"
std::string frame_log_header();

// The field of `row` in column `c`, formatted as the writer writes it, into buf (NUL-terminated);
// the number of characters, or -1 when buf is too small.
int format_frame_log_field(const FrameLogRow& row, FrameLogColumn c, char* buf, std::size_t size);

// Appends rows to a file, one line each, with the header first.
class FrameLogWriter {
 public:
  // kIoError naming the path when it cannot be created.
  Status open(const std::string& path);
  // Nothing when not open.
  Status append(const FrameLogRow& row);
  // Flushes and closes; kIoError if anything written was lost.
  Status close() { return file_.close(); }
  bool is_open() const { return file_.is_open(); }

 private:
  TextFileWriter file_;
};

}  // namespace ale
