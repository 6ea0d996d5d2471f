#include "app/daemon/board.h"

#include "hal/linux/gpiod_lines.h"
#include "hal/linux/v4l2_camera.h"
#include "hal/replay/dataset.h"
#include "hal/replay/replay_camera.h"

namespace ale::app {
namespace {

Status build_camera(const DaemonConfig& config, Board& board) {
  const CameraConfig& c = config.camera;
  if (c.source == "replay") {
    ale::replay::ReplayOptions options;
    options.buffers = c.buffers;
    options.odometry = config.odometry.enabled;
    auto cam = ale::replay::open_replay(c.replay_path, options);
    if (!cam.ok()) return cam.status();
    board.odometry = (*cam)->dataset().odometry;
    board.camera = std::move(*cam);
    return {};
  }
  ale::linux_hal::V4l2CameraOptions options;
  options.device = c.device;
  options.width = c.width;
  options.height = c.height;
  options.fps = c.fps;
  options.buffers = c.buffers;
  auto cam = ale::linux_hal::V4l2Camera::open(options);
  if (!cam.ok()) return cam.status();
  board.camera = std::move(*cam);
  return {};
}

Status build_gpio(const GpioConfig& g, Board& board) {
  if (g.chip.empty() || (g.status_led < 0 && g.ir_illuminator < 0)) {
    board.gpio = std::make_unique<ale::hal::NullGpio>();
    return {};
  }
  ale::linux_hal::GpiodLinesOptions options;
  auto mapping = [&](int offset) {
    return ale::linux_hal::GpioLineMapping{g.chip, static_cast<unsigned>(offset), g.active_low};
  };
  if (g.status_led >= 0) options.status_led = mapping(g.status_led);
  if (g.ir_illuminator >= 0) options.ir_illuminator = mapping(g.ir_illuminator);
  auto lines = ale::linux_hal::GpiodLines::open(options);
  if (!lines.ok()) return lines.status();
  board.gpio = std::move(*lines);
  return {};
}

Status resolve_calibration(const CameraConfig& c, const ale::hal::Camera& camera, ale::hal::CameraCalibration& out) {
  const CameraConfig::Intrinsics& k = c.intrinsics;
  if (k.fx > 0.0) {
    out = ale::hal::CameraCalibration{};
    out.fx = k.fx;
    out.fy = k.fy;
    out.cx = k.cx;
    out.cy = k.cy;
    out.distortion_model = k.distortion_model == "radtan"        ? ale::hal::DistortionModel::kRadialTangential
                           : k.distortion_model == "equidistant" ? ale::hal::DistortionModel::kEquidistant
                                                                 : ale::hal::DistortionModel::kNone;
    out.distortion = {k.d0, k.d1, k.d2, k.d3};
    return {};
  }
  if (!c.calibration_file.empty()) {
    Result<ale::hal::CameraCalibration> file = ale::replay::read_euroc_sensor_yaml(c.calibration_file);
    if (!file.ok()) return file.status();
    out = *file;
    return {};
  }
  Result<ale::hal::CameraCalibration> own = camera.calibration();
  if (own.ok()) {
    out = *own;
    return {};
  }
  return not_found("no camera calibration for " + camera.describe() +
                   ": set camera.calibration_file (a sensor.yaml) or camera.intrinsics.fx/fy/cx/cy");
}

}  // namespace

Status reopen_camera(const DaemonConfig& config, Board& board) {
  board.camera.reset();  // closes the old descriptor before the device node is opened again
  return build_camera(config, board);
}

Status build_board(const DaemonConfig& config, Board& board) {
  ALE_RETURN_IF_ERROR(build_camera(config, board));
  ALE_RETURN_IF_ERROR(resolve_calibration(config.camera, *board.camera, board.calibration));
  return build_gpio(config.gpio, board);
}

}  // namespace ale::app
