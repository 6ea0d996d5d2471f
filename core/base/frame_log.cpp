#include "core/base/frame_log.h"

namespace ale {

std::string frame_log_header() {
  std::string header = "#";
  for (std::size_t c = 0; c < kFrameLogColumns; ++c) header += std::string(c ? "," : "") + kFrameLogTable[c].name;
  return header;
}

int format_frame_log_field(const FrameLogRow& r, FrameLogColumn c, char* buf, std::size_t size) {
  const FrameLogColumnInfo& info = kFrameLogTable[static_cast<std::size_t>(c)];
  double number = 0.0;
  unsigned long long count = 0;
  const char* name = nullptr;
  switch (c) {
    case FrameLogColumn::kTimestampNs: count = r.timestamp_ns; break;
    case FrameLogColumn::kSequence: count = r.sequence; break;
    case FrameLogColumn::kState: name = to_string(r.state); break;
    case FrameLogColumn::kBrightness: name = to_string(r.brightness); break;
    case FrameLogColumn::kMean: number = r.mean; break;
    case FrameLogColumn::kSigma: number = r.sigma; break;
    case FrameLogColumn::kGamma: number = r.gamma; break;
    case FrameLogColumn::kClip: number = r.clip; break;
    case FrameLogColumn::kNegative: count = r.negative ? 1 : 0; break;
    case FrameLogColumn::kFeatures: count = static_cast<unsigned long long>(r.features); break;
    case FrameLogColumn::kInliers: count = static_cast<unsigned long long>(r.inliers); break;
    case FrameLogColumn::kFrameTimeMs: number = r.frame_time_ms; break;
    case FrameLogColumn::kMapId: count = r.map_id; break;
    case FrameLogColumn::kKeyframes: count = static_cast<unsigned long long>(r.keyframes); break;
    case FrameLogColumn::kLandmarks: count = static_cast<unsigned long long>(r.landmarks); break;
    case FrameLogColumn::kFrontendMs: number = r.frontend_ms; break;
    case FrameLogColumn::kTrackingMs: number = r.tracking_ms; break;
    case FrameLogColumn::kMappingMs: number = r.mapping_ms; break;
    case FrameLogColumn::kPlaceMs: number = r.place_ms; break;
    case FrameLogColumn::kLoops: count = static_cast<unsigned long long>(r.loops); break;
    case FrameLogColumn::kLoopMs: number = r.loop_ms; break;
    case FrameLogColumn::kMerges: count = static_cast<unsigned long long>(r.merges); break;
    case FrameLogColumn::kMergesRefused: count = static_cast<unsigned long long>(r.merges_refused); break;
    case FrameLogColumn::kCount: return -1;
  }
  int n = -1;
  switch (info.kind) {
    case FrameLogKind::kCount:
    case FrameLogKind::kSmallCount:
    case FrameLogKind::kFlag: n = std::snprintf(buf, size, "%llu", count); break;
    case FrameLogKind::kNumber:
    case FrameLogKind::kTime: n = std::snprintf(buf, size, "%.*f", info.decimals, number); break;
    case FrameLogKind::kState:
    case FrameLogKind::kBrightness: n = std::snprintf(buf, size, "%s", name); break;
  }
  return n >= 0 && static_cast<std::size_t>(n) < size ? n : -1;
}

Status FrameLogWriter::open(const std::string& path) {
  ALE_RETURN_IF_ERROR(file_.open(path, "frame log"));
  return file_.write(frame_log_header() + "\n");
}

Status FrameLogWriter::append(const FrameLogRow& row) {
  if (!file_.is_open()) return {};
  char line[512];
  std::size_t used = 0;
  for (std::size_t c = 0; c < kFrameLogColumns; ++c) {
    if (c > 0) line[used++] = ',';
    const int n = format_frame_log_field(row, static_cast<FrameLogColumn>(c), line + used, sizeof line - used - 2);
    if (n < 0) return internal_error(file_.name() + ": a row longer than " + std::to_string(sizeof line));
    used += static_cast<std::size_t>(n);
  }
  line[used++] = '\n';
  return file_.write(line, used);
}

}  // namespace ale
