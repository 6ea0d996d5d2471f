// Camera models: project a point in camera coordinates to a pixel, unproject a pixel to a ray,
// and the Jacobian of projection. One camera model for the whole tree (undistortion of
// keypoints, solvers, bundle adjustment).
//
// - Pinhole with radial-tangential distortion (EuRoC's "radtan", OpenCV's plumb bob), parameters
//   in OpenCV's order (k1, k2, p1, p2, k3). For normalised coordinates (x, y), r2 = x^2 + y^2:
//     x_d = x (1 + k1 r2 + k2 r2^2 + k3 r2^3) + 2 p1 x y + p2 (r2 + 2 x^2)
//     y_d = y (1 + k1 r2 + k2 r2^2 + k3 r2^3) + p1 (r2 + 2 y^2) + 2 p2 x y
//   With all coefficients 0 it is the ideal pinhole.
// - Equidistant (fisheye, OpenCV's cv::fisheye / Kalibr's "equidistant"), (k1, k2, k3, k4):
//     theta = atan(r), theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8),
//     (x_d, y_d) = (theta_d / r) (x, y).
// Pixels: u = fx x_d + cx, v = fy y_d + cy.
#pragma once

#include <array>

#include "core/base/status.h"
#include "core/geometry/lie.h"

namespace ale::geometry {

enum class CameraModel { kPinholeRadTan, kEquidistant };

struct CameraIntrinsics {
  CameraModel model = CameraModel::kPinholeRadTan;
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
  // radtan: k1 k2 p1 p2 k3; equidistant: k1 k2 k3 k4 (the fifth unused, 0).
  std::array<double, 5> distortion{};
  int width = 0, height = 0;  // image size in pixels (0: unknown)
};

class Camera {
 public:
  Camera() = default;  // an invalid camera: create() makes usable ones
  // kInvalidArgument when a focal length is not positive, a value is not finite, or the size is
  // negative.
  static Result<Camera> create(const CameraIntrinsics& intrinsics);
  // The ideal pinhole with the same fx fy cx cy and no distortion.
  Camera undistorted() const;

  const CameraIntrinsics& intrinsics() const { return k_; }
  bool has_distortion() const;

  // Pixel of a point in camera coordinates; false (uv untouched) when the point is not in
  // front of the camera (z <= 1e-9 relative to its distance) or not finite. d_uv_d_p, when
  // given, receives the 2x3 Jacobian of the pixel with respect to the point.
  bool project(const Vec3& p_c, Vec2* uv, Mat23* d_uv_d_p = nullptr) const;
  // Ray (x, y, 1) on the normalised plane through a pixel: the distortion is inverted by
  // Newton iterations; false when they do not converge to 1e-10 in normalised units or the
  // pixel is not finite. Also false where the root is not a real ray: the radial-tangential map
  // is not orientation preserving there (beyond the fold of a strong barrel distortion), or the
  // equidistant ray is 90 deg or more off axis (which (x, y, 1) cannot hold).
  bool unproject(const Vec2& uv, Vec3* ray) const;
  // The pixel the ideal pinhole (same fx fy cx cy) sees for a distorted pixel: unproject then
  // project without distortion. false as unproject.
  bool undistort_pixel(const Vec2& distorted, Vec2* ideal) const;

 private:
  explicit Camera(const CameraIntrinsics& k);
  CameraIntrinsics k_;
  bool ideal_ = false;  // radtan with every coefficient 0: project() skips the distortion
};

}  // namespace ale::geometry
