#include "app/config.h"

#include <sys/stat.h>

#include <cmath>
#include <exception>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "app/daemon/pose_frames.h"

namespace ale::app {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

// Keys that have moved: an old file gets the new name in its error instead of a bare "unknown key".
struct RenamedKey {
  const char* old_key;
  const char* new_key;
};
constexpr RenamedKey kRenamedKeys[] = {
    {"daemon.process_fps", "slam.process_fps"},
};

constexpr const char* kSources[] = {"v4l2", "replay", nullptr};

constexpr const char* kDistortionModels[] = {"none", "radtan", "equidistant", nullptr};

constexpr ConfigField kIntrinsicsFields[] = {
    number<&CameraConfig::Intrinsics::fx>("fx", 0, 1e5, "focal length x, pixels (0: take the lens from elsewhere)"),
    number<&CameraConfig::Intrinsics::fy>("fy", 0, 1e5, "focal length y, pixels"),
    number<&CameraConfig::Intrinsics::cx>("cx", -1e5, 1e5, "principal point x, pixels"),
    number<&CameraConfig::Intrinsics::cy>("cy", -1e5, 1e5, "principal point y, pixels"),
    text<&CameraConfig::Intrinsics::distortion_model>("distortion_model", "lens distortion", kDistortionModels),
    number<&CameraConfig::Intrinsics::d0>("d0", -10, 10, "radtan k1; equidistant k1"),
    number<&CameraConfig::Intrinsics::d1>("d1", -10, 10, "radtan k2; equidistant k2"),
    number<&CameraConfig::Intrinsics::d2>("d2", -10, 10, "radtan p1; equidistant k3"),
    number<&CameraConfig::Intrinsics::d3>("d3", -10, 10, "radtan p2; equidistant k4"),
};
constexpr ConfigTable kIntrinsicsTable = table_of<CameraConfig::Intrinsics>(kIntrinsicsFields);

constexpr ConfigField kCameraFields[] = {
    text<&CameraConfig::source>("source", "where frames come from", kSources),
    text<&CameraConfig::device>("device", "V4L2 device node"),
    text<&CameraConfig::replay_path>("replay_path", "dataset folder (EuRoC ASL or TUM); required for `replay`"),
    number<&CameraConfig::width>("width", 16, 4096, "requested capture width"),
    number<&CameraConfig::height>("height", 16, 4096, "requested capture height"),
    number<&CameraConfig::fps>("fps", 1, 120, "requested frame rate"),
    number<&CameraConfig::buffers>("buffers", 2, 32, "frame buffers lent between camera and pipeline"),
    number<&CameraConfig::acquire_timeout_ms>("acquire_timeout_ms", 10, 60000,
                                              "a camera silent this long counts as one error"),
    number<&CameraConfig::max_consecutive_errors>("max_consecutive_errors", 1, 100000,
                                                  "then the camera is closed and reopened"),
    number<&CameraConfig::reconnect_initial_ms>("reconnect_initial_ms", 10, 60000,
                                                "first wait before reopening a lost camera (doubles each try)"),
    number<&CameraConfig::reconnect_max_ms>("reconnect_max_ms", 10, 600000, "cap of the wait between reopen tries"),
    number<&CameraConfig::reconnect_give_up_ms>("reconnect_give_up_ms", 0, 86400000,
                                                "exit (status 1; init restarts it) when the camera is not back by then"),
    text<&CameraConfig::calibration_file>("calibration_file",
                                          "EuRoC/Kalibr sensor.yaml of the lens (when no inline intrinsics)"),
    nested<&CameraConfig::intrinsics>("intrinsics", kIntrinsicsTable),
};
constexpr ConfigTable kCameraTable = table_of<CameraConfig>(kCameraFields);

constexpr ConfigField kLcmFields[] = {
    text<&LcmConfig::url>("url", "LCM provider; `ttl=0` keeps traffic on the robot, `memq://` for tests"),
    text<&LcmConfig::pose_channel>("pose_channel", "channel of `ale_lcm.pose_t` (non-empty)"),
    text<&LcmConfig::status_channel>("status_channel", "channel of `ale_lcm.status_t` (non-empty)"),
    text<&LcmConfig::command_channel>("command_channel", "channel of `ale_lcm.command_t` (in; empty: no commands)"),
    text<&LcmConfig::reply_channel>("reply_channel", "channel of `ale_lcm.command_reply_t` (non-empty)"),
};
constexpr ConfigTable kLcmTable = table_of<LcmConfig>(kLcmFields);

constexpr ConfigField kGpioFields[] = {
    text<&GpioConfig::chip>("chip", "e.g. `gpiochip0`; required when a line offset is set"),
    number<&GpioConfig::status_led>("status_led", -1, 1023, "line offset of the status LED (-1: none)"),
    number<&GpioConfig::ir_illuminator>("ir_illuminator", -1, 1023, "line offset of the IR illuminator (-1: none)"),
    flag<&GpioConfig::active_low>("active_low", "lines are active low"),
    number<&GpioConfig::ir_on_dark_frames>("ir_on_dark_frames", 1, 10000,
                                           "IR on after this many consecutive extremely dark frames"),
    number<&GpioConfig::ir_off_normal_frames>("ir_off_normal_frames", 1, 10000,
                                              "IR off after this many consecutive normal or bright frames"),
    number<&GpioConfig::ir_min_toggle_ms>("ir_min_toggle_ms", 0, 3600000,
                                          "the IR illuminator is never switched twice within this (camera time)"),
};
constexpr ConfigTable kGpioTable = table_of<GpioConfig>(kGpioFields);

constexpr const char* kLogLevels[] = {"error", "warning", "info", "debug", nullptr};
constexpr const char* kLogTargets[] = {"stderr", "syslog", nullptr};
constexpr ConfigField kLogFields[] = {
    text<&LogConfig::level>("level", "messages up to this level are logged (a command can change it)", kLogLevels),
    text<&LogConfig::target>("target", "where log messages go", kLogTargets),
};
constexpr ConfigTable kLogTable = table_of<LogConfig>(kLogFields);

constexpr ConfigField kRecorderFields[] = {
    text<&RecorderConfig::dir>("dir", "record the raw frames and the wheel odometry as EuRoC ASL sequences under "
                                      "this folder (empty: off)"),
    number<&RecorderConfig::max_mb>("max_mb", 1, 1 << 20,
                                    "MiB of recordings in dir at most; the oldest sequence goes first"),
    number<&RecorderConfig::queue_frames>("queue_frames", 1, 256,
                                          "frames waiting for the writer at most (a live camera's extra frames are not recorded)"),
    number<&RecorderConfig::png_compression>("png_compression", 0, 9, "zlib level of the PNG files (0 stored .. 9 smallest)"),
};
constexpr ConfigTable kRecorderTable = table_of<RecorderConfig>(kRecorderFields);

constexpr ConfigField kOdometryFields[] = {
    flag<&OdometryConfig::enabled>("enabled", "hand wheel odometry to the SLAM core when a source provides it"),
    text<&OdometryConfig::channel>("channel", "channel of `ale_lcm.odometry_t` (in; empty: none)"),
    number<&OdometryConfig::clock_offset_ms>("clock_offset_ms", -1e6, 1e6, "camera time = MCU time + this, ms"),
    number<&OdometryConfig::lookahead_ms>("lookahead_ms", 0, 1000,
                                          "a replay hands over the samples up to this past each frame's time, ms"),
    text<&OdometryConfig::T_bc>("T_bc",
                                "camera in the base frame, 16 numbers row-major (empty: the dataset's T_BC; LCM needs it)"),
};
constexpr ConfigTable kOdometryTable = table_of<OdometryConfig>(kOdometryFields);

constexpr const char* kBodyFrames[] = {"camera", "calibration", nullptr};
constexpr const char* kTrajectoryPoses[] = {"final", "online", nullptr};

constexpr const char* kEnhancementModes[] = {"ale", "off", "clahe", "he", "gamma", nullptr};  // by features::ExtractorMode

constexpr ConfigField kEnhancementFields[] = {
    choice<&DaemonConfig::Enhancement::mode>("mode", kEnhancementModes,
                                             "ALE (the product); off: the ORB-SLAM3 front end; clahe: CLAHE on every level; he: global histogram equalisation; gamma: the CDF gamma alone"),
};
constexpr ConfigTable kEnhancementTable = table_of<DaemonConfig::Enhancement>(kEnhancementFields);

constexpr ConfigField kRunFields[] = {
    number<&DaemonConfig::Run::max_frames>("max_frames", 0, 1 << 30, "stop after this many frames (0: never)"),
    text<&DaemonConfig::Run::frame_log>("frame_log",
                                        "CSV, one line per frame (core/base/frame_log.h; `ale-eval --report` plots it)"),
    text<&DaemonConfig::Run::trajectory>("trajectory",
                                         "TUM file: one line per frame with a pose, the camera in the map frame"),
    text<&DaemonConfig::Run::trajectory_poses>(
        "trajectory_poses", "final: rewritten at the end with poses relative to keyframes' final poses; online: as published",
        kTrajectoryPoses),
    text<&DaemonConfig::Run::body_frame>("body_frame",
                                         "`calibration`: publish the body pose through the calibration's T_BS too",
                                         kBodyFrames),
    text<&DaemonConfig::Run::vocabulary>("vocabulary",
                                         "place recognition: builtin, none, or a vocabulary file (ale-vocab train)"),
};
constexpr ConfigTable kRunTable = table_of<DaemonConfig::Run>(kRunFields);

constexpr ConfigField kMapFileFields[] = {
    text<&DaemonConfig::MapFile::load>("load", "map file loaded at start: the run relocalises in it (empty: none)"),
    text<&DaemonConfig::MapFile::save>(
        "save", "map file written at the end of the run, every save_period_s, and by SAVE_MAP without a path (empty: none)"),
    number<&DaemonConfig::MapFile::save_period_s>("save_period_s", 0, 86400,
                                                  "also save map.save this often while running, seconds (0: never)"),
};
constexpr ConfigTable kMapFileTable = table_of<DaemonConfig::MapFile>(kMapFileFields);

// Not constexpr: the features' table comes from the core by function.
const ConfigField kDaemonFields[] = {
    nested<&DaemonConfig::camera>("camera", kCameraTable),
    nested<&DaemonConfig::lcm>("lcm", kLcmTable),
    nested<&DaemonConfig::gpio>("gpio", kGpioTable),
    nested<&DaemonConfig::log>("log", kLogTable),
    nested<&DaemonConfig::recorder>("recorder", kRecorderTable),
    nested<&DaemonConfig::odometry>("odometry", kOdometryTable),
    nested<&DaemonConfig::daemon>("daemon", kRunTable),
    nested<&DaemonConfig::map>("map", kMapFileTable),
    nested<&DaemonConfig::enhancement>("enhancement", kEnhancementTable),
    nested<&DaemonConfig::features>("features", ale::features::extractor_config_table()),
    nested<&DaemonConfig::slam>("slam", ale::slam::slam_config_table()),
};
const ConfigTable kDaemonTable = table_of<DaemonConfig>(kDaemonFields);

}  // namespace

