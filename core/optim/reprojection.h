// The reprojection residual r = project(T_cw * p_w) - uv_obs, with the camera model as a
// parameter, and its analytic Jacobians. Pose Jacobians are for the left perturbation
// T_cw <- exp(xi) T_cw with xi = (rho, phi) (core/geometry/lie.h):
//   d_res_d_pose  = d_uv_d_pc * [I, -hat(p_c)]     (2x6)
//   d_res_d_point = d_uv_d_pc * R_cw                (2x3)
#pragma once

#include "core/geometry/camera.h"
#include "core/geometry/lie.h"

namespace ale::optim {

// False (outputs untouched) when the point is not in front of the camera or the projection is
// not finite; the Jacobian pointers may be null.
// The pose as R_cw, t_cw (optimisers keep the rotation matrix of each pose for all its
// observations instead of rebuilding it from the quaternion).
inline bool reprojection_residual(const geometry::Camera& camera, const geometry::Mat3& R_cw,
                                  const geometry::Vec3& t_cw, const geometry::Vec3& p_w,
                                  const geometry::Vec2& uv_obs_px, geometry::Vec2* res,
                                  geometry::Mat26* d_res_d_pose, geometry::Mat23* d_res_d_point) {
  const geometry::Vec3 p_c = R_cw * p_w + t_cw;
  geometry::Vec2 uv;
  geometry::Mat23 d_uv_d_pc;
  const bool want_jacobian = d_res_d_pose != nullptr || d_res_d_point != nullptr;
  if (!camera.project(p_c, &uv, want_jacobian ? &d_uv_d_pc : nullptr)) return false;
  *res = uv - uv_obs_px;
  if (d_res_d_pose != nullptr) {
    d_res_d_pose->leftCols<3>() = d_uv_d_pc;
    // d_uv_d_pc * (-hat(p_c)) written out: column k of -hat(p_c) is p_c x e_k.
    const geometry::Vec3& q = p_c;
    d_res_d_pose->col(3) = d_uv_d_pc.col(1) * (-q.z()) + d_uv_d_pc.col(2) * q.y();
    d_res_d_pose->col(4) = d_uv_d_pc.col(0) * q.z() - d_uv_d_pc.col(2) * q.x();
    d_res_d_pose->col(5) = -d_uv_d_pc.col(0) * q.y() + d_uv_d_pc.col(1) * q.x();
  }
  if (d_res_d_point != nullptr) *d_res_d_point = d_uv_d_pc * R_cw;
  return true;
}

// A point on a plane fixed in the camera frame: r = n_c . p_c + offset with p_c = R_cw p_w + t_cw
// (n_c a unit normal; for a floor landmark the camera's height is the offset). Jacobians as rows:
// d r / d pose = n_c^T [I, -hat(p_c)] = [n_c^T, (p_c x n_c)^T], d r / d point = n_c^T R_cw. False
// (outputs untouched) when the point is not in front of the camera.
inline bool plane_residual(const geometry::Mat3& R_cw, const geometry::Vec3& t_cw, const geometry::Vec3& p_w,
                           const geometry::Vec3& normal_c, double offset, double* res,
                           Eigen::Matrix<double, 1, 6>* d_res_d_pose, Eigen::Matrix<double, 1, 3>* d_res_d_point) {
  const geometry::Vec3 p_c = R_cw * p_w + t_cw;
  if (!(p_c.z() > 0.0)) return false;
  *res = normal_c.dot(p_c) + offset;
  if (d_res_d_pose != nullptr) {
    d_res_d_pose->head<3>() = normal_c.transpose();
    d_res_d_pose->tail<3>() = p_c.cross(normal_c).transpose();
  }
  if (d_res_d_point != nullptr) *d_res_d_point = normal_c.transpose() * R_cw;
  return true;
}

// A prior on a pose's camera centre c = -R_cw^T t_cw: the residual c - centre_w (metres or map
// units).
inline geometry::Vec3 centre_residual(const geometry::Mat3& R_cw, const geometry::Vec3& t_cw,
                                      const geometry::Vec3& centre_w) {
  return -(R_cw.transpose() * t_cw) - centre_w;
}

// Its share of the pose's normal equations with IRLS weight w (information x rho'): under the
// left perturbation exp((rho, phi)) T, dc/drho = -R^T and dc/dphi = 0, so h's translation block
// gains w I and g's translation part -w R e.
template <class H, class G>
inline void add_centre_normal_equations(H& h, G& g, const geometry::Mat3& R_cw, const geometry::Vec3& e, double w) {
  h.template topLeftCorner<3, 3>() += w * geometry::Mat3::Identity();
  g.template head<3>() += -w * (R_cw * e);
}

// A rotation prior's residual: log(R_cw R_target^T), the rotation (radians, world-to-camera
// side) that takes the target to the pose's rotation.
inline geometry::Vec3 rotation_residual(const geometry::Mat3& R_cw, const geometry::Mat3& R_target) {
  return geometry::SO3::from_matrix(R_cw * R_target.transpose()).log();
}

// Its share of the pose's normal equations with IRLS weight w: under the left perturbation
// exp((rho, phi)) T, log(exp(phi) R R_target^T) = e + J_l(e)^-1 phi, taken as e + phi (the
// residual is small): h's rotation block gains w I and g's rotation part w e.
template <class H, class G>
inline void add_rotation_normal_equations(H& h, G& g, const geometry::Vec3& e, double w) {
  h.template bottomRightCorner<3, 3>() += w * geometry::Mat3::Identity();
  g.template tail<3>() += w * e;
}

inline bool reprojection_residual(const geometry::Camera& camera, const geometry::SE3& T_cw,
                                  const geometry::Vec3& p_w, const geometry::Vec2& uv_obs_px,
                                  geometry::Vec2* res, geometry::Mat26* d_res_d_pose = nullptr,
                                  geometry::Mat23* d_res_d_point = nullptr) {
  return reprojection_residual(camera, T_cw.rotation(), T_cw.translation(), p_w, uv_obs_px, res,
                               d_res_d_pose, d_res_d_point);
}

}  // namespace ale::optim
