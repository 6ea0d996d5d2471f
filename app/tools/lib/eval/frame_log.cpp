#include "app/tools/lib/eval/frame_log.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "app/tools/lib/eval/text.h"

namespace ale::eval {
namespace {

using Column = FrameLogColumn;
constexpr std::size_t kColumnCount = kFrameLogColumns;
constexpr std::size_t kUnset = std::numeric_limits<std::size_t>::max();

// A whole number >= 0 written in decimal digits only.
bool parse_count(std::string_view token, std::uint64_t* value) {
  if (token.empty() || !std::all_of(token.begin(), token.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    return false;
  }
  const std::string copy(token);
  errno = 0;
  *value = std::strtoull(copy.c_str(), nullptr, 10);
  return errno == 0;
}

class Parser {
 public:
  explicit Parser(const std::string& name) : name_(name) {
    log_.name = name;
    index_.fill(kUnset);
  }

  Status line(std::size_t line_no, std::string_view raw) {
    std::string_view line = trim(raw);
    if (line.empty()) return Status::ok_status();
    if (header_columns_ == 0) return header(line_no, line);
    if (line.front() == '#') return Status::ok_status();  // a comment after the header
    const std::vector<std::string_view> fields = split_commas(line);
    if (fields.size() != header_columns_) {
      return corrupt_data(where(name_, line_no) + std::to_string(fields.size()) + " columns, the header has " +
                          std::to_string(header_columns_));
    }
    FrameRecord r;
    for (std::size_t c = 0; c < kColumnCount; ++c) {
      if (index_[c] != kUnset) ALE_RETURN_IF_ERROR(field(line_no, fields, Column(c), r));  // else optional: 0
    }
    const std::uint64_t timestamp_ns = r.timestamp_ns;
    if (!log_.frames.empty() && timestamp_ns <= last_timestamp_ns_) {
      return corrupt_data(where(name_, line_no) + "timestamp_ns " + std::to_string(timestamp_ns) +
                          " is not later than " + std::to_string(last_timestamp_ns_) + " on line " +
                          std::to_string(last_line_) + " (timestamps must increase)");
    }
    last_timestamp_ns_ = timestamp_ns;
    last_line_ = line_no;
    log_.frames.push_back(r);
    return Status::ok_status();
  }

  Result<FrameLog> finish() && {
    if (header_columns_ == 0) return corrupt_data(name_ + ": empty file, expected a frame log header");
    if (log_.frames.empty()) return corrupt_data(name_ + ": no frames in the log");
    return std::move(log_);
  }

 private:
  Status header(std::size_t line_no, std::string_view line) {
    if (line.front() == '#') line.remove_prefix(1);
    const std::vector<std::string_view> names = split_commas(line);
    for (std::size_t i = 0; i < names.size(); ++i) {
      const auto known = std::find_if(kFrameLogTable.begin(), kFrameLogTable.end(),
                                      [&](const FrameLogColumnInfo& column) { return names[i] == column.name; });
      if (known == kFrameLogTable.end()) continue;  // a column this reader does not know
      std::size_t& index = index_[static_cast<std::size_t>(known - kFrameLogTable.begin())];
      if (index != kUnset) {
        return corrupt_data(where(name_, line_no) + "column '" + std::string(names[i]) + "' appears twice");
      }
      index = i;
    }
    for (std::size_t c = 0; c < kColumnCount; ++c) {
      if (index_[c] == kUnset && !kFrameLogTable[c].optional) {
        return corrupt_data(where(name_, line_no) + "header has no column '" + kFrameLogTable[c].name +
                            "' (is this an ale-slamd --frame-log file?)");
      }
    }
    header_columns_ = names.size();
    log_.has_slam_columns = true;
    for (std::size_t c = static_cast<std::size_t>(Column::kMapId); c <= static_cast<std::size_t>(Column::kMappingMs); ++c) {
      if (index_[c] == kUnset) log_.has_slam_columns = false;
    }
    log_.has_place_column = has(Column::kPlaceMs);
    log_.has_loop_columns = has(Column::kLoops) && has(Column::kLoopMs);
    log_.has_merge_columns = has(Column::kMerges) && has(Column::kMergesRefused);
    return Status::ok_status();
  }

  static const FrameLogColumnInfo& info(Column c) { return kFrameLogTable[static_cast<std::size_t>(c)]; }
  bool has(Column c) const { return index_[static_cast<std::size_t>(c)] != kUnset; }
  std::string_view text(const std::vector<std::string_view>& fields, Column c) const {
    return fields[index_[static_cast<std::size_t>(c)]];
  }

  // Column c of the line into its member of r, checked by the column's kind.
  Status field(std::size_t line_no, const std::vector<std::string_view>& fields, Column c, FrameRecord& r) const {
    std::uint64_t count_value = 0;
    int small = 0;
    double number_value = 0.0;
    switch (info(c).kind) {
      case FrameLogKind::kCount:
        ALE_RETURN_IF_ERROR(count(line_no, fields, c, &count_value));
        break;
      case FrameLogKind::kFlag:
        ALE_RETURN_IF_ERROR(count(line_no, fields, c, &count_value));
        if (count_value > 1) return bad_value(line_no, fields, c, "0 or 1");
        break;
      case FrameLogKind::kSmallCount:
        ALE_RETURN_IF_ERROR(small_count(line_no, fields, c, &small));
        break;
      case FrameLogKind::kNumber:
        ALE_RETURN_IF_ERROR(number(line_no, fields, c, &number_value));
        break;
      case FrameLogKind::kTime:
        ALE_RETURN_IF_ERROR(number(line_no, fields, c, &number_value));
        if (number_value < 0.0) return bad_value(line_no, fields, c, "a time >= 0");
        break;
      case FrameLogKind::kState:
        return name_field(line_no, fields, c, parse_tracking_state, &r.state);
      case FrameLogKind::kBrightness:
        return name_field(line_no, fields, c, parse_brightness_class, &r.brightness);
    }
    switch (c) {
      case Column::kTimestampNs: r.timestamp_ns = count_value; break;
      case Column::kSequence: r.sequence = count_value; break;
      case Column::kMean: r.mean = number_value; break;
      case Column::kSigma: r.sigma = number_value; break;
      case Column::kGamma: r.gamma = number_value; break;
      case Column::kClip: r.clip = number_value; break;
      case Column::kNegative: r.negative = count_value == 1; break;
      case Column::kFeatures: r.features = small; break;
      case Column::kInliers: r.inliers = small; break;
      case Column::kFrameTimeMs: r.frame_time_ms = number_value; break;
      case Column::kMapId: r.map_id = count_value; break;
      case Column::kKeyframes: r.keyframes = small; break;
      case Column::kLandmarks: r.landmarks = small; break;
      case Column::kFrontendMs: r.frontend_ms = number_value; break;
      case Column::kTrackingMs: r.tracking_ms = number_value; break;
      case Column::kMappingMs: r.mapping_ms = number_value; break;
      case Column::kPlaceMs: r.place_ms = number_value; break;
      case Column::kLoops: r.loops = small; break;
      case Column::kLoopMs: r.loop_ms = number_value; break;
      case Column::kMerges: r.merges = small; break;
      case Column::kMergesRefused: r.merges_refused = small; break;
      case Column::kState:
      case Column::kBrightness:
      case Column::kCount: break;  // names are stored above; kCount is no column
    }
    return Status::ok_status();
  }

  Status bad_value(std::size_t line_no, const std::vector<std::string_view>& fields, Column c,
                   const char* expected) const {
    return corrupt_data(where(name_, line_no) + info(c).name + " '" + std::string(text(fields, c)) +
                        "' is not " + expected);
  }

  Status number(std::size_t line_no, const std::vector<std::string_view>& fields, Column c, double* out) const {
    if (!parse_double(text(fields, c), out) || !std::isfinite(*out)) {
      return bad_value(line_no, fields, c, "a finite number");
    }
    return Status::ok_status();
  }

  Status count(std::size_t line_no, const std::vector<std::string_view>& fields, Column c,
               std::uint64_t* out) const {
    if (!parse_count(text(fields, c), out)) return bad_value(line_no, fields, c, "a whole number >= 0");
    return Status::ok_status();
  }

  Status small_count(std::size_t line_no, const std::vector<std::string_view>& fields, Column c, int* out) const {
    std::uint64_t value = 0;
    ALE_RETURN_IF_ERROR(count(line_no, fields, c, &value));
    if (value > static_cast<std::uint64_t>(std::numeric_limits<int>::max())) {
      return bad_value(line_no, fields, c, "a plausible count");
    }
    *out = static_cast<int>(value);
    return Status::ok_status();
  }

  template <class T, class Parse>
  Status name_field(std::size_t line_no, const std::vector<std::string_view>& fields, Column c, Parse parse,
                    T* out) const {
    Result<T> parsed = parse(text(fields, c));
    if (!parsed.ok()) return corrupt_data(where(name_, line_no) + parsed.status().message());
    *out = *parsed;
    return Status::ok_status();
  }

  const std::string& name_;
  FrameLog log_;
  std::array<std::size_t, kColumnCount> index_{};
  std::size_t header_columns_ = 0;
  std::uint64_t last_timestamp_ns_ = 0;
  std::size_t last_line_ = 0;
};

template <class Enum, std::size_t N>
Result<Enum> parse_enum(std::string_view name, const std::array<Enum, N>& values, const char* what) {
  std::string names;
  for (Enum v : values) {
    if (name == to_string(v)) return v;
    names += names.empty() ? "" : ", ";
    names += to_string(v);
  }
  return invalid_argument("unknown " + std::string(what) + " '" + std::string(name) + "' (expected " + names + ")");
}

}  // namespace

Result<BrightnessClass> parse_brightness_class(std::string_view name) {
  return parse_enum(name,
                    std::array<BrightnessClass, kBrightnessClasses>{BrightnessClass::kExtremelyDark, BrightnessClass::kDark,
                                                                    BrightnessClass::kNormal, BrightnessClass::kBright},
                    "brightness class");
}

Result<TrackingState> parse_tracking_state(std::string_view name) {
  return parse_enum(name,
                    std::array<TrackingState, 5>{TrackingState::kNotInitialized, TrackingState::kInitializing,
                                                 TrackingState::kTracking, TrackingState::kLost,
                                                 TrackingState::kRelocalized},
                    "tracking state");
}

Result<FrameLog> parse_frame_log(std::string_view text, const std::string& name) {
  Parser parser(name);
  ALE_RETURN_IF_ERROR(for_each_line(
      text, [&](std::size_t line_no, std::string_view line) { return parser.line(line_no, line); }));
  return std::move(parser).finish();
}

Result<FrameLog> read_frame_log(const std::string& path) {
  Result<std::string> content = read_text_file(path, "frame log");
  if (!content.ok()) return content.status();
  return parse_frame_log(*content, path);
}

namespace {

// How far the running count `count` of frame i is above its predecessor's (the first frame's
// above 0); 0 when it did not rise.
int rise_at(const FrameLog& log, std::size_t i, int FrameRecord::*count) {
  const int before = i > 0 ? log.frames[i - 1].*count : 0;
  return std::max(0, log.frames[i].*count - before);
}

}  // namespace

int loops_closed_at(const FrameLog& log, std::size_t i) { return rise_at(log, i, &FrameRecord::loops); }

int merges_at(const FrameLog& log, std::size_t i) { return rise_at(log, i, &FrameRecord::merges); }

FrameLogSummary summarize(const FrameLog& log) {
  FrameLogSummary s;
  s.frames = log.frames.size();
  if (s.frames == 0) return s;
  double features_sum = 0.0;
  double via_sum = 0.0;
  double time_sum = 0.0;
  std::vector<double> times;
  times.reserve(s.frames);
  for (std::size_t i = 0; i < s.frames; ++i) {
    const FrameRecord& f = log.frames[i];
    s.brightness_share[static_cast<std::size_t>(f.brightness)] += 1.0;
    features_sum += f.features;
    if (f.inliers >= kViaMinInliers) {
      via_sum += f.inliers;
      ++s.via_frames;
    }
    time_sum += f.frame_time_ms;
    times.push_back(f.frame_time_ms);
    if (i > 0 && f.state == TrackingState::kLost && log.frames[i - 1].state != TrackingState::kLost) {
      ++s.tracking_losses;
    }
    if (has_pose(f.state)) s.tracked_share += 1.0;
    if (f.state == TrackingState::kRelocalized) ++s.relocalisations;
    const int merged = merges_at(log, i);
    // A merge moves the frame into an older map: no new map.
    if (i == 0 || (f.map_id != log.frames[i - 1].map_id && merged == 0)) ++s.maps;
    s.merges += static_cast<std::size_t>(merged);
    s.merges_refused += static_cast<std::size_t>(rise_at(log, i, &FrameRecord::merges_refused));
    s.frontend_mean_ms += f.frontend_ms;
    s.tracking_mean_ms += f.tracking_ms;
    s.mapping_mean_ms += f.mapping_ms;
    s.place_mean_ms += f.place_ms;
    s.place_max_ms = std::max(s.place_max_ms, f.place_ms);
    s.loop_mean_ms += f.loop_ms;
    s.loop_max_ms = std::max(s.loop_max_ms, f.loop_ms);
    const int closed = loops_closed_at(log, i);
    s.loops_closed += static_cast<std::size_t>(closed);
    if (closed > 0) s.loop_frame_time_max_ms = std::max(s.loop_frame_time_max_ms, f.frame_time_ms);
  }
  s.loops_logged = log.has_loop_columns;
  s.merges_logged = log.has_merge_columns;
  s.keyframes_last = log.frames.back().keyframes;
  s.landmarks_last = log.frames.back().landmarks;
  const double n = static_cast<double>(s.frames);
  for (double& share : s.brightness_share) share /= n;
  s.features_mean = features_sum / n;
  s.tracked_share /= n;
  s.frontend_mean_ms /= n;
  s.tracking_mean_ms /= n;
  s.mapping_mean_ms /= n;
  s.place_mean_ms /= n;
  s.loop_mean_ms /= n;
  s.via = s.via_frames > 0 ? via_sum / static_cast<double>(s.via_frames) : std::nan("");
  s.frame_time_mean_ms = time_sum / n;
  std::sort(times.begin(), times.end());
  const std::size_t mid = s.frames / 2;
  s.frame_time_median_ms = s.frames % 2 == 1 ? times[mid] : 0.5 * (times[mid - 1] + times[mid]);
  const auto rank = static_cast<std::size_t>(std::ceil(0.95 * n));
  s.frame_time_p95_ms = times[std::max<std::size_t>(rank, 1) - 1];
  s.frame_time_max_ms = times.back();
  return s;
}

}  // namespace ale::eval
