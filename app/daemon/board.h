// The board file: builds the concrete backends the configuration asks for and hands them to
// the loop by reference. The one place that knows which backends exist.
#pragma once

#include <memory>
#include <optional>

#include "app/config.h"
#include "hal/camera.h"
#include "hal/gpio.h"
#include "hal/replay/dataset.h"

namespace ale::app {

struct Board {
  std::unique_ptr<ale::hal::Camera> camera;
  std::unique_ptr<ale::hal::Gpio> gpio;
  // The lens (camera.intrinsics, else camera.calibration_file, else what the camera reports);
  // width and height 0 when only the frames will tell (inline intrinsics).
  ale::hal::CameraCalibration calibration;
  // A replayed EuRoC dataset's wheel odometry (mav0/odometry0/), read when odometry.enabled.
  std::optional<ale::replay::OdometryTrack> odometry;
};

// kNotFound "no camera calibration ..." when no source knows the lens; the error of the
// calibration file or backend otherwise.
Status build_board(const DaemonConfig& config, Board& board);
// Closes the board's camera (a device that went away) and opens it again as configured.
Status reopen_camera(const DaemonConfig& config, Board& board);

}  // namespace ale::app
