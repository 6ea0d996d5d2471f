// SO(3), SE(3), Sim(3): exp/log round trips from 1e-12 rad to exactly pi, exp against the
// matrix exponential of the generator, composition, inverse and adjoint identities, and every
// Jacobian (left, right, inverse, Sim(3)'s W, transformed-point) against central differences.
#include "core/geometry/lie.h"
#include "core/geometry/portable_math.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <unsupported/Eigen/MatrixFunctions>
#include <vector>

#include "core/base/rng.h"

namespace ale::geometry {
namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3 random_unit(SplitMix64& rng) {
  for (;;) {
    // one declaration per draw: the order of constructor arguments is unspecified (and
    // differs between GCC's x86 and ARM targets), the order of declarations is not
    const double vx = 2.0 * rng.uniform_double() - 1.0;
    const double vy = 2.0 * rng.uniform_double() - 1.0;
    const double vz = 2.0 * rng.uniform_double() - 1.0;
    const Vec3 v(vx, vy, vz);
    const double n = v.norm();
    if (n > 0.1 && n <= 1.0) return v / n;
  }
}

Vec3 random_vec(SplitMix64& rng, double scale) {
  const double vx = 2.0 * rng.uniform_double() - 1.0;
  const double vy = 2.0 * rng.uniform_double() - 1.0;
  const double vz = 2.0 * rng.uniform_double() - 1.0;
  return scale * Vec3(vx, vy, vz);
}

// Rotation vectors covering every regime of exp/log: random, tiny, small, around the series
// threshold, near pi and exactly pi.
std::vector<Vec3> test_rotations() {
  SplitMix64 rng(7);
  std::vector<Vec3> out;
  for (int i = 0; i < 50; ++i) out.push_back(random_unit(rng) * (kPi * rng.uniform_double()));
  for (double angle : {0.0, 1e-12, 1e-9, 1e-6, 9.99e-5, 1e-4, 1.01e-4, 1e-3, 0.5, 2.0, kPi - 1e-3, kPi - 1e-6,
                       kPi - 1e-9, kPi - 1e-12, kPi}) {
    for (int i = 0; i < 4; ++i) out.push_back(random_unit(rng) * angle);
    out.push_back(Vec3(angle, 0.0, 0.0));
  }
  return out;
}

// Reference rotation: Rodrigues' formula in long double.
Mat3 rodrigues(const Vec3& phi) {
  const long double theta = std::sqrt(static_cast<long double>(phi.squaredNorm()));
  if (theta == 0.0L) return Mat3::Identity();
  const Vec3 axis = phi / static_cast<double>(theta);
  const Mat3 k = hat(axis);
  return Mat3::Identity() + static_cast<double>(std::sin(theta)) * k +
         static_cast<double>(1.0L - std::cos(theta)) * k * k;
}

double rotation_distance(const Mat3& a, const Mat3& b) { return (a - b).cwiseAbs().maxCoeff(); }

TEST(Lie, HatVee) {
  const Vec3 w(0.3, -1.2, 2.5), v(-0.7, 0.4, 1.1);
  EXPECT_LT((hat(w) * v - w.cross(v)).norm(), 1e-15);
  EXPECT_EQ(vee(hat(w)), w);
  EXPECT_LT((hat(w) + hat(w).transpose()).norm(), 1e-300);
}

TEST(So3, ExpMatchesRodrigues) {
  for (const Vec3& phi : test_rotations()) {
    const Mat3 r = SO3::exp(phi).matrix();
    EXPECT_LT(rotation_distance(r, rodrigues(phi)), 1e-15 * 4) << phi.transpose();
    EXPECT_LT((r * r.transpose() - Mat3::Identity()).norm(), 1e-15 * 4);
    EXPECT_NEAR(r.determinant(), 1.0, 1e-15 * 4);
  }
}

TEST(So3, LogRoundTrip) {
  for (const Vec3& phi : test_rotations()) {
    const Vec3 back = SO3::exp(phi).log();
    const double theta = phi.norm();
    EXPECT_LE(back.norm(), kPi + 1e-15);
    if (theta < kPi - 1e-6) {
      // relative accuracy also for tiny angles (a series that dropped its first term fails here)
      EXPECT_LT((back - phi).norm(), 1e-15 * 4 + 1e-15 * theta) << phi.transpose();
      if (theta > 0.0) {
        EXPECT_LT((back - phi).norm() / theta, 1e-14) << phi.transpose();
      }
    } else {
      // near pi, phi and -phi are (almost) the same rotation: the group element must round-trip
      EXPECT_LT(rotation_distance(SO3::exp(back).matrix(), SO3::exp(phi).matrix()), 1e-14) << phi.transpose();
      EXPECT_NEAR(back.norm(), std::min(theta, 2.0 * kPi - theta), 1e-14);
      const double axis_dot = std::abs(back.normalized().dot(phi.normalized()));
      EXPECT_NEAR(axis_dot, 1.0, 1e-12) << phi.transpose();
    }
  }
}

TEST(So3, LogFromMatrixNearPi) {
  // The matrix path (from_matrix) is what solvers use; its axis must survive near pi, where the
  // skew-symmetric part of R vanishes.
  SplitMix64 rng(11);
  for (double angle : {kPi - 1e-3, kPi - 1e-7, kPi - 1e-10, kPi}) {
    for (int i = 0; i < 20; ++i) {
      const Vec3 axis = random_unit(rng);
      const SO3 r = SO3::from_matrix(rodrigues(axis * angle));
      const Vec3 back = r.log();
      EXPECT_NEAR(back.norm(), angle, 1e-13);
      EXPECT_NEAR(std::abs(back.normalized().dot(axis)), 1.0, 1e-13);
      EXPECT_LT(rotation_distance(SO3::exp(back).matrix(), rodrigues(axis * angle)), 1e-14);
    }
  }
}

TEST(So3, FromMatrixOrthonormalises) {
  SplitMix64 rng(3);
  const Mat3 r = rodrigues(Vec3(0.4, -0.2, 1.1));
  Mat3 noisy = r;
  for (int i = 0; i < 9; ++i) noisy(i / 3, i % 3) += 1e-4 * (rng.uniform_double() - 0.5);
  const Mat3 back = SO3::from_matrix(noisy).matrix();
  EXPECT_LT((back * back.transpose() - Mat3::Identity()).norm(), 1e-14);
  EXPECT_LT(rotation_distance(back, r), 1e-4);
  // an exact rotation comes back as itself
  EXPECT_LT(rotation_distance(SO3::from_matrix(r).matrix(), r), 1e-15 * 4);
}

TEST(So3, CompositionInverseAdjoint) {
  SplitMix64 rng(5);
  for (int i = 0; i < 50; ++i) {
    const SO3 a = SO3::exp(random_vec(rng, 2.0)), b = SO3::exp(random_vec(rng, 2.0));
    const Vec3 p = random_vec(rng, 3.0), phi = random_vec(rng, 1.0);
    EXPECT_LT(rotation_distance((a * b).matrix(), a.matrix() * b.matrix()), 1e-15 * 8);
    EXPECT_LT(((a * p) - a.matrix() * p).norm(), 1e-14);
    EXPECT_LT(rotation_distance((a * a.inverse()).matrix(), Mat3::Identity()), 1e-15 * 4);
    EXPECT_LT(rotation_distance(SO3::exp(a.adjoint() * phi).matrix() * a.matrix(), a.matrix() * SO3::exp(phi).matrix()),
              1e-14);
  }
}

// Central differences with step h: f maps R^n to R^m around 0.
template <int M, int N, class F>
Eigen::Matrix<double, M, N> numeric_jacobian(F f, double h = 1e-6) {
  Eigen::Matrix<double, M, N> j;
  for (int i = 0; i < N; ++i) {
    Eigen::Matrix<double, N, 1> d = Eigen::Matrix<double, N, 1>::Zero();
    d[i] = h;
    j.col(i) = (f(d) - f(-d)) / (2.0 * h);
  }
  return j;
}

TEST(So3, JacobiansMatchNumeric) {
  for (const Vec3& phi : test_rotations()) {
    if (phi.norm() > kPi - 1e-3) continue;  // log jumps at pi; the Jacobians are checked below it
    const SO3 r = SO3::exp(phi);
    // exp(phi + d) = exp(J_l d) exp(phi) and = exp(phi) exp(J_r d)
    const Mat3 jl = numeric_jacobian<3, 3>([&](const Vec3& d) { return (SO3::exp(phi + d) * r.inverse()).log(); });
    const Mat3 jr = numeric_jacobian<3, 3>([&](const Vec3& d) { return (r.inverse() * SO3::exp(phi + d)).log(); });
    EXPECT_LT((SO3::left_jacobian(phi) - jl).norm(), 1e-8) << phi.transpose();
    EXPECT_LT((SO3::right_jacobian(phi) - jr).norm(), 1e-8) << phi.transpose();
    // log(exp(d) R) = phi + J_l^-1 d and log(R exp(d)) = phi + J_r^-1 d
    const Mat3 jli = numeric_jacobian<3, 3>([&](const Vec3& d) { return (SO3::exp(d) * r).log(); });
    const Mat3 jri = numeric_jacobian<3, 3>([&](const Vec3& d) { return (r * SO3::exp(d)).log(); });
    EXPECT_LT((SO3::left_jacobian_inverse(phi) - jli).norm(), 1e-7) << phi.transpose();
    EXPECT_LT((SO3::right_jacobian_inverse(phi) - jri).norm(), 1e-7) << phi.transpose();
    EXPECT_LT((SO3::left_jacobian(phi) * SO3::left_jacobian_inverse(phi) - Mat3::Identity()).norm(), 1e-13);
  }
  // At exactly pi the inverse stays finite and is still the inverse.
  const Vec3 phi_pi(0.0, kPi, 0.0);
  EXPECT_LT((SO3::left_jacobian(phi_pi) * SO3::left_jacobian_inverse(phi_pi) - Mat3::Identity()).norm(), 1e-13);
}

// The generator of se(3) / sim(3) as a 4x4 matrix, for Eigen's matrix exponential.
Mat4 generator(const Vec3& rho, const Vec3& phi, double sigma) {
  Mat4 g = Mat4::Zero();
  g.topLeftCorner<3, 3>() = hat(phi) + sigma * Mat3::Identity();
  g.topRightCorner<3, 1>() = rho;
  return g;
}

TEST(Se3, ExpMatchesMatrixExponentialAndRoundTrips) {
  SplitMix64 rng(13);
  for (const Vec3& phi : test_rotations()) {
    Vec6 xi;
    xi << random_vec(rng, 2.0), phi;
    const SE3 t = SE3::exp(xi);
    const Mat4 ref = generator(xi.head<3>(), phi, 0.0).exp();
    EXPECT_LT((t.matrix() - ref).cwiseAbs().maxCoeff(), 1e-13) << xi.transpose();
    const Vec6 back = t.log();
    if (phi.norm() < kPi - 1e-6) {
      EXPECT_LT((back - xi).norm(), 1e-12) << xi.transpose();
    } else {
      EXPECT_LT((SE3::exp(back).matrix() - t.matrix()).cwiseAbs().maxCoeff(), 1e-12) << xi.transpose();
    }
  }
}

TEST(Se3, CompositionInverseAdjointPointJacobian) {
  SplitMix64 rng(17);
  for (int i = 0; i < 50; ++i) {
    Vec6 xa, xb, xi;
    xa << random_vec(rng, 3.0), random_vec(rng, 1.5);
    xb << random_vec(rng, 3.0), random_vec(rng, 1.5);
    xi << random_vec(rng, 0.5), random_vec(rng, 0.5);
    const SE3 a = SE3::exp(xa), b = SE3::exp(xb);
    const Vec3 p = random_vec(rng, 4.0);
    EXPECT_LT(((a * b).matrix() - a.matrix() * b.matrix()).cwiseAbs().maxCoeff(), 1e-13);
    EXPECT_LT(((a * a.inverse()).matrix() - Mat4::Identity()).cwiseAbs().maxCoeff(), 1e-14);
    EXPECT_LT((a * p - (a.matrix() * p.homogeneous()).head<3>()).norm(), 1e-13);
    // exp(Ad xi) T = T exp(xi)
    EXPECT_LT(((SE3::exp(a.adjoint() * xi) * a).matrix() - (a * SE3::exp(xi)).matrix()).cwiseAbs().maxCoeff(), 1e-12);
    // the header's convention: d (exp(d) T p) / d d = [I, -hat(T p)]
    Eigen::Matrix<double, 3, 6> expected;
    expected << Mat3::Identity(), -hat(a * p);
    const auto num = numeric_jacobian<3, 6>([&](const Vec6& d) { return SE3::exp(d) * (a * p); });
    EXPECT_LT((num - expected).norm(), 1e-8);
  }
}

// W(phi, sigma) by composite Simpson's rule on its defining integral.
Mat3 w_by_quadrature(const Vec3& phi, double sigma) {
  constexpr int kN = 2000;  // even
  Mat3 sum = Mat3::Zero();
  for (int i = 0; i <= kN; ++i) {
    const double u = static_cast<double>(i) / kN;
    const double weight = (i == 0 || i == kN) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    sum += weight * std::exp(u * sigma) * rodrigues(u * phi);
  }
  return sum / (3.0 * kN);
}

TEST(Sim3, TranslationJacobianMatchesQuadratureInEveryRegime) {
  SplitMix64 rng(19);
  // (|sigma|, theta) on both sides of the series threshold |sigma| + theta = 0.1 and of the
  // theta -> 0 branch.
  const double sigmas[] = {0.0, 1e-12, -1e-7, 0.03, -0.0999, 0.1001, -0.5, 1.5, -2.0};
  const double thetas[] = {0.0, 1e-12, 1e-8, 1e-6, 0.04, 0.0999, 0.2, 1.0, kPi - 1e-6, kPi};
  for (double sigma : sigmas) {
    for (double theta : thetas) {
      const Vec3 phi = random_unit(rng) * theta;
      const Mat3 w = Sim3::translation_jacobian(phi, sigma);
      const Mat3 ref = w_by_quadrature(phi, sigma);
      EXPECT_LT((w - ref).cwiseAbs().maxCoeff(), 1e-12) << "sigma " << sigma << " theta " << theta;
    }
  }
  // sigma = 0 is SO(3)'s left Jacobian
  const Vec3 phi(0.3, -0.9, 0.4);
  EXPECT_LT((Sim3::translation_jacobian(phi, 0.0) - SO3::left_jacobian(phi)).norm(), 1e-14);
}

TEST(Sim3, ExpMatchesMatrixExponentialAndRoundTrips) {
  SplitMix64 rng(23);
  const double sigmas[] = {0.0, 1e-12, 1e-6, -0.05, 0.3, -1.2};
  int k = 0;
  for (const Vec3& phi : test_rotations()) {
    const double sigma = sigmas[k++ % 6];
    Vec7 zeta;
    zeta << random_vec(rng, 2.0), phi, sigma;
    const Sim3 s = Sim3::exp(zeta);
    EXPECT_NEAR(s.scale(), std::exp(sigma), 1e-15 * 4);
    const Mat4 ref = generator(zeta.head<3>(), phi, sigma).exp();
    EXPECT_LT((s.matrix() - ref).cwiseAbs().maxCoeff(), 1e-12) << zeta.transpose();
    const Vec7 back = s.log();
    if (phi.norm() < kPi - 1e-6) {
      EXPECT_LT((back - zeta).norm(), 1e-12) << zeta.transpose();
    } else {
      EXPECT_LT((Sim3::exp(back).matrix() - s.matrix()).cwiseAbs().maxCoeff(), 1e-12) << zeta.transpose();
    }
  }
}

TEST(Sim3, CompositionInverseAdjointPointJacobian) {
  SplitMix64 rng(29);
  for (int i = 0; i < 50; ++i) {
    Vec7 za, zb, z;
    za << random_vec(rng, 3.0), random_vec(rng, 1.5), rng.uniform_double() - 0.5;
    zb << random_vec(rng, 3.0), random_vec(rng, 1.5), rng.uniform_double() - 0.5;
    z << random_vec(rng, 0.5), random_vec(rng, 0.5), 0.4 * (rng.uniform_double() - 0.5);
    const Sim3 a = Sim3::exp(za), b = Sim3::exp(zb);
    const Vec3 p = random_vec(rng, 4.0);
    EXPECT_LT(((a * b).matrix() - a.matrix() * b.matrix()).cwiseAbs().maxCoeff(), 1e-13);
    EXPECT_LT(((a * a.inverse()).matrix() - Mat4::Identity()).cwiseAbs().maxCoeff(), 1e-13);
    EXPECT_LT((a * p - (a.matrix() * p.homogeneous()).head<3>()).norm(), 1e-13);
    EXPECT_LT(((Sim3::exp(a.adjoint() * z) * a).matrix() - (a * Sim3::exp(z)).matrix()).cwiseAbs().maxCoeff(), 1e-12);
    // d (exp(d) S p) / d d = [I, -hat(S p), S p]
    Eigen::Matrix<double, 3, 7> expected;
    const Vec3 q = a * p;
    expected << Mat3::Identity(), -hat(q), q;
    const auto num = numeric_jacobian<3, 7>([&](const Vec7& d) { return Sim3::exp(d) * q; });
    EXPECT_LT((num - expected).norm(), 1e-8);
  }
  // SE3 embeds with scale 1
  Vec6 xi;
  xi << 0.1, 0.2, -0.3, 0.4, -0.2, 0.1;
  const SE3 t = SE3::exp(xi);
  EXPECT_LT((Sim3(t).matrix() - t.matrix()).norm(), 1e-15);
}

TEST(Se3, LeftJacobianMatchesNumeric) {
  SplitMix64 rng(31);
  for (const Vec3& phi : test_rotations()) {
    if (phi.norm() > kPi - 1e-3) continue;  // log jumps at pi
    Vec6 xi;
    xi << random_vec(rng, 3.0), phi;
    const SE3 t = SE3::exp(xi);
    const Mat6 jl = SE3::left_jacobian(xi);
    const Mat6 num_l = numeric_jacobian<6, 6>([&](const Vec6& d) { return (SE3::exp(xi + d) * t.inverse()).log(); });
    const Mat6 num_r = numeric_jacobian<6, 6>([&](const Vec6& d) { return (t.inverse() * SE3::exp(xi + d)).log(); });
    EXPECT_LT((jl - num_l).norm(), 1e-7 * (1.0 + jl.norm())) << xi.transpose();
    EXPECT_LT((SE3::left_jacobian(-xi) - num_r).norm(), 1e-7 * (1.0 + jl.norm())) << xi.transpose();
    // its diagonal blocks are SO(3)'s
    EXPECT_LT((jl.topLeftCorner<3, 3>() - SO3::left_jacobian(phi)).norm(), 1e-14);
    EXPECT_LT((jl.bottomRightCorner<3, 3>() - SO3::left_jacobian(phi)).norm(), 1e-14);
    EXPECT_LT((SE3::left_jacobian_inverse(xi) * jl - Mat6::Identity()).norm(), 1e-12);
    // ad is the bracket: ad(a) b = log-level commutator, checked via Ad(exp(a)) = exp(ad(a))
    EXPECT_LT((SE3::ad(xi).exp() - t.adjoint()).cwiseAbs().maxCoeff(), 1e-11);
  }
}

TEST(Sim3, LeftJacobianMatchesNumeric) {
  SplitMix64 rng(37);
  const double sigmas[] = {0.0, 1e-9, -0.05, 0.4, -1.1, 2.0};
  int k = 0;
  for (const Vec3& phi : test_rotations()) {
    if (phi.norm() > kPi - 1e-3) continue;
    Vec7 zeta;
    zeta << random_vec(rng, 3.0), phi, sigmas[k++ % 6];
    const Sim3 s = Sim3::exp(zeta);
    const Mat7 jl = Sim3::left_jacobian(zeta);
    const Mat7 num_l = numeric_jacobian<7, 7>([&](const Vec7& d) { return (Sim3::exp(zeta + d) * s.inverse()).log(); });
    const Mat7 num_r = numeric_jacobian<7, 7>([&](const Vec7& d) { return (s.inverse() * Sim3::exp(zeta + d)).log(); });
    EXPECT_LT((jl - num_l).norm(), 1e-7 * (1.0 + jl.norm())) << zeta.transpose();
    EXPECT_LT((Sim3::left_jacobian(-zeta) - num_r).norm(), 1e-7 * (1.0 + jl.norm())) << zeta.transpose();
    EXPECT_LT((Sim3::left_jacobian_inverse(zeta) * jl - Mat7::Identity()).norm(), 1e-12);
    EXPECT_LT((Sim3::ad(zeta).exp() - s.adjoint()).cwiseAbs().maxCoeff(), 1e-11);
  }
}


// The portable exp, expm1 and log (core/geometry/portable_math.h) agree with the C library's
// within a few ulps where the Lie groups use them.
TEST(PortableMath, AgreesWithTheLibraryWithinAFewUlps) {
  for (double x = -30.0; x <= 30.0; x += 0.0137) {
    EXPECT_NEAR(portable_exp(x), std::exp(x), 4e-16 * std::exp(x)) << x;
    EXPECT_NEAR(portable_expm1(x), std::expm1(x), 4e-16 * std::max(1.0, std::abs(std::expm1(x)))) << x;
  }
  for (double x = -1e-3; x <= 1e-3; x += 1.37e-5) EXPECT_NEAR(portable_expm1(x), std::expm1(x), 4e-16 * std::abs(x) + 1e-300) << x;
  for (double x = 1e-6; x <= 1e6; x *= 1.0173) EXPECT_NEAR(portable_log(x), std::log(x), 4e-16 * std::max(1.0, std::abs(std::log(x)))) << x;
  EXPECT_EQ(portable_exp(0.0), 1.0);
  EXPECT_EQ(portable_log(1.0), 0.0);
  EXPECT_EQ(portable_log(2.0), std::log(2.0));
  EXPECT_TRUE(std::isnan(portable_log(-1.0)));
  EXPECT_TRUE(std::isinf(portable_exp(1000.0)));
}

}  // namespace
}  // namespace ale::geometry
