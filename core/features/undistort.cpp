#include "core/features/undistort.h"

#include <cmath>
#include <string>

namespace ale::features {

Status validate(const RadTanCamera& c) {
  const double all[] = {c.fx, c.fy, c.cx, c.cy, c.k1, c.k2, c.p1, c.p2, c.k3};
  for (double v : all)
    if (!std::isfinite(v)) return invalid_argument("camera: a value is not finite");
  if (c.fx <= 0.0 || c.fy <= 0.0)
    return invalid_argument("camera: focal lengths must be positive, got fx " + std::to_string(c.fx) + " fy " +
                            std::to_string(c.fy));
  return {};
}

namespace {

// Distorted normalised coordinates of undistorted normalised (x, y).
Point2 distort_normalised(const RadTanCamera& c, double x, double y) {
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (c.k1 + r2 * (c.k2 + r2 * c.k3));
  return {x * radial + 2.0 * c.p1 * x * y + c.p2 * (r2 + 2.0 * x * x),
          y * radial + c.p1 * (r2 + 2.0 * y * y) + 2.0 * c.p2 * x * y};
}

}  // namespace

Point2 distort_pixel(const RadTanCamera& c, Point2 u) {
  const Point2 d = distort_normalised(c, (u.x - c.cx) / c.fx, (u.y - c.cy) / c.fy);
  return {d.x * c.fx + c.cx, d.y * c.fy + c.cy};
}

Point2 undistort_pixel(const RadTanCamera& c, Point2 d, int iterations) {
  const double xd = (d.x - c.cx) / c.fx;
  const double yd = (d.y - c.cy) / c.fy;
  double x = xd;
  double y = yd;
  // x = (x_d - tangential(x, y)) / radial(x, y), starting from the distorted point.
  for (int i = 0; i < iterations; ++i) {
    const double r2 = x * x + y * y;
    const double radial = 1.0 + r2 * (c.k1 + r2 * (c.k2 + r2 * c.k3));
    const double dx = 2.0 * c.p1 * x * y + c.p2 * (r2 + 2.0 * x * x);
    const double dy = c.p1 * (r2 + 2.0 * y * y) + 2.0 * c.p2 * x * y;
    x = (xd - dx) / radial;
    y = (yd - dy) / radial;
  }
  return {x * c.fx + c.cx, y * c.fy + c.cy};
}

void undistort_pixels(const RadTanCamera& cam, const std::vector<Point2>& in, std::vector<Point2>& out,
                      int iterations) {
  out.resize(in.size());
  for (std::size_t i = 0; i < in.size(); ++i) out[i] = undistort_pixel(cam, in[i], iterations);
}

}  // namespace ale::features
