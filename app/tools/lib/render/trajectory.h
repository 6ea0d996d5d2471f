// Where the rendered camera goes: the sweeper's closed loops and real EuRoC flights fitted into
// the room. A trajectory is a list of body poses at increasing times, interpolated in between.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "core/base/status.h"
#include "app/tools/lib/render/scene.h"

namespace ale::render {

struct Pose {
  Eigen::Quaterniond q_wb = Eigen::Quaterniond::Identity();
  Eigen::Vector3d p_wb = Eigen::Vector3d::Zero();
};

struct TimedPose {
  double t_s = 0.0;  // from the start of the trajectory
  Pose pose;
};

// The camera's mounting on the body: camera-to-body rotation and the camera's position in the body
// frame (EuRoC's T_BS).
struct Rig {
  Eigen::Matrix3d R_bc = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_bc = Eigen::Vector3d::Zero();
};

// The sweeper: body frame x forward, y left, z up with its origin at the camera's optical
// centre (so ground-truth positions are camera positions), camera tilted up `tilt_up_deg`.
Rig sweeper_rig(double tilt_up_deg);
// EuRoC's cam0 mounting on its IMU (body) frame, from the dataset's sensor.yaml.
Rig euroc_cam0_rig();

class Trajectory {
 public:
  Trajectory() = default;
  explicit Trajectory(std::vector<TimedPose> samples) : samples_(std::move(samples)) {}

  // Linear interpolation of position and slerp of orientation; clamped at the ends.
  Pose at(double t_s) const;
  double duration_s() const { return samples_.empty() ? 0.0 : samples_.back().t_s - samples_.front().t_s; }
  const std::vector<TimedPose>& samples() const { return samples_; }
  bool empty() const { return samples_.empty(); }

 private:
  std::vector<TimedPose> samples_;
};

struct DriveOptions {
  double speed_mps = 0.3;          // along straight lines and the loop
  double turn_rate_dps = 60.0;     // turning in place at the square's corners
  double camera_height_m = 0.09;   // optical centre above the floor
  double camera_ahead_m = 0.15;    // optical centre ahead of the turning axis
};

// An ellipse (3.0 x 2.0 m) around the room's centre, driven anticlockwise at constant speed:
// one lap is about 26 s at 0.3 m/s. `duration_s` may cover several laps.
Trajectory make_loop(const Scene& scene, const DriveOptions& drive, double duration_s);
// A 2.4 x 1.6 m rectangle around the room's centre: straight lines, and at each corner the robot
// stops and turns 90 degrees in place about its axis (the camera swings on a 15 cm arm).
Trajectory make_square(const Scene& scene, const DriveOptions& drive, double duration_s);

// How a recorded trajectory was put into the room.
struct FitReport {
  double scale = 1.0;
  double yaw_deg = 0.0;                       // rotation about the vertical
  Eigen::Vector3d source_centre = Eigen::Vector3d::Zero();  // of its bounding box, before
  Eigen::Vector3d room_centre = Eigen::Vector3d::Zero();    // where that centre went
  int camera_in_furniture = 0;                // samples whose camera is inside a box (sees nothing)
};

// Fits a recorded body trajectory (times from its start) into the room: rotates it about the
// vertical by 0 or 90 degrees (whichever lets it be larger), scales positions uniformly by at
// most 1 so that its bounding box fits inside the room less `margin_m` from every wall, the floor
// plus the camera height and the ceiling, and centres it there. Orientations are kept (turned by
// the same yaw): the camera still moves in 6-DoF as recorded.
Result<Trajectory> fit_into_room(const std::vector<TimedPose>& recorded, const Scene& scene, const Rig& rig,
                                 double margin_m, FitReport* report);

}  // namespace ale::render