const ConfigTable& config_table() { return kDaemonTable; }

Status parse_config(const std::string& text, const std::string& origin, DaemonConfig& config) {
  DaemonConfig parsed = config;  // the caller's config changes only if the whole file is valid
  std::istringstream in(text);
  std::string line;
  std::string section;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string where_line = origin + ":" + std::to_string(line_no);
    const auto hash = line.find('#');
    line = trim(hash == std::string::npos ? line : line.substr(0, hash));
    if (line.empty()) continue;
    if (line.front() == '[') {
      if (line.back() != ']' || line.size() < 3) return invalid_argument(where_line + ": malformed section header");
      section = trim(line.substr(1, line.size() - 2));
      continue;
    }
    const auto eq = line.find('=');
    if (eq == std::string::npos) return invalid_argument(where_line + ": expected 'key = value'");
    const std::string key = trim(line.substr(0, eq));
    std::string value = trim(line.substr(eq + 1));
    if (value.size() >= 2 && value.front() == '"' && value.back() == '"') value = value.substr(1, value.size() - 2);
    const std::string full = section.empty() ? key : section + "." + key;
    Status s = set_field(kDaemonTable, &parsed, full, value, where_line + ": " + full);
    if (s.code() == StatusCode::kNotFound) {
      for (const RenamedKey& r : kRenamedKeys)
        if (full == r.old_key)
          return invalid_argument(where_line + ": '" + full + "' is now '" + r.new_key + "' (rename the key)");
      return invalid_argument(where_line + ": unknown key '" + full + "'");
    }
    ALE_RETURN_IF_ERROR(s);
  }
  ALE_RETURN_IF_ERROR(validate_config(parsed));
  config = parsed;
  return {};
}

