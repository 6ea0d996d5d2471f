// Wheel odometry as a camera trajectory: the base's pose on the floor (x, y, theta about z up, as
// a dataset's mav0/odometry0/ has it) composed with T_BC (the camera in the base frame), so the
// odometry alone can be scored against groundtruth.txt exactly like a SLAM trajectory.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "hal/replay/dataset.h"
#include "app/tools/lib/eval/trajectory.h"

namespace ale::eval {

// T_wc = [Rz(theta) | (x, y, 0)] * T_BC at each row's time (kTum trajectory named after the
// track's data.csv). With `at_ns` non-empty, the base pose is interpolated at those times instead
// (x, y linearly, theta along the shorter arc); times before the first row or after the last are
// left out. kInvalidArgument when the track has no T_BC or a T_BC that is not rigid, a row holds a
// value that is not finite (naming data.csv and the row's line), or no pose is left.
Result<Trajectory> odometry_camera_trajectory(const replay::OdometryTrack& track,
                                              const std::vector<std::int64_t>& at_ns = {});

// TUM text (`t tx ty tz qx qy qz qw`, t in seconds with 9 decimals) with a header comment line.
std::string tum_text(const Trajectory& trajectory, const std::string& comment);

}  // namespace ale::eval
