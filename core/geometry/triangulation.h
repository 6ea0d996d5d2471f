// Linear (DLT) triangulation of one match seen from two camera poses, with the checks a
// monocular initialiser and a local mapper apply before accepting the point: finite, in front
// of both cameras, reprojected under a chi-square gate, and seen with enough parallax.
//
// Plain functions on fixed-size Eigen types: nothing is allocated.
#pragma once

#include "core/geometry/camera.h"
#include "core/geometry/chi_square.h"
#include "core/geometry/lie.h"

namespace ale::geometry {

// The first check a triangulation failed, in the order the checks run (kOk: all passed).
enum class TriangulationStatus {
  kOk = 0,
  kNotFinite,          // an input (pose, ray, pixel, sigma) is NaN/inf, or a sigma is not > 0
  kUnprojectFailed,    // a pixel could not be turned into a ray by the camera model
  kAtInfinity,         // the DLT solution is a point at infinity (parallel rays), or the two
                       // centres coincide so that no depth is determined
  kBehindFirst,        // depth in the first camera <= 0
  kBehindSecond,       // depth in the second camera <= 0
  kReprojectionFirst,  // squared reprojection error / sigma^2 above the gate in the first view
  kReprojectionSecond,
  kLowParallax,  // every other check passed, but cos(parallax) >= max_cos_parallax
};

const char* to_string(TriangulationStatus status);

struct TriangulationParams {
  // A point is accepted when the cosine of the angle between its two viewing rays is below
  // this (ORB-SLAM's initialiser: 0.99998, about 0.36 deg).
  double max_cos_parallax = 0.99998;
  // Gate on (squared reprojection error) / sigma^2: chi-square, 2 dof, 95 %.
  double chi2 = kChi2TwoDof95;
};

// Everything computed, filled as far as the checks got: a caller that treats low-parallax
// points like ORB-SLAM's CheckRT (counted as good, not created) reads status == kLowParallax.
struct Triangulation {
  TriangulationStatus status = TriangulationStatus::kNotFinite;
  Vec3 p_w = Vec3::Zero();    // valid from kBehindFirst on
  double cos_parallax = 1.0;  // between the two rays in the world; valid from kAtInfinity on
  double depth_1 = 0.0;       // z in each camera; valid from kBehindFirst on
  double depth_2 = 0.0;
  double err2_1 = 0.0;  // squared reprojection error in the observations' unit
  double err2_2 = 0.0;  //   (normalised plane or pixels); valid from kReprojection*
  bool ok() const { return status == TriangulationStatus::kOk; }
};

// The homogeneous DLT solution X_w (unit norm, the right singular vector of the 4x4 system for
// the smallest singular value) for rays (x, y, 1) on the normalised planes of the two cameras.
// No checks: the caller divides by X_w(3).
Vec4 triangulate_dlt(const SE3& T_1w, const SE3& T_2w, const Vec2& xn_1, const Vec2& xn_2);

// Observations on the normalised image planes (x, y) = (X/Z, Y/Z); sigma_1, sigma_2 are the
// observation noise in the same unit (a pixel sigma divided by the focal length).
Triangulation triangulate_normalised(const SE3& T_1w, const SE3& T_2w, const Vec2& xn_1, const Vec2& xn_2,
                                     double sigma_1, double sigma_2, const TriangulationParams& params = {});

// Observations as pixels of `camera` (an ideal pinhole for undistorted pixels, or a model with
// distortion for raw ones); sigma in pixels; the reprojection error is measured in pixels
// through the camera's projection.
Triangulation triangulate_pixels(const Camera& camera, const SE3& T_1w, const SE3& T_2w, const Vec2& uv_1,
                                 const Vec2& uv_2, double sigma_px_1, double sigma_px_2,
                                 const TriangulationParams& params = {});

}  // namespace ale::geometry
