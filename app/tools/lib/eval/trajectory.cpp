#include "app/tools/lib/eval/trajectory.h"

#include <Eigen/Geometry>

#include <cmath>
#include <sstream>

#include "app/tools/lib/eval/text.h"

namespace ale::eval {
namespace {

constexpr std::size_t kTumColumns = 8;
constexpr std::size_t kKittiColumns = 12;
constexpr std::size_t kEurocMinColumns = 8;  // timestamp, position, quaternion
constexpr double kNsPerS = 1e9;

std::vector<std::string_view> split_fields(std::string_view line, TrajectoryFormat format) {
  return format == TrajectoryFormat::kEuroc ? split_commas(line) : split_whitespace(line);
}

bool is_comment(std::string_view line) { return !line.empty() && line.front() == '#'; }

// `# lost <t>`: returns true and the time when the comment is a loss marker.
bool parse_loss_marker(std::string_view comment, double* t) {
  comment.remove_prefix(1);
  const std::vector<std::string_view> words = split_whitespace(comment);
  return words.size() == 2 && words[0] == "lost" && parse_double(words[1], t);
}

class Parser {
 public:
  Parser(TrajectoryFormat format, bool skip_duplicates, const std::string& name)
      : format_(format), skip_duplicates_(skip_duplicates), name_(name) {
    trajectory_.name = name;
    trajectory_.format = format;
  }

  Status line(std::size_t line_no, std::string_view raw) {
    const std::string_view line = trim(raw);
    if (line.empty()) return Status::ok_status();
    if (is_comment(line)) return comment(line_no, line);
    const std::vector<std::string_view> fields = split_fields(line, format_);
    std::vector<double> values(fields.size());
    for (std::size_t i = 0; i < fields.size(); ++i) {
      if (!parse_double(fields[i], &values[i])) {
        // A CSV header without the leading '#' is tolerated as the first line of an EuRoC file.
        if (format_ == TrajectoryFormat::kEuroc && data_lines_ == 0 && i == 0 && !header_seen_) {
          header_seen_ = true;
          return Status::ok_status();
        }
        return corrupt_data(where(name_, line_no) + "column " + std::to_string(i + 1) + " '" +
                            std::string(fields[i]) + "' is not a number");
      }
      if (!std::isfinite(values[i])) {
        return corrupt_data(where(name_, line_no) + "column " + std::to_string(i + 1) +
                            " is not finite (" + std::string(fields[i]) + ")");
      }
    }
    ALE_RETURN_IF_ERROR(check_columns(line_no, values.size()));
    StampedPose pose;
    ALE_RETURN_IF_ERROR(fill_pose(line_no, values, &pose));
    if (!trajectory_.poses.empty()) {
      const double previous = trajectory_.poses.back().t_s;
      if (pose.t_s == previous) {
        if (skip_duplicates_) {
          ++trajectory_.duplicates_skipped;
          return Status::ok_status();
        }
        return corrupt_data(where(name_, line_no) + "duplicate timestamp " + format_time(pose.t_s) +
                            " (same as line " + std::to_string(last_pose_line_) +
                            "; --duplicates skip keeps the first)");
      }
      if (pose.t_s < previous) {
        return corrupt_data(where(name_, line_no) + "timestamp " + format_time(pose.t_s) +
                            " is earlier than " + format_time(previous) + " on line " +
                            std::to_string(last_pose_line_) + " (timestamps must increase)");
      }
    }
    trajectory_.poses.push_back(pose);
    last_pose_line_ = line_no;
    ++data_lines_;
    return Status::ok_status();
  }

  Result<Trajectory> finish() && {
    if (trajectory_.poses.empty()) return corrupt_data(name_ + ": no poses in the file");
    return std::move(trajectory_);
  }

 private:
  Status comment(std::size_t line_no, std::string_view line) {
    double t = 0.0;
    if (format_ == TrajectoryFormat::kKitti || !parse_loss_marker(line, &t)) return Status::ok_status();
    if (!std::isfinite(t)) return corrupt_data(where(name_, line_no) + "loss marker time is not finite");
    trajectory_.loss_marks_s.push_back(format_ == TrajectoryFormat::kEuroc ? t / kNsPerS : t);
    return Status::ok_status();
  }

  Status check_columns(std::size_t line_no, std::size_t columns) {
    std::size_t expected = 0;
    const char* what = "";
    switch (format_) {
      case TrajectoryFormat::kTum:
        expected = kTumColumns;
        what = "TUM needs 8: t tx ty tz qx qy qz qw";
        break;
      case TrajectoryFormat::kKitti:
        expected = kKittiColumns;
        what = "KITTI needs 12: a row-major 3x4 pose";
        break;
      case TrajectoryFormat::kEuroc:
        // Every row must have as many columns as the first one (8 for pose-only files, 17 for
        // the full state CSV).
        if (columns < kEurocMinColumns) {
          return corrupt_data(where(name_, line_no) + std::to_string(columns) +
                              " columns, EuRoC needs at least 8: t_ns, p xyz, q wxyz");
        }
        if (euroc_columns_ == 0) euroc_columns_ = columns;
        expected = euroc_columns_;
        what = "as many as the first data line";
        break;
      case TrajectoryFormat::kAuto:
        return internal_error("parser called with format auto");
    }
    if (columns != expected) {
      return corrupt_data(where(name_, line_no) + std::to_string(columns) + " columns, expected " +
                          std::to_string(expected) + " (" + what + ")");
    }
    return Status::ok_status();
  }

