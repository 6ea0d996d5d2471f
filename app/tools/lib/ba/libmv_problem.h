// Ceres' libmv bundle-adjustment problems (film camera tracking: many cameras, few points,
// pixel observations, one shared radial-tangential camera), loaded for tests, benchmarks and
// ale_ba_bench. Format: ../shared/data/ba_libmv/README.md.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "core/geometry/camera.h"
#include "core/geometry/lie.h"

namespace ale::optim {

struct LibmvObservation {
  int camera = 0;  // index into LibmvProblem::T_cw (not the file's image id)
  int point = 0;   // index into LibmvProblem::points_w (not the file's track id)
  geometry::Vec2 uv_px = geometry::Vec2::Zero();
};

struct LibmvProblem {
  geometry::CameraIntrinsics intrinsics;  // fx = fy = f, OpenCV order (k1 k2 p1 p2 k3)
  std::vector<int> image_ids;             // the file's id of each camera
  std::vector<geometry::SE3> T_cw;        // x_cam = R x_w + t (R orthonormalised from floats)
  std::vector<int> track_ids;             // the file's id of each point
  std::vector<geometry::Vec3> points_w;
  std::vector<LibmvObservation> observations;
  bool normalised_observations = false;  // tag N; the residual is computed the same way
  int skipped_observations = 0;          // markers naming an image or track the file does not define
};

// kNotFound when the file cannot be opened, kCorruptData when it is truncated, has an unknown
// byte-order or space tag, bad counts, or non-finite values. As in libmv's own adjuster (Ceres'
// examples/libmv_bundle_adjuster.cc), a repeated camera or track id replaces the earlier one and
// observations naming an undefined image or track are skipped (counted in skipped_observations).
Result<LibmvProblem> load_libmv_problem(const std::string& path);

// Seeded perturbation for "from a perturbed start" runs: every camera rotated by
// `rotation_deg` about a random axis (applied on the left, in the camera frame) and its centre
// moved by `relative` times the median depth of the points it sees, in a random direction;
// every point moved by `relative` times its median depth over the cameras that see it. Scales
// come from the unperturbed problem, so the result depends only on the problem and the seed.
void perturb_libmv_problem(std::uint64_t seed, double rotation_deg, double relative, LibmvProblem* problem);

// 0.5 * sum of squared pixel residuals over all observations (Ceres' convention), with the
// given camera; +inf when some point projects behind its camera.
double libmv_cost(const LibmvProblem& problem, const geometry::Camera& camera);

}  // namespace ale::optim
