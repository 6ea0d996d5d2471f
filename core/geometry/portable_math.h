// exp, expm1 and log from IEEE-754 +, -, *, / and exact scalings only, so that they give the same
// bits on the host (x86-64) and the robot (armhf): the C library's implementations are accurate
// to within an ulp but not the same bits on both (a Sim(3) pose graph over a monocular map's
// scales then ended a loop-closing replay a last digit apart under qemu-arm). With
// -ffp-contract=off (toolchains/) no multiply-add is fused, so the operations below are the same
// on both. Accuracy: within a few ulps over the ranges the Lie groups use (scales of e^-700 to
// e^700).
#pragma once

#include <cmath>

namespace ale::geometry {

namespace portable_detail {
constexpr double kLn2Hi = 6.93147180369123816490e-01;  // ln 2 to 32 bits: k * kLn2Hi is exact
constexpr double kLn2Lo = 1.90821492927058770002e-10;  // the rest of ln 2
constexpr double kInvLn2 = 1.44269504088896338700e+00;

// e^r - 1 for |r| <= 0.35 (Taylor to r^17, error below 1e-19 relative).
inline double expm1_reduced(double r) {
  double p = 1.0;
  for (int n = 17; n >= 2; --n) p = 1.0 + p * r / static_cast<double>(n);
  return r * p;
}
}  // namespace portable_detail

// e^x; outside [-700, 700] (and for NaN) the C library's (overflow, underflow, NaN).
inline double portable_exp(double x) {
  using namespace portable_detail;
  if (!(x >= -700.0 && x <= 700.0)) return std::exp(x);
  const double k = std::floor(x * kInvLn2 + 0.5);
  const double r = (x - k * kLn2Hi) - k * kLn2Lo;
  return std::ldexp(1.0 + expm1_reduced(r), static_cast<int>(k));
}

// e^x - 1, accurate for small x.
inline double portable_expm1(double x) {
  if (x >= -0.35 && x <= 0.35) return portable_detail::expm1_reduced(x);
  return portable_exp(x) - 1.0;
}

// ln x for x > 0; 0, negative, infinite and NaN arguments get the C library's answer.
inline double portable_log(double x) {
  using namespace portable_detail;
  if (!(x > 0.0) || std::isinf(x)) return std::log(x);
  int e = 0;
  double m = std::frexp(x, &e);  // x = m 2^e, m in [0.5, 1), exact
  if (m < 0.70710678118654752440) {
    m *= 2.0;
    --e;
  }
  // ln m = 2 atanh(f), f = (m - 1) / (m + 1), |f| <= 0.172: the odd series to f^29
  const double f = (m - 1.0) / (m + 1.0);
  const double f2 = f * f;
  double s = 0.0;
  for (int n = 29; n >= 3; n -= 2) s = (s + 1.0 / static_cast<double>(n)) * f2;
  const double ln_m = 2.0 * f * (1.0 + s);
  return static_cast<double>(e) * kLn2Hi + (static_cast<double>(e) * kLn2Lo + ln_m);
}

}  // namespace ale::geometry