  Status fill_pose(std::size_t line_no, const std::vector<double>& v, StampedPose* pose) const {
    if (format_ == TrajectoryFormat::kKitti) {
      pose->t_s = static_cast<double>(data_lines_);
      pose->R_wb << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
      pose->p_wb << v[3], v[7], v[11];
      return Status::ok_status();
    }
    const bool euroc = format_ == TrajectoryFormat::kEuroc;
    pose->t_s = euroc ? v[0] / kNsPerS : v[0];
    pose->p_wb << v[1], v[2], v[3];
    const Eigen::Quaterniond q = euroc ? Eigen::Quaterniond(v[4], v[5], v[6], v[7])
                                       : Eigen::Quaterniond(v[7], v[4], v[5], v[6]);
    const double norm = q.norm();
    if (norm < 1e-9) return corrupt_data(where(name_, line_no) + "quaternion has zero length");
    pose->R_wb = Eigen::Quaterniond(q.coeffs() / norm).toRotationMatrix();
    return Status::ok_status();
  }

  std::string format_time(double t_s) const {
    std::ostringstream out;
    out.precision(format_ == TrajectoryFormat::kKitti ? 6 : 17);
    if (format_ == TrajectoryFormat::kEuroc) {
      out << t_s * kNsPerS << " ns";
    } else {
      out << t_s << " s";
    }
    return out.str();
  }

  TrajectoryFormat format_;
  bool skip_duplicates_;
  const std::string& name_;
  Trajectory trajectory_;
  std::size_t data_lines_ = 0;
  std::size_t last_pose_line_ = 0;
  std::size_t euroc_columns_ = 0;
  bool header_seen_ = false;
};

}  // namespace

const char* to_string(TrajectoryFormat format) {
  switch (format) {
    case TrajectoryFormat::kAuto: return "auto";
    case TrajectoryFormat::kTum: return "tum";
    case TrajectoryFormat::kEuroc: return "euroc";
    case TrajectoryFormat::kKitti: return "kitti";
  }
  return "?";
}

Result<TrajectoryFormat> parse_format(std::string_view name) {
  for (TrajectoryFormat f : {TrajectoryFormat::kAuto, TrajectoryFormat::kTum,
                             TrajectoryFormat::kEuroc, TrajectoryFormat::kKitti}) {
    if (name == to_string(f)) return f;
  }
  return invalid_argument("unknown trajectory format '" + std::string(name) +
                          "' (expected tum, euroc, kitti or auto)");
}

Result<TrajectoryFormat> detect_format(std::string_view text, const std::string& name) {
  Result<TrajectoryFormat> found = corrupt_data(name + ": no poses in the file");
  bool decided = false;
  const Status walked = for_each_line(text, [&](std::size_t line_no, std::string_view raw) {
    const std::string_view line = trim(raw);
    if (decided || line.empty() || is_comment(line)) return Status::ok_status();
    decided = true;
    if (line.find(',') != std::string_view::npos) {
      found = TrajectoryFormat::kEuroc;
      return Status::ok_status();
    }
    const std::size_t columns = split_whitespace(line).size();
    if (columns == kTumColumns) {
      found = TrajectoryFormat::kTum;
    } else if (columns == kKittiColumns) {
      found = TrajectoryFormat::kKitti;
    } else {
      found = corrupt_data(where(name, line_no) + "cannot tell the format from " +
                           std::to_string(columns) +
                           " columns (TUM has 8, KITTI 12, EuRoC is comma-separated); "
                           "give --format");
    }
    return Status::ok_status();
  });
  if (!walked.ok()) return walked;
  return found;
}

Result<Trajectory> parse_trajectory(std::string_view text, const ReadOptions& options,
                                    const std::string& name) {
  TrajectoryFormat format = options.format;
  if (format == TrajectoryFormat::kAuto) {
    Result<TrajectoryFormat> detected = detect_format(text, name);
    if (!detected.ok()) return detected.status();
    format = *detected;
  }
  Parser parser(format, options.skip_duplicate_times, name);
  ALE_RETURN_IF_ERROR(for_each_line(
      text, [&](std::size_t line_no, std::string_view line) { return parser.line(line_no, line); }));
  return std::move(parser).finish();
}

Result<Trajectory> read_trajectory(const std::string& path, const ReadOptions& options) {
  Result<std::string> content = read_text_file(path, "trajectory file");
  if (!content.ok()) return content.status();
  return parse_trajectory(*content, options, path);
}

}  // namespace ale::eval
