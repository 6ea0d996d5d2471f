// Pose errors in degrees, for tests that compare estimates with the truth.
#pragma once

#include <algorithm>
#include <cmath>

#include "core/geometry/lie.h"

namespace ale::test {

// Angle of the rotation a^T b (0 when a == b); atan2 keeps it accurate near 0, where acos is not.
inline double rotation_error_deg(const geometry::Mat3& a, const geometry::Mat3& b) {
  const geometry::Mat3 d = a.transpose() * b;
  const double c = std::clamp((d.trace() - 1.0) / 2.0, -1.0, 1.0);
  const double s = 0.5 * geometry::Vec3(d(2, 1) - d(1, 2), d(0, 2) - d(2, 0), d(1, 0) - d(0, 1)).norm();
  return std::atan2(s, c) * 180.0 / M_PI;
}

// Angle between two directions (any lengths).
inline double direction_error_deg(const geometry::Vec3& a, const geometry::Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * 180.0 / M_PI;
}

}  // namespace ale::test
