// Keypoint undistortion for the radial-tangential (plumb bob) model, as in EuRoC's sensor.yaml
// and OpenCV's (k1, k2, p1, p2, k3): for normalised coordinates (x, y), r^2 = x^2 + y^2,
//   x_d = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2)
//   y_d = y (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y^2) + 2 p2 x y
// Undistortion inverts this by fixed-point iteration, the method of cv::undistortPoints.
#pragma once

#include <vector>

#include "core/base/status.h"

namespace ale::features {

struct RadTanCamera {
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
  double k1 = 0.0, k2 = 0.0, p1 = 0.0, p2 = 0.0, k3 = 0.0;
};

struct Point2 {
  double x = 0.0;
  double y = 0.0;
};

// kInvalidArgument when a focal length is not positive or a value is not finite.
Status validate(const RadTanCamera& cam);

// Pixel of an ideal (undistorted) pixel: the forward model.
Point2 distort_pixel(const RadTanCamera& cam, Point2 undistorted);

// Ideal pixel of a distorted pixel: `iterations` fixed-point steps (cv::undistortPoints uses 5;
// EuRoC's strong barrel distortion needs 20 for 1e-3 px in the image corners). The result is in pixels of the same camera matrix.
Point2 undistort_pixel(const RadTanCamera& cam, Point2 distorted, int iterations = 20);

// Undistorts `in` into `out` (resized to match).
void undistort_pixels(const RadTanCamera& cam, const std::vector<Point2>& in, std::vector<Point2>& out,
                      int iterations = 20);

}  // namespace ale::features
