// Writing the EuRoC ASL layout that open_dataset() reads back: <root>/mav0/cam0/ with data.csv
// ("#timestamp [ns],filename" then one row per frame), data/<timestamp>.png and sensor.yaml, and
// <root>/mav0/odometry0/ (sensor.yaml, data.csv). The daemon's recorder writes its sequences with it.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "core/base/status.h"
#include "hal/camera.h"
#include "hal/replay/dataset.h"

namespace ale::replay {

// A list file that only grows by whole rows: each row goes in one write, and a row the disk took
// only in part is cut off again, so the file is readable after every row.
class RowFile {
 public:
  RowFile() = default;
  RowFile(RowFile&& other) noexcept { *this = std::move(other); }
  RowFile& operator=(RowFile&& other) noexcept;
  RowFile(const RowFile&) = delete;
  RowFile& operator=(const RowFile&) = delete;
  ~RowFile() { (void)close(); }

  // Makes `path` with `header` (an existing file is refused: never append to another's list; a
  // header the disk did not take leaves no file). kIoError naming the path.
  Status create(const std::string& path, const std::string& header);
  bool is_open() const { return fd_ >= 0; }
  // kIoError naming the file (nothing of the row left in it).
  Status append(const std::string& row);
  std::uint64_t bytes() const { return bytes_; }
  Status close();

 private:
  std::string path_;
  int fd_ = -1;
  std::uint64_t bytes_ = 0;  // what the file holds of whole rows
};

// sensor.yaml for `c` (pinhole; its distortion model; resolution; rate_hz when > 0; T_BS), the
// numbers with 17 significant digits so read_euroc_sensor_yaml() gives back exactly `c`.
std::string euroc_sensor_yaml(const hal::CameraCalibration& c);

class EurocWriter {
 public:
  // Creates <root>/mav0/cam0/data/ (and the folders above it) and data.csv with its header; an
  // existing data.csv is refused. kIoError naming the path that could not be made.
  static Result<EurocWriter> create(const std::string& root);


  const std::string& root() const { return root_; }
  const std::string& cam0() const { return cam0_; }
  // Where the frame taken at t_ns goes: <cam0>/data/<t_ns>.png.
  std::string frame_path(std::int64_t t_ns) const;
  // Writes sensor.yaml (replacing one written before). kIoError naming the file.
  Status write_calibration(const hal::CameraCalibration& c);
  // Lists the frame at t_ns, whose file is written: its row goes to data.csv in one write, so the
  // folder is a readable dataset after every frame; a row the disk took only in part is cut off
  // again. Timestamps must increase (kInvalidArgument otherwise, nothing written). kIoError naming
  // data.csv.
  Status append(std::int64_t t_ns);
  // Bytes in data.csv and sensor.yaml (the frames are the caller's to count).
  std::uint64_t text_bytes() const { return csv_.bytes() + yaml_bytes_; }
  Status close() { return csv_.close(); }

 private:
  EurocWriter() = default;

  std::string root_;
  std::string cam0_;
  RowFile csv_;
  std::optional<std::int64_t> last_t_ns_;
  std::uint64_t yaml_bytes_ = 0;
};

// mav0/odometry0/ as read_odometry_folder() reads it back. sensor.yaml comes first, at create(),
// so the folder never holds a data.csv the reader would refuse for want of it; data.csv is made
// with the first row, its header naming that row's columns: timestamp [ns], x [m], y [m],
// theta [rad], then gyro_z [rad/s] when has_gyro and v_left [m/s], v_right [m/s] when has_wheels.
// Values are written so that they read back to the same doubles ("nan", "inf" as such).
class OdometryWriter {
 public:
  // Creates <root>/mav0/odometry0/ and its sensor.yaml: T_BC (row-major, p_base = T_BC * p_camera)
  // and rate_hz when > 0. kIoError naming what could not be made.
  static Result<OdometryWriter> create(const std::string& root, const std::array<double, 16>& T_BC, double rate_hz);

  const std::string& folder() const { return folder_; }
  // Lists one row in one write. A timestamp not after the last row's, or other columns than the
  // first row's: kInvalidArgument, nothing written. kIoError naming data.csv.
  Status append(const OdometryRow& row);
  // Bytes in data.csv and sensor.yaml.
  std::uint64_t text_bytes() const { return csv_.bytes() + yaml_bytes_; }
  Status close() { return csv_.close(); }

 private:
  OdometryWriter() = default;

  std::string folder_;
  RowFile csv_;
  bool gyro_ = false, wheels_ = false;  // data.csv's columns
  std::optional<std::int64_t> last_t_ns_;
  std::uint64_t yaml_bytes_ = 0;
};

}  // namespace ale::replay
