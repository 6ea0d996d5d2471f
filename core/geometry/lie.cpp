#include "core/geometry/lie.h"

#include "core/geometry/portable_math.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>
#include <Eigen/SVD>

namespace ale::geometry {

namespace {

// Below this angle the trigonometric ratios are replaced by their Taylor series: the series'
// first dropped term is then below 1e-20 while the closed forms lose digits to cancellation.
constexpr double kSmallAngle = 1e-4;

// (1 - cos t) / t^2 and (t - sin t) / t^3, the coefficients of hat(phi) and hat(phi)^2 in the
// left Jacobian.
void left_jacobian_coefficients(double theta, double* a, double* b) {
  if (theta < kSmallAngle) {
    const double t2 = theta * theta;
    *a = 0.5 - t2 / 24.0 + t2 * t2 / 720.0;
    *b = 1.0 / 6.0 - t2 / 120.0 + t2 * t2 / 5040.0;
    return;
  }
  // 1 - cos t = 2 sin^2(t/2) keeps a's digits for small t; b's cancellation costs about
  // eps / t^2 relative, which its factor hat(phi)^2 ~ t^2 brings back to eps absolute.
  const double t2 = theta * theta;
  const double sinc_half = std::sin(0.5 * theta) / (0.5 * theta);
  *a = 0.5 * sinc_half * sinc_half;
  *b = (theta - std::sin(theta)) / (t2 * theta);
}

// J_l = sum_n ad^n / (n + 1)!. The eigenvalues of ad are 0, +-i theta and sigma +- i theta
// (no rho: it only enters the nilpotent part), so for theta <= pi and moderate sigma the terms
// shrink quickly and never grow large enough to cancel; the sum stops when a term is below
// 1e-18 of the identity, or after 60 terms.
template <int N>
Eigen::Matrix<double, N, N> left_jacobian_series(const Eigen::Matrix<double, N, N>& ad) {
  using M = Eigen::Matrix<double, N, N>;
  M sum = M::Identity();
  M term = M::Identity();
  for (int n = 1; n < 60; ++n) {
    term = term * ad / static_cast<double>(n + 1);
    sum += term;
    if (term.cwiseAbs().maxCoeff() < 1e-18 * std::max(1.0, sum.cwiseAbs().maxCoeff())) break;
  }
  return sum;
}

}  // namespace

Mat3 hat(const Vec3& w) {
  Mat3 m;
  m << 0.0, -w.z(), w.y(),  //
      w.z(), 0.0, -w.x(),   //
      -w.y(), w.x(), 0.0;
  return m;
}

Vec3 vee(const Mat3& m) { return Vec3(m(2, 1), m(0, 2), m(1, 0)); }

// ---- SO(3) ----

SO3::SO3(const Eigen::Quaterniond& q) : q_(q.normalized()) {}

SO3 SO3::from_matrix(const Mat3& m) {
  // The nearest rotation in the Frobenius norm is U V^T, with the last singular vector flipped
  // when that would be a reflection.
  const Eigen::JacobiSVD<Mat3> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 d = Mat3::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) d(2, 2) = -1.0;
  const Mat3 r = svd.matrixU() * d * svd.matrixV().transpose();
  // Eigen's matrix-to-quaternion conversion picks the largest of w, x, y, z to divide by
  // (Shepperd's method), so the axis stays accurate near pi where the skew part vanishes.
  return SO3(Eigen::Quaterniond(r));
}

SO3 SO3::exp(const Vec3& phi) {
  const double theta = phi.norm();
  const double half = 0.5 * theta;
  double w, k;  // q = (cos(theta/2), sin(theta/2)/theta * phi)
  if (theta < kSmallAngle) {
    const double t2 = theta * theta;
    w = 1.0 - t2 / 8.0 + t2 * t2 / 384.0;
    k = 0.5 - t2 / 48.0 + t2 * t2 / 3840.0;
  } else {
    w = std::cos(half);
    k = std::sin(half) / theta;
  }
  SO3 r;
  r.q_ = Eigen::Quaterniond(w, k * phi.x(), k * phi.y(), k * phi.z());
  r.q_.normalize();
  return r;
}

Vec3 SO3::log() const {
  // q and -q are the same rotation; w >= 0 keeps the angle in [0, pi].
  const double sign = q_.w() < 0.0 ? -1.0 : 1.0;
  const double w = sign * q_.w();
  const Vec3 v = sign * q_.vec();
  const double n = v.norm();
  // atan2 of the sine and cosine of the half angle is well conditioned everywhere, including
  // at pi (w = 0) where acos(w) or asin(n) would lose half their digits.
  double factor;  // theta / n, with theta = 2 atan2(n, w)
  if (n < kSmallAngle * 0.5) {
    // 2 atan(n / w) / n = (2 / w) (1 - n^2 / (3 w^2) + n^4 / (5 w^4)); w is close to 1 here.
    const double r2 = (n * n) / (w * w);
    factor = (2.0 / w) * (1.0 - r2 / 3.0 + r2 * r2 / 5.0);
  } else {
    factor = 2.0 * std::atan2(n, w) / n;
  }
  return factor * v;
}

