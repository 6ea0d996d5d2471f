// What the loop adds to the pipeline's camera pose before publishing it: the body pose through the
// camera-to-body extrinsics, and the velocities of the constant-velocity motion model.
#pragma once

#include <array>
#include <optional>

#include "hal/pose_sink.h"

namespace ale::app {

// The camera-to-body transform T_bc (row-major 4x4, e.g. CameraCalibration::T_BS: p_b = T_bc p_c)
// as position and unit quaternion (w, x, y, z); nullopt when its rotation block is not a rotation.
struct RigidTransform {
  std::array<double, 3> p{0, 0, 0};
  std::array<double, 4> q{1, 0, 0, 0};
};
std::optional<RigidTransform> rigid_from_row_major(const std::array<double, 16>& T);

// Sets p_bc / q_bc and the body pose T_wb = T_wc * T_bc^-1 with body_valid; without extrinsics
// the body pose is a copy of the camera pose and body_valid false.
void apply_body_frame(const std::optional<RigidTransform>& T_bc, ale::hal::PoseEstimate& pose);

// Linear (camera centre) and angular velocity in the map frame from the previous pose, per second
// of camera time; zero unless both poses are tracked (not relocalised) on the same map.
void apply_motion(const ale::hal::PoseEstimate& previous, ale::hal::PoseEstimate& pose);

}  // namespace ale::app
