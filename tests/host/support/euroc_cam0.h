// EuRoC MAV cam0 as its sensor.yaml gives it (752x480, radial-tangential), for tests that need
// a real lens: the camera model's, the extractor's and the solvers' synthetic scenes (those
// without its distortion clear it).
#pragma once

#include "core/geometry/camera.h"

namespace ale::test {

inline geometry::CameraIntrinsics euroc_cam0_intrinsics() {
  geometry::CameraIntrinsics k;
  k.fx = 458.654;
  k.fy = 457.296;
  k.cx = 367.215;
  k.cy = 248.375;
  k.distortion = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05, 0.0};
  k.width = 752;
  k.height = 480;
  return k;
}

}  // namespace ale::test
