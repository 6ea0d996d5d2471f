// Writes a rendered sequence in the EuRoC ASL layout, so the replay backend reads it unchanged:
//
//   <out>/mav0/cam0/data.csv                       #timestamp [ns],filename
//   <out>/mav0/cam0/data/<timestamp>.png           8-bit grey frames
//   <out>/mav0/cam0/sensor.yaml                    intrinsics, distortion, T_BS
//   <out>/mav0/state_groundtruth_estimate0/data.csv  EuRoC state of the body: t [ns], p, q (w x y z), v,
//                                                  biases (as EuRoC's: the camera is body x T_BS)
//   <out>/groundtruth.txt                          the camera's poses in TUM format (seconds): what
//                                                  ale-slamd --trajectory writes and ale-eval compares
//   <out>/lighting.csv                             per frame: light, exposure, gain, mean grey
//   <out>/mav0/odometry0/data.csv, sensor.yaml     the sweeper's wheel odometry (odometry.h)
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/image.h"
#include "core/base/status.h"
#include "app/tools/lib/render/odometry.h"
#include "app/tools/lib/render/renderer.h"

namespace ale::render {

class EurocWriter {
 public:
  // Creates the folders. An existing <out>/mav0 is an error unless `overwrite`, which removes it
  // (and the files below) first.
  static Result<EurocWriter> create(const std::string& out_dir, bool overwrite);

  // `notes`: '#' lines of the file (sensor_yaml_text()), e.g. the sensor noise model.
  Status write_sensor_yaml(const PinholeCamera& camera, double fps, const Rig& rig, const std::string& comment,
                           const std::string& notes = "");
  // Writes the frame's PNG and remembers its rows for the lists written by finish().
  Status add_frame(std::int64_t timestamp_ns, GrayView image, const FrameRecord& record,
                   const Eigen::Vector3d& velocity_w, const char* profile);
  Status finish();
  // Writes mav0/odometry0/data.csv and sensor.yaml (texts from odometry.h).
  Status write_odometry(const std::string& csv, const std::string& yaml);

  const std::string& out_dir() const { return out_; }

 private:
  explicit EurocWriter(std::string out) : out_(std::move(out)) {}

  std::string out_;
  std::string frames_csv_;
  std::string state_csv_;
  std::string tum_;
  std::string lighting_csv_;
};

// The sweeper's wheel odometry over the frames written (mav0/odometry0, odometry.h), `route`
// naming the route in its comment. Returns the summary line: samples, settings and the error at
// the last sample against the base's truth; or, with fewer than 2 frames or a span shorter than
// one odometry step, a line saying that nothing was written.
Result<std::string> write_sweeper_odometry(EurocWriter& writer, const Trajectory& trajectory, const Rig& rig,
                                           const Eigen::Isometry3d& T_BC, const std::vector<FrameTime>& frames,
                                           const OdometrySettings& settings, const std::string& route);

// "1403715274.302140000" for 1403715274302140000 ns (exact, no floating point).
std::string ns_to_seconds_text(std::int64_t ns);

}  // namespace ale::render
