// The floor under a sweeper, as a scale anchor for monocular mapping.
//
// A camera on a robot that drives on a flat floor keeps its height above the floor, and the floor
// keeps its place in the camera's frame: the plane n_c.x + height = 0 (x in camera coordinates)
// is the same for every keyframe. Monocular mapping does not know that: its scale drifts, most in
// turns (docs/slam.md, session 16), and nothing in the images ties one part of the map's scale to
// another's. Once the map shows such a plane (landmarks seen by most keyframes lie on one plane in
// their cameras' frames, below the camera, within max_tilt_deg of its up axis), the local bundle
// adjustment holds each observed floor landmark on it in the observing camera's frame
// (BundleAdjuster::add_observation_plane_prior): floor points carry the scale through a turn, and
// each keyframe's pitch and roll stay those of the mount.
//
// A camera that does not keep its height (a drone, a hand-held camera) shows no such plane, and
// its map gets no prior: find_floor() is the test.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/geometry/lie.h"

namespace ale::slam {

struct FloorParams {
  bool enabled = true;           // look for a floor at all (slam.mapping.floor.enabled)
  int min_keyframes = 10;        // keyframes in the map before the floor is looked for
  int max_keyframes = 40;        // none found by then: this map gets no floor
  double max_tilt_deg = 35.0;    // pitch of the floor's normal from the camera's up axis (-y), at most
  double max_roll_deg = 10.0;    // roll, at most
  double search_step_deg = 2.5;  // of the coarse search over normals (the fine one: a fifth)
  double band = 0.3;             // x camera height: a landmark this close to the floor is on it
  int min_support = 150;         // landmark observations on the floor, over all keyframes
  double min_keyframe_share = 0.8;  // keyframes that see min_keyframe_support of them
  int min_keyframe_support = 8;
  double max_below_share = 0.5;  // landmarks more than `band` below the floor, / its support
  double prior_band = 0.3;       // x camera height: observations this close get the floor prior
  double point_sigma = 0.15;     // x camera height: the prior's sigma
};

// The floor in camera coordinates: n_c.x + height = 0.
struct FloorPlane {
  geometry::Vec3 n_c = -geometry::Vec3::UnitY();  // unit, the camera's up from the floor
  double height = 0.0;                            // the camera's height above it (map units)
  int support = 0;                                // observations within band of it
  double height_of(const geometry::Vec3& x_c) const { return n_c.dot(x_c) + height; }
};

// One keyframe's landmarks in its camera's frame.
struct FloorSample {
  std::vector<geometry::Vec3> points_c;
};

// The floor shared by the keyframes' samples, or nothing when there is none (see FloorParams).
// A search over normals near the camera's up axis (pitch and roll on a grid, coarse then fine):
// for each, the landmarks' depths below the camera along it, and the band of relative width
// `band` with the most landmarks per unit of depth; the best normal's band is the floor. It must
// hold min_support landmarks, have few below it, and be seen by most keyframes.
std::optional<FloorPlane> find_floor(const std::vector<FloorSample>& keyframes, const FloorParams& params);

}  // namespace ale::slam
