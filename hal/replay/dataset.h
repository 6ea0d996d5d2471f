// Recorded datasets as lists of timestamped frame files: the EuRoC ASL layout and the TUM RGB-D
// layout. Reading a dataset checks everything that can be checked without decoding every frame;
// every error names the file, and the line where there is one ("<file>:<line>: <problem>").
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/status.h"
#include "hal/camera.h"

namespace ale::replay {

enum class DatasetFormat { kEuroc, kTum };
const char* to_string(DatasetFormat format);

struct FrameEntry {
  std::int64_t timestamp_ns = 0;
  std::string path;  // the frame's file, ready to open
};

// One row of a EuRoC-style mav0/odometry0/data.csv: the robot base's pose on the floor as its MCU
// reported it (x forward, y left, z up; theta about z). Values are as written: "nan" or "inf"
// are kept, for the consumer to refuse and count as it does with a live MCU's.
struct OdometryRow {
  std::int64_t timestamp_ns = 0;  // the MCU's clock
  double x_m = 0.0, y_m = 0.0, theta_rad = 0.0;
  bool has_gyro = false;          // a gyro_z [rad/s] column
  double gyro_z_rps = 0.0;
  bool has_wheels = false;        // v_left [m/s] and v_right [m/s] columns
  double v_left_mps = 0.0, v_right_mps = 0.0;
};

// mav0/odometry0/: data.csv (header "#timestamp [ns],x [m],y [m],theta [rad]", optionally
// followed by "gyro_z [rad/s]" and/or "v_left [m/s],v_right [m/s]"; columns found by their header
// names, in any order) and sensor.yaml (rate_hz, T_BC: the camera in the base frame as a 4x4
// row-major `data:` list like EuRoC's T_BS; other keys ignored).
struct OdometryTrack {
  std::string list_file;    // data.csv
  std::string sensor_yaml;  // sensor.yaml
  std::vector<OdometryRow> rows;  // strictly increasing timestamps, at least one
  double rate_hz = 0.0;     // 0: not given
  std::optional<std::array<double, 16>> T_BC;  // row-major, p_base = T_BC * p_camera; nullopt: not given
};

struct DatasetOptions {
  bool odometry = true;  // read mav0/odometry0/ when it is there
};

struct Dataset {
  DatasetFormat format = DatasetFormat::kEuroc;
  std::string folder;      // EuRoC: the cam0/ folder; TUM: the sequence folder
  std::string list_file;   // data.csv or rgb.txt; empty when frames were found by their names
  std::vector<FrameEntry> frames;  // strictly increasing timestamps, every file present
  int width = 0;           // of the frames (from sensor.yaml, checked against the first frame)
  int height = 0;
  std::optional<hal::CameraCalibration> calibration;  // EuRoC: from sensor.yaml
  std::string groundtruth_file;  // EuRoC: mav0/state_groundtruth_estimate0/data.csv if present
  std::optional<OdometryTrack> odometry;  // EuRoC: mav0/odometry0/ if present (and asked for)
};

// Detects the layout at `path` and reads it:
// - EuRoC: `path` is the folder holding mav0/, or mav0/, or cam0/ (data.csv, data/, sensor.yaml).
// - TUM: `path` holds rgb.txt, or an rgb/ folder of images named by their time in seconds
//   (1311868169.163498.png), or is such a folder itself.
// kNotFound when `path` does not exist or holds no frames; kCorruptData for malformed lists,
// timestamps that do not increase and frames of the wrong size.
// A EuRoC dataset with mav0/odometry0/data.csv has its odometry read too (options.odometry): a
// row with the wrong number of columns, an unknown or missing column, text that is not a number,
// a timestamp not after the previous row's or a header with no rows after it is kCorruptData
// naming the file and line; a missing sensor.yaml is kNotFound. A value written "nan" or "inf" is kept (OdometryRow).
Result<Dataset> open_dataset(const std::string& path, const DatasetOptions& options = {});

// Reads mav0/odometry0/ (the folder holding data.csv and sensor.yaml), as open_dataset() does.
Result<OdometryTrack> read_odometry_folder(const std::string& folder);

// The subset of EuRoC's sensor.yaml that describes a pinhole camera: camera_model, intrinsics,
// distortion_model, distortion_coefficients, resolution, rate_hz and T_BS.
Result<hal::CameraCalibration> read_euroc_sensor_yaml(const std::string& path);

// "1311868169.163498" (seconds) -> nanoseconds, exactly (no floating point). Up to 9 decimals.
std::optional<std::int64_t> parse_seconds_ns(std::string_view text);
// "1403715273262142976" -> nanoseconds; nullopt unless all digits and in range.
std::optional<std::int64_t> parse_integer_ns(std::string_view text);

// One row of EuRoC's state_groundtruth_estimate0/data.csv (body pose in the world frame).
struct GroundTruthState {
  std::int64_t timestamp_ns = 0;
  std::array<double, 3> p_wb{};       // position, m
  std::array<double, 4> q_wb_wxyz{};  // orientation quaternion w, x, y, z
  std::array<double, 3> v_wb{};       // velocity, m/s (0 when the file has no such columns)
};

// Reads a EuRoC ground-truth CSV (at least the 8 columns t, p, q; 11 or more adds velocity).
Result<std::vector<GroundTruthState>> read_euroc_groundtruth(const std::string& path);

}  // namespace ale::replay