Status load_config(const std::string& path, DaemonConfig& config) {
  // A directory opens as a stream that reads nothing, which would parse as an empty file.
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode))
    return invalid_argument("config file " + path + " is not a regular file");
  std::ifstream in(path, std::ios::binary);
  if (!in) return not_found("config file " + path + " cannot be opened");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) return io_error("config file " + path + " cannot be read");
  return parse_config(text, path, config);
}

Status validate_config(const DaemonConfig& c) {
  // The app's own tables' ranges here; the core's structs (features.*, slam.*) by their own
  // validate() below, which checks their tables' ranges and their cross-field rules: each key is
  // checked once.
  const ConfigTable& features_table = ale::features::extractor_config_table();
  const ConfigTable& slam_table = ale::slam::slam_config_table();
  for (const ConfigField& f : kDaemonFields) {
    if (f.table == &features_table || f.table == &slam_table) continue;
    ALE_RETURN_IF_ERROR(check_ranges(*f.table, f.at(const_cast<DaemonConfig*>(&c)), std::string(f.key) + "."));
  }
  if (c.camera.source == "replay" && c.camera.replay_path.empty())
    return invalid_argument("camera.replay_path: required when camera.source = replay");
  if (c.lcm.pose_channel.empty() || c.lcm.status_channel.empty() || c.lcm.reply_channel.empty())
    return invalid_argument("lcm.pose_channel / lcm.status_channel / lcm.reply_channel must not be empty");
  if (c.camera.reconnect_max_ms < c.camera.reconnect_initial_ms)
    return invalid_argument("camera.reconnect_max_ms: must be >= camera.reconnect_initial_ms");
  if (c.map.save_period_s > 0.0 && c.map.save.empty())
    return invalid_argument("map.save_period_s: needs map.save, the file saved to");
  if ((c.gpio.status_led >= 0 || c.gpio.ir_illuminator >= 0) && c.gpio.chip.empty())
    return invalid_argument("gpio.chip: required when a GPIO line offset is set");
  if (Status s = ale::features::validate(c.features); !s.ok()) return invalid_argument("features." + s.message());
  ALE_RETURN_IF_ERROR(ale::slam::validate(c.slam));
  if (Result<std::optional<std::array<double, 16>>> t = parse_T_bc(c.odometry.T_bc); !t.ok()) return t.status();
  const CameraConfig::Intrinsics& k = c.camera.intrinsics;
  if (k.fx > 0.0 && !(k.fy > 0.0))
    return invalid_argument("camera.intrinsics.fy: required (> 0) when camera.intrinsics.fx is set");
  return {};
}

