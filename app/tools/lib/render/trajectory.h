// Where the rendered camera goes: the sweeper's closed loops, and recorded flights (EuRoC) in a
// room sized around them. A trajectory is a list of body poses at increasing times, interpolated in between.
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
  explicit Trajectory(std::vector<TimedPose> samples, double lap_s = 0.0)
      : samples_(std::move(samples)), lap_s_(lap_s) {}

  // Linear interpolation of position and slerp of orientation; clamped at the ends.
  Pose at(double t_s) const;
  double duration_s() const { return samples_.empty() ? 0.0 : samples_.back().t_s - samples_.front().t_s; }
  const std::vector<TimedPose>& samples() const { return samples_; }
  bool empty() const { return samples_.empty(); }
  // The route's period in seconds: the pose at t + lap_s() is the pose at t (the sweeper's routes,
  // whatever their duration); 0 for a recorded trajectory, which does not repeat.
  double lap_s() const { return lap_s_; }

 private:
  std::vector<TimedPose> samples_;
  double lap_s_ = 0.0;
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

// A cleaning pattern: lanes side by side, each driven straight; at a lane's end the robot turns 90
// degrees in place, moves over by the lane width, turns 90 degrees in place again and drives the
// next lane back. After the last lane it turns around in place and cleans the lanes again in
// reverse order, and so on. The lanes are centred in the room, along its x axis.
// With `return_to_start` it instead turns in place after the last lane, drives straight back to
// the first lane's start and turns to face along it, and drives the lanes again the same way: each
// lap passes the places of the first in the same direction (ale-render --laps).
struct LaneOptions {
  int lanes = 6;
  double width_m = 0.3;    // centre to centre: one sweeper width
  double length_m = 3.0;
  bool return_to_start = false;
};
Trajectory make_lanes(const Scene& scene, const DriveOptions& drive, const LaneOptions& lanes, double duration_s);
// kInvalidArgument naming the option out of range: lanes 2..12, width 0.1..1 m, length 0.5..20 m;
// in the living room (build_default_scene, 6 x 5 m) at most 4 m long and 2.4 m across, clear of
// its furniture. In other rooms the caller checks that the route fits.
Status validate(const LaneOptions& lanes, bool living_room = true);

// The route of build_twin_scene: make_square's rectangle in the left room (one lap, then its first
// side again), through the opening (1.2 m past the square's far side, y = centre + 0.95 m) to the
// same rectangle in the right room, one lap there the same way round, and back through the
// opening; the turns are in place.
Trajectory make_twin_route(const Scene& scene, const DriveOptions& drive, double duration_s);

// Walls, floor and ceiling around a recorded flight: how far from the path they stand.
struct RoomMargins {
  double walls_m = 2.0;    // from the path's bounding box to each wall
  double floor_m = 0.5;    // below its lowest point
  double ceiling_m = 1.0;  // above its highest point
};

// Where a recorded trajectory went: a room sized around it, the trajectory moved into it.
struct RoomPlacement {
  Eigen::Vector3d size = Eigen::Vector3d::Zero();    // of the room, metres
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();  // added to every recorded position
  Eigen::Vector3d path_lo = Eigen::Vector3d::Zero();  // bounding box of the body and camera
  Eigen::Vector3d path_hi = Eigen::Vector3d::Zero();  // positions used, in the recorded frame
};

// A recorded body trajectory (absolute times, strictly increasing) as it is rendered: times from
// its first pose, positions moved by a translation (no rotation, no scaling: the motion is the
// recorded one) into a room whose walls, floor and ceiling stand `margins` away from the bounding
// box of the body's and the camera's positions between `start_s` and `end_s` (times from the
// first pose; the part that is rendered). Errors: fewer than 2 poses, times that do not
// increase, a window outside the recording.
Result<Trajectory> place_in_room(const std::vector<TimedPose>& recorded, const Rig& rig, double start_s, double end_s,
                                 const RoomMargins& margins, RoomPlacement* placement);

// Body and camera positions of `trajectory` between start_s and end_s, at its own samples and at
// both ends: what the room's furniture has to keep clear of.
std::vector<Eigen::Vector3f> path_points(const Trajectory& trajectory, const Rig& rig, double start_s, double end_s);

}  // namespace ale::render
