// Writing the EuRoC ASL camera layout that open_dataset() reads back: <root>/mav0/cam0/ with
// data.csv ("#timestamp [ns],filename" then one row per frame), data/<timestamp>.png and
// sensor.yaml. The daemon's recorder writes its sequences with it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/base/status.h"
#include "hal/camera.h"

namespace ale::replay {

// sensor.yaml for `c` (pinhole; its distortion model; resolution; rate_hz when > 0; T_BS), the
// numbers with 17 significant digits so read_euroc_sensor_yaml() gives back exactly `c`.
std::string euroc_sensor_yaml(const hal::CameraCalibration& c);

class EurocWriter {
 public:
  // Creates <root>/mav0/cam0/data/ (and the folders above it) and data.csv with its header; an
  // existing data.csv is refused. kIoError naming the path that could not be made.
  static Result<EurocWriter> create(const std::string& root);

  EurocWriter(EurocWriter&& other) noexcept;
  EurocWriter& operator=(EurocWriter&& other) noexcept;
  EurocWriter(const EurocWriter&) = delete;
  EurocWriter& operator=(const EurocWriter&) = delete;
  ~EurocWriter();

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
  std::uint64_t text_bytes() const { return text_bytes_; }
  Status close();

 private:
  EurocWriter() = default;

  std::string root_;
  std::string cam0_;
  int csv_fd_ = -1;
  std::uint64_t csv_bytes_ = 0;  // what data.csv holds of whole rows
  std::optional<std::int64_t> last_t_ns_;
  std::uint64_t text_bytes_ = 0;
  std::uint64_t yaml_bytes_ = 0;
};

}  // namespace ale::replay