Result<std::optional<std::array<double, 16>>> parse_T_bc(const std::string& text) {
  std::string spaced = text;
  for (char& ch : spaced)
    if (ch == ',' || ch == '\t') ch = ' ';
  std::istringstream in(spaced);
  std::vector<std::string> words{std::istream_iterator<std::string>(in), std::istream_iterator<std::string>()};
  if (words.empty()) return std::optional<std::array<double, 16>>();
  if (words.size() != 16)
    return invalid_argument("odometry.T_bc: expected 16 numbers (4x4 row-major), found " + std::to_string(words.size()));
  std::array<double, 16> m{};
  for (std::size_t i = 0; i < 16; ++i) {
    std::size_t used = 0;
    try {
      m[i] = std::stod(words[i], &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != words[i].size() || !std::isfinite(m[i]))
      return invalid_argument("odometry.T_bc: '" + words[i] + "' is not a number");
  }
  if (m[12] != 0.0 || m[13] != 0.0 || m[14] != 0.0 || m[15] != 1.0 || !rigid_from_row_major(m))
    return invalid_argument("odometry.T_bc: not a rigid transform (a rotation, a translation, last row 0 0 0 1)");
  return std::optional<std::array<double, 16>>(m);
}

std::string print_config(const DaemonConfig& config) {
  std::string out;
  std::string section;
  for_each_field(kDaemonTable, &config, "", [&](const std::string& key, const ConfigField& f, const void* owner) {
    const std::size_t dot = key.find('.');
    const std::string top = key.substr(0, dot);
    if (top != section) {
      out += (section.empty() ? "[" : "\n[") + top + "]\n";
      section = top;
    }
    const std::string value = format_field(f, owner);
    const bool quote = value.empty() || value.find_first_of("# \t") != std::string::npos;
    out += key.substr(dot + 1) + " = " + (quote ? "\"" + value + "\"" : value) + "\n";
  });
  return out;
}

std::string config_reference_markdown() {
  std::string out = "| key | default | range / values | meaning |\n|---|---|---|---|\n";
  for_each_field(kDaemonTable, kDaemonTable.defaults, "",
                 [&](const std::string& key, const ConfigField& f, const void* owner) {
                   const std::string value = format_field(f, owner);
                   std::string range = range_of(f);  // "a|b" would split the markdown row
                   for (std::size_t bar = range.find('|'); bar != std::string::npos; bar = range.find('|'))
                     range.replace(bar, 1, ", ");
                   out += "| `" + key + "` | " + (value.empty() ? "(none)" : "`" + value + "`") + " | " + range +
                          " | " + f.help + " |\n";
                 });
  return out;
}

}  // namespace ale::app