Mat3 SO3::matrix() const { return q_.toRotationMatrix(); }

SO3 SO3::inverse() const {
  SO3 r;
  r.q_ = q_.conjugate();
  return r;
}

SO3 SO3::operator*(const SO3& other) const {
  SO3 r;
  // Renormalised so that long chains of compositions stay rotations.
  r.q_ = (q_ * other.q_).normalized();
  return r;
}

Vec3 SO3::operator*(const Vec3& p) const { return q_ * p; }

Mat3 SO3::left_jacobian(const Vec3& phi) {
  double a, b;
  left_jacobian_coefficients(phi.norm(), &a, &b);
  const Mat3 h = hat(phi);
  return Mat3::Identity() + a * h + b * h * h;
}

Mat3 SO3::left_jacobian_inverse(const Vec3& phi) {
  const double theta = phi.norm();
  // J_l^-1 = I - hat/2 + c hat^2 with c = (1 - (theta/2) cot(theta/2)) / theta^2, which stays
  // finite at theta = pi (where the textbook form (1 + cos) / (2 theta sin) is 0/0).
  double c;
  if (theta < kSmallAngle) {
    const double t2 = theta * theta;
    c = 1.0 / 12.0 + t2 / 720.0 + t2 * t2 / 30240.0;
  } else {
    const double half = 0.5 * theta;
    c = (1.0 - half * std::cos(half) / std::sin(half)) / (theta * theta);
  }
  const Mat3 h = hat(phi);
  return Mat3::Identity() - 0.5 * h + c * h * h;
}

Mat3 SO3::right_jacobian(const Vec3& phi) { return left_jacobian(-phi); }

Mat3 SO3::right_jacobian_inverse(const Vec3& phi) { return left_jacobian_inverse(-phi); }

// ---- SE(3) ----

SE3 SE3::exp(const Vec6& xi) {
  const Vec3 rho = xi.head<3>();
  const Vec3 phi = xi.tail<3>();
  return SE3(SO3::exp(phi), SO3::left_jacobian(phi) * rho);
}

Vec6 SE3::log() const {
  const Vec3 phi = r_.log();
  Vec6 xi;
  xi.head<3>() = SO3::left_jacobian_inverse(phi) * t_;
  xi.tail<3>() = phi;
  return xi;
}

Mat4 SE3::matrix() const {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = r_.matrix();
  m.topRightCorner<3, 1>() = t_;
  return m;
}

SE3 SE3::inverse() const {
  const SO3 r_inv = r_.inverse();
  return SE3(r_inv, -(r_inv * t_));
}

SE3 SE3::operator*(const SE3& other) const { return SE3(r_ * other.r_, r_ * other.t_ + t_); }

Vec3 SE3::operator*(const Vec3& p) const { return r_ * p + t_; }

Mat6 SE3::adjoint() const {
  const Mat3 r = r_.matrix();
  Mat6 ad = Mat6::Zero();
  ad.topLeftCorner<3, 3>() = r;
  ad.topRightCorner<3, 3>() = hat(t_) * r;
  ad.bottomRightCorner<3, 3>() = r;
  return ad;
}

Mat6 SE3::ad(const Vec6& xi) {
  Mat6 a = Mat6::Zero();
  const Mat3 phi_hat = hat(xi.tail<3>());
  a.topLeftCorner<3, 3>() = phi_hat;
  a.topRightCorner<3, 3>() = hat(xi.head<3>());
  a.bottomRightCorner<3, 3>() = phi_hat;
  return a;
}

Mat6 SE3::left_jacobian(const Vec6& xi) { return left_jacobian_series<6>(ad(xi)); }

Mat6 SE3::left_jacobian_inverse(const Vec6& xi) { return left_jacobian(xi).partialPivLu().inverse(); }

// ---- Sim(3) ----

Mat7 Sim3::ad(const Vec7& zeta) {
  // From the bracket of [[sigma I + hat(phi), rho], [0, 0]] generators:
  // rho' = (hat(phi1) + sigma1) rho2 + hat(rho1) phi2 - sigma2 rho1, phi' = phi1 x phi2.
  Mat7 a = Mat7::Zero();
  const Mat3 phi_hat = hat(zeta.segment<3>(3));
  a.block<3, 3>(0, 0) = phi_hat + zeta[6] * Mat3::Identity();
  a.block<3, 3>(0, 3) = hat(zeta.head<3>());
  a.block<3, 1>(0, 6) = -zeta.head<3>();
  a.block<3, 3>(3, 3) = phi_hat;
  return a;
}

