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

struct Dataset {
  DatasetFormat format = DatasetFormat::kEuroc;
  std::string folder;      // EuRoC: the cam0/ folder; TUM: the sequence folder
  std::string list_file;   // data.csv or rgb.txt; empty when frames were found by their names
  std::vector<FrameEntry> frames;  // strictly increasing timestamps, every file present
  int width = 0;           // of the frames (from sensor.yaml, checked against the first frame)
  int height = 0;
  std::optional<hal::CameraCalibration> calibration;  // EuRoC: from sensor.yaml
  std::string groundtruth_file;  // EuRoC: mav0/state_groundtruth_estimate0/data.csv if present
};

// Detects the layout at `path` and reads it:
// - EuRoC: `path` is the folder holding mav0/, or mav0/, or cam0/ (data.csv, data/, sensor.yaml).
// - TUM: `path` holds rgb.txt, or an rgb/ folder of images named by their time in seconds
//   (1311868169.163498.png), or is such a folder itself.
// kNotFound when `path` does not exist or holds no frames; kCorruptData for malformed lists,
// timestamps that do not increase and frames of the wrong size.
Result<Dataset> open_dataset(const std::string& path);

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
