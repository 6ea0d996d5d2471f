// Robust kernels (values, continuity, weight = numeric derivative of rho) and the LM controller
// (Nielsen's damping, stops) on a 1-D least-squares problem.
#include <gtest/gtest.h>

#include <cmath>

#include "core/optim/lm.h"
#include "core/optim/robust.h"

namespace ale::optim {
namespace {

TEST(RobustKernel, WeightIsTheDerivativeOfRho) {
  for (const RobustKernel k : {RobustKernel::none(), RobustKernel::huber(1.5), RobustKernel::cauchy(0.7),
                               RobustKernel::tukey(2.0)}) {
    for (double s : {0.01, 0.3, 1.0, 2.0, 2.24, 3.9, 4.1, 10.0, 100.0}) {
      const double h = 1e-6 * (1.0 + s);
      const double numeric = (k.rho(s + h) - k.rho(s - h)) / (2.0 * h);
      EXPECT_NEAR(k.d_rho(s), numeric, 1e-6) << "kind " << static_cast<int>(k.kind) << " s " << s;
      double rho = 0.0, w = 0.0;
      k.evaluate(s, &rho, &w);
      EXPECT_DOUBLE_EQ(rho, k.rho(s));
      EXPECT_DOUBLE_EQ(w, k.weight(s));
    }
    EXPECT_DOUBLE_EQ(k.rho(0.0), 0.0);
    EXPECT_DOUBLE_EQ(k.d_rho(0.0), 1.0);
  }
}

TEST(RobustKernel, KnownValues) {
  const RobustKernel huber = RobustKernel::huber(2.0);
  EXPECT_DOUBLE_EQ(huber.rho(3.0), 3.0);           // inside: quadratic
  EXPECT_DOUBLE_EQ(huber.rho(9.0), 2 * 2 * 3 - 4);  // outside: 2 d |r| - d^2
  EXPECT_DOUBLE_EQ(huber.weight(9.0), 2.0 / 3.0);
  EXPECT_NEAR(RobustKernel::cauchy(1.0).rho(1.0), std::log(2.0), 1e-15);
  EXPECT_DOUBLE_EQ(RobustKernel::tukey(1.0).weight(1.5), 0.0);  // beyond: ignored
  EXPECT_DOUBLE_EQ(RobustKernel::tukey(1.0).rho(1.5), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(RobustKernel::tukey(1.0).rho(1.0), 1.0 / 3.0);  // continuous at the edge
}

// min over x of 0.5 * sum (exp(a_i x) - b_i)^2, a small nonlinear problem, with a GN/LM loop
// driven by the controller.
struct ExpFit {
  double a[4] = {0.1, 0.4, 0.9, 1.3};
  double b[4] = {1.2, 2.0, 4.5, 8.9};
  double cost(double x) const {
    double c = 0.0;
    for (int i = 0; i < 4; ++i) c += 0.5 * std::pow(std::exp(a[i] * x) - b[i], 2);
    return c;
  }
  void linearise(double x, double* h, double* g) const {
    *h = *g = 0.0;
    for (int i = 0; i < 4; ++i) {
      const double e = std::exp(a[i] * x);
      const double j = a[i] * e;
      *h += j * j;
      *g += j * (e - b[i]);
    }
  }
};

TEST(LmController, ConvergesAndStopsOnTolerance) {
  const ExpFit f;
  double x = 5.0;  // far: the first steps overshoot and get rejected
  LmController lm;
  LmOptions o;
  o.function_tolerance = 1e-12;
  double h = 0.0, g = 0.0;
  f.linearise(x, &h, &g);
  lm.start(o, f.cost(x), std::abs(g));
  int rejected = 0;
  while (!lm.done()) {
    const double d = lm.damping_diagonal(h);
    const double dx = -g / (h + lm.lambda() * d);
    const double predicted = 0.5 * dx * (lm.lambda() * d * dx - g);
    const double c = f.cost(x + dx);
    if (lm.report_step(c, predicted, std::abs(dx), std::abs(x))) {
      x += dx;
      f.linearise(x, &h, &g);
      lm.set_gradient(std::abs(g));
    } else {
      ++rejected;
    }
  }
  EXPECT_TRUE(converged(lm.stop())) << to_string(lm.stop());
  EXPECT_LT(std::abs(g), 1e-4);  // stationary point
  EXPECT_LT(lm.cost(), lm.initial_cost());
  EXPECT_EQ(lm.iterations(), lm.accepted_steps() + rejected);
  EXPECT_DOUBLE_EQ(lm.cost(), f.cost(x));
}

TEST(LmController, NielsenDampingUpdate) {
  LmController lm;
  LmOptions o;
  o.initial_lambda = 1.0;
  o.function_tolerance = 0.0;
  lm.start(o, 10.0, 1.0);
  // gain 1 (the model was exact): lambda / 3
  EXPECT_TRUE(lm.report_step(9.0, 1.0, 1.0, 1.0));
  EXPECT_NEAR(lm.lambda(), 1.0 / 3.0, 1e-15);
  // gain 0.5: factor max(1/3, 1 - 0) = 1
  EXPECT_TRUE(lm.report_step(8.0, 2.0, 1.0, 1.0));
  EXPECT_NEAR(lm.lambda(), 1.0 / 3.0, 1e-15);
  // rejections: x2 then x4
  EXPECT_FALSE(lm.report_step(9.0, 1.0, 1.0, 1.0));
  EXPECT_NEAR(lm.lambda(), 2.0 / 3.0, 1e-15);
  lm.report_failed_step();
  EXPECT_NEAR(lm.lambda(), 8.0 / 3.0, 1e-15);
  EXPECT_EQ(lm.iterations(), 4);
  EXPECT_EQ(lm.accepted_steps(), 2);
  EXPECT_FALSE(lm.done());
}

TEST(LmController, StopsAndFailures) {
  LmController lm;
  LmOptions o;
  lm.start(o, NAN, 1.0);
  EXPECT_EQ(lm.stop(), LmStop::kNumericalFailure);
  EXPECT_FALSE(converged(lm.stop()));
  lm.start(o, 1.0, 0.0);
  EXPECT_EQ(lm.stop(), LmStop::kGradientTolerance);
  o.max_iterations = 2;
  o.function_tolerance = 0.0;
  lm.start(o, 1.0, 1.0);
  lm.report_failed_step();
  EXPECT_FALSE(lm.done());
  lm.report_failed_step();
  EXPECT_EQ(lm.stop(), LmStop::kMaxIterations);
  EXPECT_FALSE(converged(lm.stop()));
  o.max_iterations = 1000;
  lm.start(o, 1.0, 1.0);
  while (!lm.done()) lm.report_failed_step();  // never a good step: the damping limit ends it
  EXPECT_EQ(lm.stop(), LmStop::kDampingLimit);
  lm.start(o, 1.0, 1.0);
  EXPECT_TRUE(lm.report_step(0.5, 0.5, 1e-20, 1.0));  // tiny step: parameter tolerance
  EXPECT_EQ(lm.stop(), LmStop::kParameterTolerance);
  EXPECT_DOUBLE_EQ(lm.cost(), 0.5);
}

}  // namespace
}  // namespace ale::optim
