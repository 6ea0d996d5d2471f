#include "core/geometry/triangulation.h"

#include <Eigen/SVD>
#include <cmath>

namespace ale::geometry {

const char* to_string(TriangulationStatus status) {
  switch (status) {
    case TriangulationStatus::kOk: return "ok";
    case TriangulationStatus::kNotFinite: return "input not finite";
    case TriangulationStatus::kUnprojectFailed: return "pixel could not be unprojected";
    case TriangulationStatus::kAtInfinity: return "point at infinity";
    case TriangulationStatus::kBehindFirst: return "behind the first camera";
    case TriangulationStatus::kBehindSecond: return "behind the second camera";
    case TriangulationStatus::kReprojectionFirst: return "reprojection error in the first view above the gate";
    case TriangulationStatus::kReprojectionSecond: return "reprojection error in the second view above the gate";
    case TriangulationStatus::kLowParallax: return "parallax too low";
  }
  return "unknown";
}

namespace {

bool finite_pose(const SE3& T) { return T.so3().quaternion().coeffs().allFinite() && T.translation().allFinite(); }

bool valid_sigma(double sigma) { return std::isfinite(sigma) && sigma > 0.0; }

// The DLT solution; *null_ratio (when given) receives the second-smallest over the largest
// singular value, which is ~0 when the solution is not unique (no baseline).
Vec4 dlt(const SE3& T_1w, const SE3& T_2w, const Vec2& xn_1, const Vec2& xn_2, double* null_ratio) {
  Eigen::Matrix<double, 3, 4> P1, P2;
  P1 << T_1w.rotation(), T_1w.translation();
  P2 << T_2w.rotation(), T_2w.translation();
  // x * (P.row(2) X) = P.row(0) X and y * (P.row(2) X) = P.row(1) X for each view.
  Mat4 A;
  A.row(0) = xn_1.x() * P1.row(2) - P1.row(0);
  A.row(1) = xn_1.y() * P1.row(2) - P1.row(1);
  A.row(2) = xn_2.x() * P2.row(2) - P2.row(0);
  A.row(3) = xn_2.y() * P2.row(2) - P2.row(1);
  const Eigen::JacobiSVD<Mat4> svd(A, Eigen::ComputeFullV);
  if (null_ratio) {
    const Vec4& sv = svd.singularValues();
    *null_ratio = sv(0) > 0.0 ? sv(2) / sv(0) : 0.0;
  }
  return svd.matrixV().col(3);
}

// The checks shared by both observation kinds; `err2_in_view(i, p_c)` gives the squared
// reprojection error of a camera-frame point in view i (false when it cannot be projected).
template <class Err2>
Triangulation triangulate_checked(const SE3& T_1w, const SE3& T_2w, const Vec2& xn_1, const Vec2& xn_2, double sigma_1,
                                  double sigma_2, const TriangulationParams& params, const Err2& err2_in_view) {
  Triangulation out;
  const Mat3 R_1w = T_1w.rotation();
  const Mat3 R_2w = T_2w.rotation();
  // Parallax from the rays alone, so that it is known even for points the DLT cannot place.
  const Vec3 ray_1w = R_1w.transpose() * xn_1.homogeneous();
  const Vec3 ray_2w = R_2w.transpose() * xn_2.homogeneous();
  out.cos_parallax = ray_1w.dot(ray_2w) / (ray_1w.norm() * ray_2w.norm());

  double null_ratio = 0.0;
  const Vec4 X = dlt(T_1w, T_2w, xn_1, xn_2, &null_ratio);
  // |w| relative to the unit-norm solution: below this the point is farther than ~1e9 times
  // the coordinates' scale, which float maps and depth checks cannot use. A second null
  // direction means both centres coincide (pure rotation): any depth fits the rays.
  constexpr double kMinW = 1e-9;
  constexpr double kMinNullRatio = 1e-10;
  if (!X.allFinite() || std::abs(X(3)) < kMinW || null_ratio < kMinNullRatio) {
    out.status = TriangulationStatus::kAtInfinity;
    return out;
  }
  out.p_w = X.head<3>() / X(3);
  const Vec3 p_1 = R_1w * out.p_w + T_1w.translation();
  const Vec3 p_2 = R_2w * out.p_w + T_2w.translation();
  out.depth_1 = p_1.z();
  out.depth_2 = p_2.z();
  if (!(out.depth_1 > 0.0)) {
    out.status = TriangulationStatus::kBehindFirst;
    return out;
  }
  if (!(out.depth_2 > 0.0)) {
    out.status = TriangulationStatus::kBehindSecond;
    return out;
  }
  if (!err2_in_view(0, p_1, &out.err2_1) || !(out.err2_1 <= params.chi2 * sigma_1 * sigma_1)) {
    out.status = TriangulationStatus::kReprojectionFirst;
    return out;
  }
  if (!err2_in_view(1, p_2, &out.err2_2) || !(out.err2_2 <= params.chi2 * sigma_2 * sigma_2)) {
    out.status = TriangulationStatus::kReprojectionSecond;
    return out;
  }
  out.status =
      out.cos_parallax < params.max_cos_parallax ? TriangulationStatus::kOk : TriangulationStatus::kLowParallax;
  return out;
}

}  // namespace

Vec4 triangulate_dlt(const SE3& T_1w, const SE3& T_2w, const Vec2& xn_1, const Vec2& xn_2) {
  return dlt(T_1w, T_2w, xn_1, xn_2, nullptr);
}

Triangulation triangulate_normalised(const SE3& T_1w, const SE3& T_2w, const Vec2& xn_1, const Vec2& xn_2,
                                     double sigma_1, double sigma_2, const TriangulationParams& params) {
  if (!finite_pose(T_1w) || !finite_pose(T_2w) || !xn_1.allFinite() || !xn_2.allFinite() || !valid_sigma(sigma_1) ||
      !valid_sigma(sigma_2)) {
    return Triangulation{};
  }
  const auto err2 = [&](int view, const Vec3& p_c, double* e2) {
    const Vec2& obs = view == 0 ? xn_1 : xn_2;
    *e2 = (p_c.head<2>() / p_c.z() - obs).squaredNorm();
    return true;
  };
  return triangulate_checked(T_1w, T_2w, xn_1, xn_2, sigma_1, sigma_2, params, err2);
}

Triangulation triangulate_pixels(const Camera& camera, const SE3& T_1w, const SE3& T_2w, const Vec2& uv_1,
                                 const Vec2& uv_2, double sigma_px_1, double sigma_px_2,
                                 const TriangulationParams& params) {
  if (!finite_pose(T_1w) || !finite_pose(T_2w) || !uv_1.allFinite() || !uv_2.allFinite() || !valid_sigma(sigma_px_1) ||
      !valid_sigma(sigma_px_2)) {
    return Triangulation{};
  }
  Vec3 ray_1, ray_2;
  if (!camera.unproject(uv_1, &ray_1) || !camera.unproject(uv_2, &ray_2)) {
    Triangulation out;
    out.status = TriangulationStatus::kUnprojectFailed;
    return out;
  }
  const auto err2 = [&](int view, const Vec3& p_c, double* e2) {
    Vec2 uv;
    if (!camera.project(p_c, &uv)) return false;
    *e2 = (uv - (view == 0 ? uv_1 : uv_2)).squaredNorm();
    return true;
  };
  return triangulate_checked(T_1w, T_2w, ray_1.head<2>() / ray_1.z(), ray_2.head<2>() / ray_2.z(), sigma_px_1,
                             sigma_px_2, params, err2);
}

}  // namespace ale::geometry
