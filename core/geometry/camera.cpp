#include "core/geometry/camera.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace ale::geometry {

namespace {

// Newton's stopping rule in normalised units (header: 1e-10) and its iteration budget. Newton
// on these smooth maps converges quadratically: EuRoC's corners need about 5 steps; 30 leaves
// room for strong fisheye lenses without letting a diverging start run long.
constexpr double kUnprojectTolerance = 1e-10;
constexpr int kMaxNewtonIterations = 30;

bool finite2(const Vec2& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); }

// Distorted normalised coordinates of (x, y) for the radial-tangential model, with the 2x2
// Jacobian d(x_d, y_d) / d(x, y) when asked.
Vec2 distort_radtan(const std::array<double, 5>& d, const Vec2& xy, Mat2* jac) {
  const double k1 = d[0], k2 = d[1], p1 = d[2], p2 = d[3], k3 = d[4];
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
  const Vec2 out(x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
                 y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y);
  if (jac) {
    const double d_radial_d_r2 = k1 + r2 * (2.0 * k2 + 3.0 * r2 * k3);
    (*jac)(0, 0) = radial + 2.0 * x * x * d_radial_d_r2 + 2.0 * p1 * y + 6.0 * p2 * x;
    (*jac)(0, 1) = 2.0 * x * y * d_radial_d_r2 + 2.0 * p1 * x + 2.0 * p2 * y;
    (*jac)(1, 0) = 2.0 * x * y * d_radial_d_r2 + 2.0 * p1 * x + 2.0 * p2 * y;
    (*jac)(1, 1) = radial + 2.0 * y * y * d_radial_d_r2 + 6.0 * p1 * y + 2.0 * p2 * x;
  }
  return out;
}

// theta_d(theta) = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8) and its
// derivative.
double equidistant_theta_d(const std::array<double, 5>& d, double theta, double* d_theta_d) {
  const double t2 = theta * theta;
  const double poly = 1.0 + t2 * (d[0] + t2 * (d[1] + t2 * (d[2] + t2 * d[3])));
  if (d_theta_d) *d_theta_d = 1.0 + t2 * (3.0 * d[0] + t2 * (5.0 * d[1] + t2 * (7.0 * d[2] + t2 * 9.0 * d[3])));
  return theta * poly;
}

// Equidistant: (x_d, y_d) = g(r) (x, y) with g = theta_d(atan r) / r, and Jacobian
// g I + (g'(r) / r) (x, y)^T (x, y).
Vec2 distort_equidistant(const std::array<double, 5>& d, const Vec2& xy, Mat2* jac) {
  const double r2 = xy.squaredNorm();
  double g, dg_over_r;
  if (r2 < 1e-8) {
    // theta_d(atan r) = r + a r^3 + b r^5 + O(r^7) with a = k1 - 1/3, b = 1/5 - k1 + k2; the
    // closed form of g'/r below would cancel to a few digits here.
    const double a = d[0] - 1.0 / 3.0, b = 0.2 - d[0] + d[1];
    g = 1.0 + r2 * (a + r2 * b);
    dg_over_r = 2.0 * a + 4.0 * b * r2;
  } else {
    const double r = std::sqrt(r2);
    const double theta = std::atan(r);
    double d_theta_d;
    const double theta_d = equidistant_theta_d(d, theta, &d_theta_d);
    g = theta_d / r;
    // g' = (theta_d'(theta) / (1 + r^2) - g) / r
    dg_over_r = (d_theta_d / (1.0 + r2) - g) / r2;
  }
  if (jac) *jac = g * Mat2::Identity() + dg_over_r * (xy * xy.transpose());
  return g * xy;
}

// Inverts the radial-tangential distortion by Newton's method from the distorted point. A root
// is accepted only where both eigenvalues of J have positive real part (det J > 0 and
// trace J > 0; without tangential terms they are the radial factor and its radial derivative):
// beyond the fold of a strong barrel distortion the polynomial bends back, or flips points
// through the centre, and has spurious roots that no real ray produces.
bool undistort_radtan(const std::array<double, 5>& d, const Vec2& xy_d, Vec2* xy) {
  Vec2 x = xy_d;
  Mat2 jac;
  for (int it = 0; it < kMaxNewtonIterations; ++it) {
    const Vec2 residual = distort_radtan(d, x, &jac) - xy_d;
    if (!finite2(residual)) return false;
    const double det = jac.determinant();
    const bool converged = residual.norm() < kUnprojectTolerance;
    if (converged && (!(det > 0.0) || !(jac.trace() > 0.0))) return false;
    if (!(std::abs(det) > 1e-12)) return false;
    // 2x2 inverse written out: J^-1 = [[d, -b], [-c, a]] / det
    const Vec2 step((jac(1, 1) * residual.x() - jac(0, 1) * residual.y()) / det,
                    (-jac(1, 0) * residual.x() + jac(0, 0) * residual.y()) / det);
    x -= step;
    // The step after convergence is almost free and, Newton being quadratic, takes the last
    // 1e-10 down to rounding (about 1e-13 px instead of 5e-8 px).
    if (converged) {
      *xy = x;
      return finite2(x);
    }
  }
  return false;
}

