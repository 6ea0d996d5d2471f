// Where tracking expects the next frame: the constant-velocity model (the motion between the
// last two tracked frames, applied again). It is forgotten when tracking is lost or a map starts,
// so the tracker falls back to the reference keyframe. Wheel odometry plugs in here.
#pragma once

#include "core/geometry/lie.h"

namespace ale::slam {

class MotionPrior {
 public:
  // A frame was tracked at T_cw after the last tracked frame at last_T_cw.
  void tracked(const geometry::SE3& T_cw, const geometry::SE3& last_T_cw) {
    velocity_ = T_cw * last_T_cw.inverse();
    has_velocity_ = true;
  }
  void forget() { has_velocity_ = false; }
  // The map was scaled by `factor` (SlamSystem's floor scale): the velocity's translation too.
  void rescale(double factor) { velocity_ = velocity_.scaled(factor); }
  bool available() const { return has_velocity_; }
  // T_last_to_current, when available().
  const geometry::SE3& velocity() const { return velocity_; }

 private:
  geometry::SE3 velocity_;
  bool has_velocity_ = false;
};

}  // namespace ale::slam
