// Rotations, rigid motions and similarities: SO(3), SE(3), Sim(3) with exp/log, composition,
// inverse and adjoint.
//
// Conventions, used everywhere in ale-slam (solvers, optimisers, map, messages):
// - A transform T_ab maps coordinates in frame b to frame a: p_a = T_ab * p_b. A camera pose
//   is T_cw (world to camera); its inverse T_wc is the camera's pose in the world.
// - Tangent vectors put translation first: se(3) xi = (rho, phi), sim(3) zeta = (rho, phi,
//   sigma) with scale s = exp(sigma). phi is an axis-angle rotation vector.
// - Perturbations are on the LEFT: T (+) delta = exp(delta) * T. Jacobians are named
//   d_<residual>_d_<state> and taken with respect to that left perturbation at delta = 0.
//   For p_c = T_cw * p_w: d p_c / d xi = [ I, -hat(p_c) ].
// - exp and log are accurate near 0 (series expansions) and near pi (SO3 keeps a unit
//   quaternion; from_matrix takes it from the matrix by Shepperd's method, which divides by the
//   largest of w, x, y, z, and log uses atan2 of the half angle's sine and cosine, so the axis
//   does not vanish with the skew part); log's rotation has norm in [0, pi].
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace ale::geometry {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Vec4 = Eigen::Vector4d;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Vec7 = Eigen::Matrix<double, 7, 1>;
using Mat2 = Eigen::Matrix2d;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat7 = Eigen::Matrix<double, 7, 7>;
using Mat23 = Eigen::Matrix<double, 2, 3>;
using Mat26 = Eigen::Matrix<double, 2, 6>;

// Skew-symmetric matrix of w: hat(w) * v = w x v.
Mat3 hat(const Vec3& w);
// Inverse of hat (reads the off-diagonal entries).
Vec3 vee(const Mat3& m);

class SO3 {
 public:
  SO3() = default;  // identity
  // From a unit quaternion (normalised here).
  explicit SO3(const Eigen::Quaterniond& q);
  // From a quaternion kept bit for bit (a file's copy of a quaternion() written before): the
  // caller has checked it is unit to rounding.
  static SO3 from_unit_quaternion(const Eigen::Quaterniond& q) {
    SO3 r;
    r.q_ = q;
    return r;
  }
  // The rotation nearest to m (orthonormalised); m should be close to a rotation.
  static SO3 from_matrix(const Mat3& m);
  static SO3 exp(const Vec3& phi);
  Vec3 log() const;

  Mat3 matrix() const;
  const Eigen::Quaterniond& quaternion() const { return q_; }
  SO3 inverse() const;
  SO3 operator*(const SO3& other) const;
  Vec3 operator*(const Vec3& p) const;
  // Adjoint: R, so that exp(Ad * phi) * R = R * exp(phi).
  Mat3 adjoint() const { return matrix(); }

  // Left Jacobian of SO(3) and its inverse at phi.
  static Mat3 left_jacobian(const Vec3& phi);
  static Mat3 left_jacobian_inverse(const Vec3& phi);
  // Right Jacobian J_r(phi) = J_l(-phi): exp(phi + d) = exp(phi) exp(J_r(phi) d) to first order
  // (and exp(phi + d) = exp(J_l(phi) d) exp(phi)).
  static Mat3 right_jacobian(const Vec3& phi);
  static Mat3 right_jacobian_inverse(const Vec3& phi);

 private:
  Eigen::Quaterniond q_ = Eigen::Quaterniond::Identity();
};

class SE3 {
 public:
  SE3() = default;  // identity
  SE3(const SO3& r, const Vec3& t) : r_(r), t_(t) {}
  static SE3 exp(const Vec6& xi);  // xi = (rho, phi): R = exp(phi), t = J_l(phi) rho
  Vec6 log() const;

  const SO3& so3() const { return r_; }
  Mat3 rotation() const { return r_.matrix(); }
  const Vec3& translation() const { return t_; }
  Mat4 matrix() const;
  SE3 inverse() const;
  SE3 operator*(const SE3& other) const;
  Vec3 operator*(const Vec3& p) const;
  // The same pose in a map scaled by `factor` about its origin (or a relative pose between two
  // such poses): the rotation kept, the translation times factor.
  SE3 scaled(double factor) const { return SE3(r_, factor * t_); }
  // 6x6 adjoint for (rho, phi) ordering: [[R, hat(t) R], [0, R]];
  // exp(Ad * xi) * T = T * exp(xi).
  Mat6 adjoint() const;

  // The algebra's adjoint ad(xi) = [[hat(phi), hat(rho)], [0, hat(phi)]]: ad(a) b = [a, b].
  static Mat6 ad(const Vec6& xi);
  // Left Jacobian of SE(3): exp(xi + d) = exp(J_l(xi) d) exp(xi) to first order (the right
  // Jacobian is J_l(-xi)). Summed as sum_n ad(xi)^n / (n + 1)!, accurate for |phi| <= pi.
  static Mat6 left_jacobian(const Vec6& xi);
  static Mat6 left_jacobian_inverse(const Vec6& xi);

 private:
  SO3 r_;
  Vec3 t_ = Vec3::Zero();
};

// The camera's centre in the world for a world-to-camera pose T_cw.
inline Vec3 camera_centre(const SE3& T_cw) { return T_cw.inverse().translation(); }

class Sim3 {
 public:
  Sim3() = default;  // identity
  Sim3(const SO3& r, const Vec3& t, double scale) : r_(r), t_(t), s_(scale) {}
  explicit Sim3(const SE3& t) : r_(t.so3()), t_(t.translation()), s_(1.0) {}
  static Sim3 exp(const Vec7& zeta);  // zeta = (rho, phi, sigma), scale = exp(sigma)
  Vec7 log() const;

  const SO3& so3() const { return r_; }
  Mat3 rotation() const { return r_.matrix(); }
  const Vec3& translation() const { return t_; }
  double scale() const { return s_; }
  Mat4 matrix() const;
  Sim3 inverse() const;
  Sim3 operator*(const Sim3& other) const;
  Vec3 operator*(const Vec3& p) const;  // s R p + t
  // 7x7 adjoint for (rho, phi, sigma) ordering: exp(Ad * zeta) * S = S * exp(zeta).
  Mat7 adjoint() const;

  // ad(zeta) = [[hat(phi) + sigma I, hat(rho), -rho], [0, hat(phi), 0], [0, 0, 0]].
  static Mat7 ad(const Vec7& zeta);
  // Left Jacobian of Sim(3): exp(zeta + d) = exp(J_l(zeta) d) exp(zeta) to first order (the
  // right Jacobian is J_l(-zeta)); summed as for SE(3), for |phi| <= pi.
  static Mat7 left_jacobian(const Vec7& zeta);
  static Mat7 left_jacobian_inverse(const Vec7& zeta);

  // The 3x3 matrix W(phi, sigma) with exp(zeta).translation() = W * rho: the integral over u in
  // [0, 1] of exp(u sigma) R(u phi). With sigma = 0 it is SO3::left_jacobian(phi).
  static Mat3 translation_jacobian(const Vec3& phi, double sigma);

 private:
  SO3 r_;
  Vec3 t_ = Vec3::Zero();
  double s_ = 1.0;
};

}  // namespace ale::geometry