// Inverts theta_d(theta) in [0, pi/2) (in front of the camera) by Newton's method on the
// angle, accepting only roots where theta_d is increasing for the same reason as above.
bool undistort_equidistant(const std::array<double, 5>& d, const Vec2& xy_d, Vec2* xy) {
  const double theta_d = xy_d.norm();
  if (theta_d < 1e-300) {
    *xy = xy_d;
    return true;
  }
  constexpr double kHalfPi = 1.5707963267948966;
  double theta = std::min(theta_d, kHalfPi * 0.999);
  for (int it = 0; it < kMaxNewtonIterations; ++it) {
    double slope;
    const double residual = equidistant_theta_d(d, theta, &slope) - theta_d;
    if (!std::isfinite(residual)) return false;
    const bool converged = std::abs(residual) < kUnprojectTolerance;
    if (converged && !(slope > 0.0)) return false;
    if (!(std::abs(slope) > 1e-12)) return false;
    theta -= residual / slope;  // also after convergence, as above
    if (converged) {
      if (theta < 0.0 || theta >= kHalfPi) return false;
      *xy = xy_d * (std::tan(theta) / theta_d);
      return finite2(*xy);
    }
  }
  return false;
}

}  // namespace

Result<Camera> Camera::create(const CameraIntrinsics& k) {
  if (k.model != CameraModel::kPinholeRadTan && k.model != CameraModel::kEquidistant)
    return invalid_argument("camera: unknown model " + std::to_string(static_cast<int>(k.model)));
  const double values[] = {k.fx, k.fy, k.cx, k.cy};
  for (double v : values)
    if (!std::isfinite(v)) return invalid_argument("camera: fx, fy, cx, cy must be finite");
  for (double v : k.distortion)
    if (!std::isfinite(v)) return invalid_argument("camera: distortion coefficients must be finite");
  if (!(k.fx > 0.0) || !(k.fy > 0.0))
    return invalid_argument("camera: focal lengths must be positive, got fx " + std::to_string(k.fx) + " fy " +
                            std::to_string(k.fy));
  if (k.width < 0 || k.height < 0)
    return invalid_argument("camera: image size must not be negative, got " + std::to_string(k.width) + "x" +
                            std::to_string(k.height));
  if (k.model == CameraModel::kEquidistant && k.distortion[4] != 0.0)
    return invalid_argument("camera: the equidistant model has four coefficients (k1..k4); the fifth must be 0, got " +
                            std::to_string(k.distortion[4]));
  return Camera(k);
}

Camera::Camera(const CameraIntrinsics& k) : k_(k), ideal_(!has_distortion()) {}

Camera Camera::undistorted() const {
  CameraIntrinsics k = k_;
  k.model = CameraModel::kPinholeRadTan;
  k.distortion = {};
  return Camera(k);
}

bool Camera::has_distortion() const {
  // atan(r) bends every ray of the equidistant model, even with zero coefficients.
  if (k_.model == CameraModel::kEquidistant) return true;
  for (double v : k_.distortion)
    if (v != 0.0) return true;
  return false;
}

bool Camera::project(const Vec3& p_c, Vec2* uv, Mat23* d_uv_d_p) const {
  if (!(k_.fx > 0.0)) return false;  // a default-constructed (invalid) camera
  if (!std::isfinite(p_c.x()) || !std::isfinite(p_c.y()) || !std::isfinite(p_c.z())) return false;
  if (!(p_c.z() > 1e-9 * p_c.norm())) return false;
  const double inv_z = 1.0 / p_c.z();
  const Vec2 xy(p_c.x() * inv_z, p_c.y() * inv_z);
  if (ideal_) {
    // The radtan map with zero coefficients is the identity, bit for bit (radial == 1.0 and
    // every other term 0), so skipping it changes no result.
    const Vec2 out(k_.fx * xy.x() + k_.cx, k_.fy * xy.y() + k_.cy);
    if (!finite2(out)) return false;
    *uv = out;
    if (d_uv_d_p) {
      // the general path's products, in its order
      *d_uv_d_p << inv_z * k_.fx, 0.0, (-xy.x() * inv_z) * k_.fx,  //
          0.0, inv_z * k_.fy, (-xy.y() * inv_z) * k_.fy;
    }
    return true;
  }
  Mat2 d_xyd_d_xy;
  Mat2* jac = d_uv_d_p ? &d_xyd_d_xy : nullptr;
  Vec2 xy_d;
  if (k_.model == CameraModel::kEquidistant)
    xy_d = distort_equidistant(k_.distortion, xy, jac);
  else
    xy_d = distort_radtan(k_.distortion, xy, jac);
  const Vec2 out(k_.fx * xy_d.x() + k_.cx, k_.fy * xy_d.y() + k_.cy);
  if (!finite2(out)) return false;
  *uv = out;
  if (d_uv_d_p) {
    Mat23 d_xy_d_p;
    d_xy_d_p << inv_z, 0.0, -xy.x() * inv_z,  //
        0.0, inv_z, -xy.y() * inv_z;
    Mat23 j = d_xyd_d_xy * d_xy_d_p;
    j.row(0) *= k_.fx;
    j.row(1) *= k_.fy;
    *d_uv_d_p = j;
  }
  return true;
}

bool Camera::unproject(const Vec2& uv, Vec3* ray) const {
  if (!(k_.fx > 0.0) || !finite2(uv)) return false;
  const Vec2 xy_d((uv.x() - k_.cx) / k_.fx, (uv.y() - k_.cy) / k_.fy);
  Vec2 xy;
  bool ok;
  if (k_.model == CameraModel::kEquidistant) {
    ok = undistort_equidistant(k_.distortion, xy_d, &xy);
  } else if (!has_distortion()) {
    xy = xy_d;
    ok = true;
  } else {
    ok = undistort_radtan(k_.distortion, xy_d, &xy);
  }
  if (!ok) return false;
  *ray = Vec3(xy.x(), xy.y(), 1.0);
  return true;
}

bool Camera::undistort_pixel(const Vec2& distorted, Vec2* ideal) const {
  Vec3 ray;
  if (!unproject(distorted, &ray)) return false;
  *ideal = Vec2(k_.fx * ray.x() + k_.cx, k_.fy * ray.y() + k_.cy);
  return true;
}

}  // namespace ale::geometry
