// Least-squares alignment of an estimated trajectory to the ground truth (Umeyama 1991).
#pragma once

#include <Eigen/Core>

#include <string_view>
#include <vector>

#include "core/base/status.h"
#include "app/tools/lib/eval/associate.h"

namespace ale::eval {

// kSe3: rotation and translation; kSim3: also a scale (monocular estimates); kNone: as is.
enum class Alignment { kNone, kSe3, kSim3 };

const char* to_string(Alignment alignment);
// "none", "se3" or "sim3".
Result<Alignment> parse_alignment(std::string_view name);

// p -> scale * R * p + t.
struct Sim3 {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double scale = 1.0;

  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return scale * (R * p) + t; }
};

// The transform minimising sum |y_i - (s R x_i + t)|^2 (s = 1 unless with_scale), by
// geometry::umeyama (core/geometry/sim3_solver.h). Fails when the sizes differ or the points
// are degenerate (fewer than 3, not finite, or all on one line).
Result<Sim3> umeyama(const std::vector<Eigen::Vector3d>& x, const std::vector<Eigen::Vector3d>& y,
                     bool with_scale);

// Aligns pairs->est to pairs->gt in place (positions scaled, rotated and moved; orientations
// rotated) and returns the transform applied (identity for kNone).
Result<Sim3> align_estimate(Alignment alignment, PosePairs* pairs);

}  // namespace ale::eval
