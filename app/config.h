// ale-slamd's configuration: plain structs with their defaults in one place, and one table of
// their keys (config_table(); core/base/config_table.h) that the parser, --print-config,
// docs/configuration.md and the core's validate() read. Keys are the members' paths
// (features.enhance.clahe.clip_base is DaemonConfig::features.enhance.clahe.clip_base). The file
// is parsed and validated once at start-up (unknown keys and out-of-range values are rejected with
// a message naming the line and the key); the core never sees the file.
#pragma once

#include <array>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "core/features/orb.h"
#include "core/slam/system.h"

namespace ale::app {

struct CameraConfig {
  std::string source = "v4l2";        // v4l2 | replay
  std::string device = "/dev/video0"; // v4l2 device node
  std::string replay_path;            // dataset folder (EuRoC ASL or TUM layout) for source=replay
  int width = 640;
  int height = 480;
  int fps = 30;
  int buffers = 4;
  int acquire_timeout_ms = 1000;      // a camera silent this long counts as a timeout
  int max_consecutive_errors = 30;    // then the camera is reopened (or the daemon stops)
  // Reopening a camera that went away: waits double from the first to the cap; the daemon exits
  // (status 1, procd restarts it) when the camera has not come back after give_up_ms.
  int reconnect_initial_ms = 250;
  int reconnect_max_ms = 4000;
  int reconnect_give_up_ms = 60000;
  // The lens, in this order of precedence: the inline intrinsics (when fx > 0), the calibration
  // file, what the camera itself reports (a EuRoC replay: its sensor.yaml). The SLAM core needs
  // one of them.
  std::string calibration_file;       // EuRoC/Kalibr sensor.yaml
  struct Intrinsics {
    double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;  // pixels
    std::string distortion_model = "none";           // none | radtan | equidistant
    double d0 = 0.0, d1 = 0.0, d2 = 0.0, d3 = 0.0;  // radtan: k1 k2 p1 p2; equidistant: k1..k4
  } intrinsics;
};

struct LcmConfig {
  // ttl=0 keeps packets on the robot itself.
  std::string url = "udpm://239.255.76.67:7667?ttl=0";
  std::string pose_channel = "ALE_POSE";
  std::string status_channel = "ALE_STATUS";
  std::string command_channel = "ALE_COMMAND";      // ale_lcm.command_t in
  std::string reply_channel = "ALE_COMMAND_REPLY";  // ale_lcm.command_reply_t out
};

struct GpioConfig {
  std::string chip;         // e.g. gpiochip0; empty: no GPIO
  int status_led = -1;      // line offset, -1: not wired
  int ir_illuminator = -1;
  bool active_low = false;
  // The IR illuminator follows the brightness class: on after ir_on_dark_frames consecutive
  // extremely dark frames, off after ir_off_normal_frames consecutive normal or bright ones, and
  // never switched twice within ir_min_toggle_ms (of camera time), so it cannot flicker.
  int ir_on_dark_frames = 5;
  int ir_off_normal_frames = 30;
  int ir_min_toggle_ms = 5000;
};

struct LogConfig {
  std::string level = "info";     // error | warning | info | debug
  std::string target = "stderr";  // stderr | syslog
};

// The recorder: the raw camera frames and their timestamps as EuRoC ASL sequences that
// `ale-slamd --replay` reads back (docs/daemon.md). One sequence folder per daemon start and per
// camera session, under dir; the oldest go first when the folder would pass max_mb.
struct RecorderConfig {
  std::string dir;          // empty: no recording
  int max_mb = 1024;        // of every sequence in dir together (MiB)
  int queue_frames = 8;     // frames copied and waiting for the writer at most
  int png_compression = 1;  // zlib level of the frames' PNGs (0 stored .. 9 smallest)
};

// Wheel odometry from the sweeper's MCU (core/slam/odometry.h): where samples come from and how
// they relate to the camera. The buffer's checks are slam.odometry.*.
struct OdometryConfig {
  // Hand samples to the SLAM core when a source provides them: a replayed dataset's
  // mav0/odometry0/, else ale_lcm.odometry_t on `channel`.
  bool enabled = true;
  std::string channel = "ODOMETRY";  // empty: not read from LCM
  // camera time = MCU time + clock_offset_ms.
  double clock_offset_ms = 0.0;
  // A replay hands over, before each frame, every sample up to this much past the frame's time.
  double lookahead_ms = 20.0;
  // The camera in the base frame, 16 numbers (4x4 row-major, p_base = T_bc * p_camera, like
  // EuRoC's T_BS). Empty: the replayed dataset's odometry0/sensor.yaml T_BC; samples over LCM are
  // not read without it.
  std::string T_bc;
};

struct DaemonConfig {
  CameraConfig camera;
  LcmConfig lcm;
  GpioConfig gpio;
  LogConfig log;
  RecorderConfig recorder;
  OdometryConfig odometry;
  // The ORB front end with the ALE enhancement (its `enhance` member); defaults and their
  // justification: core/features/orb.h, core/enhance/params.h, docs/enhancement.md, docs/features.md.
  ale::features::ExtractorConfig features;
  // Which enhancement the front end runs (it sets features.mode): `ale` (the product), `off` (the
  // ORB-SLAM3 front end), `clahe` (CLAHE on every level); for the article's comparisons.
  struct Enhancement {
    ale::features::ExtractorMode mode = ale::features::ExtractorMode::kAle;
  } enhancement;
  // The SLAM core (core/slam/system.h); keys: slam_config_table().
  ale::slam::SlamParams slam;
  struct Run {
    int max_frames = 0;      // 0: run until the camera ends or a signal arrives
    std::string frame_log;   // CSV with one line per frame (docs/configuration.md); empty: none
    std::string trajectory;  // TUM file, one line per frame with a pose; empty: none
    // final: at the end the trajectory file is rewritten with each frame's pose relative to its
    // keyframe composed with the keyframe's final pose (ORB-SLAM's saved trajectory); online:
    // the poses as published (app/daemon/trajectory_file.h).
    std::string trajectory_poses = "final";
    // camera: no extrinsics, the body pose is the camera's; calibration: the camera's
    // calibration gives T_bc (T_BS) and pose_t carries the body pose T_wb too.
    std::string body_frame = "camera";
    // Place recognition's vocabulary (relocalisation's candidates, docs/place.md): `builtin`, the
    // one built into the binary; `none`, no place recognition (a lost frame tries the last
    // keyframes' neighbourhood and a sweep over the map); or the path of a vocabulary file.
    std::string vocabulary = "builtin";
  } daemon;
  // The map file (core/io/map_file.h, docs/daemon.md "Map files").
  struct MapFile {
    // Loaded when the SLAM core starts (the first frame gives the image size); the run starts
    // lost in it and relocalises. A missing file starts an empty map; a refused one (corrupt,
    // another version, vocabulary or camera) is moved aside to PATH.refused, never overwritten,
    // and its backup PATH.bak is loaded instead when that is good. Empty: start without a map.
    std::string load;
    // Written at the end of the run (the replay's end, SIGTERM, SIGINT), every save_period_s and
    // by SAVE_MAP without a path. Empty: never saved.
    std::string save;
    // Seconds on the steady clock between two saves to `save` while running, between two frames
    // (at most one per frame); 0: only at the end of the run. A power cut then loses at most
    // this long of mapping.
    double save_period_s = 0.0;
  } map;
};

// Every key of DaemonConfig with its type, range and help.
const ConfigTable& config_table();

// Parses `key = value` lines; a `[section]` header prefixes the keys after it with "section."
// ([features.enhance] then `grading.t_low = 60`); '#' starts a comment. Values not given keep
// their defaults.
Status parse_config(const std::string& text, const std::string& origin, DaemonConfig& config);
Status load_config(const std::string& path, DaemonConfig& config);
// The one check of a configuration (parse_config and a reload run it): the app's tables' ranges,
// cross-field checks (e.g. source=replay needs replay_path), and the core's structs by their own
// validate() (features::validate, slam::validate: each key once). The daemon does not check the
// structs again on their way down; the core's constructors (SlamSystem::create, FramePath) check
// what they are given for callers that build the structs in code.
Status validate_config(const DaemonConfig& config);
// odometry.T_bc: 16 numbers separated by commas or blanks, the rotation block a rotation;
// nullopt for an empty text; kInvalidArgument naming what is wrong.
Result<std::optional<std::array<double, 16>>> parse_T_bc(const std::string& text);

// `config` as a config file that parses back to it: one [section] per top-level struct.
std::string print_config(const DaemonConfig& config);
// The key reference of docs/configuration.md: one table row per key (key, default, range, meaning).
std::string config_reference_markdown();

}  // namespace ale::app