Mat7 Sim3::left_jacobian(const Vec7& zeta) { return left_jacobian_series<7>(ad(zeta)); }

Mat7 Sim3::left_jacobian_inverse(const Vec7& zeta) { return left_jacobian(zeta).partialPivLu().inverse(); }

Mat3 Sim3::translation_jacobian(const Vec3& phi, double sigma) {
  // W = integral over u in [0, 1] of exp(u sigma) R(u phi) du, the matrix that maps rho to the
  // translation of exp(zeta). Near the origin of (sigma, theta) its closed form divides small
  // differences by small numbers, so there it is summed as its series
  // W = sum_n A^n / (n + 1)! with A = sigma I + hat(phi); for |sigma| + theta < 0.1 fourteen
  // terms leave an error below 1e-25.
  const double theta = phi.norm();
  if (std::abs(sigma) + theta < 0.1) {
    const Mat3 a = sigma * Mat3::Identity() + hat(phi);
    // Horner: W = I + (A/2)(I + (A/3)(I + ... (I + A/15))), the terms up to A^14 / 15!.
    Mat3 w = Mat3::Identity();
    for (int n = 13; n >= 0; --n) w = Mat3::Identity() + a * w / static_cast<double>(n + 2);
    return w;
  }
  // C0 = (e^s - 1)/s, and with K the unit axis, W = C0 I + C1 K + C2 K^2 where
  // C1 = int e^{us} sin(u theta), C2 = int e^{us} (1 - cos(u theta)).
  const double es = portable_exp(sigma);
  const double c0 = std::abs(sigma) < 1e-12 ? 1.0 + 0.5 * sigma : portable_expm1(sigma) / sigma;
  const Mat3 h = hat(phi);
  if (theta < 1e-7) {
    // The theta -> 0 limits of C1/theta and C2/theta^2 (|sigma| >= 0.1 here): int u e^{us} and
    // int u^2/2 e^{us}; the terms dropped are of order theta^2 * theta.
    const double s2 = sigma * sigma;
    const double a = ((sigma - 1.0) * es + 1.0) / s2;
    const double b = (es * (0.5 * s2 - sigma + 1.0) - 1.0) / (s2 * sigma);
    return c0 * Mat3::Identity() + a * h + b * h * h;
  }
  const double sin_t = std::sin(theta), cos_t = std::cos(theta);
  const double den = sigma * sigma + theta * theta;
  const double c1 = (es * (sigma * sin_t - theta * cos_t) + theta) / den;
  const double c_cos = (es * (sigma * cos_t + theta * sin_t) - sigma) / den;
  const double c2 = c0 - c_cos;
  return c0 * Mat3::Identity() + (c1 / theta) * h + (c2 / (theta * theta)) * h * h;
}

Sim3 Sim3::exp(const Vec7& zeta) {
  const Vec3 rho = zeta.head<3>();
  const Vec3 phi = zeta.segment<3>(3);
  const double sigma = zeta[6];
  return Sim3(SO3::exp(phi), translation_jacobian(phi, sigma) * rho, portable_exp(sigma));
}

Vec7 Sim3::log() const {
  const Vec3 phi = r_.log();
  const double sigma = portable_log(s_);
  Vec7 zeta;
  // W is invertible for every |phi| <= pi (its eigenvalues vanish only at sigma = 0, theta = 2 pi).
  zeta.head<3>() = translation_jacobian(phi, sigma).partialPivLu().solve(t_);
  zeta.segment<3>(3) = phi;
  zeta[6] = sigma;
  return zeta;
}

Mat4 Sim3::matrix() const {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = s_ * r_.matrix();
  m.topRightCorner<3, 1>() = t_;
  return m;
}

Sim3 Sim3::inverse() const {
  const SO3 r_inv = r_.inverse();
  const double s_inv = 1.0 / s_;
  return Sim3(r_inv, -s_inv * (r_inv * t_), s_inv);
}

Sim3 Sim3::operator*(const Sim3& other) const {
  return Sim3(r_ * other.r_, s_ * (r_ * other.t_) + t_, s_ * other.s_);
}

Vec3 Sim3::operator*(const Vec3& p) const { return s_ * (r_ * p) + t_; }

Mat7 Sim3::adjoint() const {
  // S zeta^ S^-1 for zeta^ = [[sigma I + hat(phi), rho], [0, 0]] gives
  // rho' = s R rho + hat(t) R phi - sigma t, phi' = R phi, sigma' = sigma.
  const Mat3 r = r_.matrix();
  Mat7 ad = Mat7::Zero();
  ad.block<3, 3>(0, 0) = s_ * r;
  ad.block<3, 3>(0, 3) = hat(t_) * r;
  ad.block<3, 1>(0, 6) = -t_;
  ad.block<3, 3>(3, 3) = r;
  ad(6, 6) = 1.0;
  return ad;
}

}  // namespace ale::geometry
