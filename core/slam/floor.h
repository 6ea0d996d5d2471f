// The floor as a scale cue: a sweeper's camera sits at a fixed, known height above a flat floor,
// so a map's landmarks on the floor lie that height below every camera, along the floor's normal.
// A map without odometry is put in metres by the distance of the floor's landmarks below the
// camera (floor_distance; at initialisation, or at the first keyframes that show the floor:
// SlamSystem), and in a metric map the local BA holds landmarks within max_height_m of the floor
// on it (MapBundleAdjustment::add_floor_observations), against the wheel odometry's radius and
// slip errors (it pulls a map whose odometry is 1-1.5 % short to 0.5-1.9 %, docs/evaluation.md).
//
// The camera's mounting on the base (T_bc, EuRoC's T_BS convention, the base frame on the floor,
// z up) gives the floor's normal in the camera frame and the camera's height; a mounting whose
// height is under min_camera_height_m (an unset T_bc) gives no cue and nothing changes.
#pragma once

#include <optional>
#include <vector>

#include "core/base/config_table.h"
#include "core/base/status.h"
#include "core/geometry/lie.h"

namespace ale::slam {

struct FloorParams {
  bool enabled = true;
  // A floor landmark's height prior in the local BA, metres: the floor's flatness and the
  // landmark's own error (about a pixel at a metre's depth).
  double sigma_m = 0.005;
  // Landmarks within this height of the floor (at the BA's start, in the frame of the first
  // keyframe of the BA that sees them) are held on it, metres. Larger than the scale error the
  // map may have when the cue starts (a few per cent of a 10 cm height), smaller than a skirting.
  double max_height_m = 0.02;
  double min_camera_height_m = 0.02;
  // Finding the floor under a keyframe (floor_distance, to put a map in metres): the landmarks
  // below the camera whose distances agree within this share (the densest such group is the
  // floor) and how many of them are needed.
  double distance_tolerance = 0.05;
  int min_points = 20;
};

// kInvalidArgument naming the first field out of range.
Status validate(const FloorParams& p);
// The keys (the daemon's `slam.floor.*`).
extern const ConfigTable kFloorConfig;

// The floor in the camera frame: points p_c on it satisfy up_c . p_c = -camera_height_m.
struct FloorGeometry {
  geometry::Vec3 up_c = geometry::Vec3::UnitZ();  // the base's z axis in camera coordinates
  double camera_height_m = 0.0;
};

// The floor's normal (the base's z axis) in the camera frame of the mounting T_bc.
geometry::Vec3 floor_normal_in_camera(const geometry::SE3& T_bc);
// From the camera's mounting T_bc; nullopt when the cue is off or the height is too small.
std::optional<FloorGeometry> floor_geometry(const FloorParams& params, const geometry::SE3& T_bc);

struct FloorFit {
  double distance = 0.0;  // the floor's distance below the camera, in the points' unit
  int points = 0;         // landmarks in the floor's group
};

// The floor under a camera from points in its frame (any unit): the densest group of distances
// below the camera (up_c . p_c < 0) agreeing within distance_tolerance, the farthest such group
// when two are as dense (nothing is below the floor); its median distance. nullopt with fewer
// than min_points in it. `scratch` is reused.
std::optional<FloorFit> floor_distance(const FloorParams& params, const geometry::Vec3& up_c,
                                       const std::vector<geometry::Vec3>& points_c, std::vector<double>& scratch);

}  // namespace ale::slam
