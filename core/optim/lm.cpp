#include "core/optim/lm.h"

#include <algorithm>
#include <cmath>

namespace ale::optim {

const char* to_string(LmStop stop) {
  switch (stop) {
    case LmStop::kRunning: return "running";
    case LmStop::kFunctionTolerance: return "function tolerance";
    case LmStop::kParameterTolerance: return "parameter tolerance";
    case LmStop::kGradientTolerance: return "gradient tolerance";
    case LmStop::kDampingLimit: return "damping limit";
    case LmStop::kMaxIterations: return "max iterations";
    case LmStop::kNumericalFailure: return "numerical failure";
  }
  return "?";
}

bool converged(LmStop stop) {
  return stop == LmStop::kFunctionTolerance || stop == LmStop::kParameterTolerance ||
         stop == LmStop::kGradientTolerance || stop == LmStop::kDampingLimit;
}

void LmController::start(const LmOptions& options, double cost, double gradient_max) {
  o_ = options;
  lambda_ = std::clamp(o_.initial_lambda, o_.min_lambda, o_.max_lambda);
  nu_ = 2.0;
  cost_ = initial_cost_ = cost;
  iterations_ = accepted_ = 0;
  stop_ = LmStop::kRunning;
  if (!std::isfinite(cost) || !std::isfinite(gradient_max)) {
    stop_ = LmStop::kNumericalFailure;
    return;
  }
  if (gradient_max <= o_.gradient_tolerance) {
    stop_ = LmStop::kGradientTolerance;
    return;
  }
  if (o_.max_iterations <= 0) stop_ = LmStop::kMaxIterations;
}

double LmController::damping_diagonal(double h) const {
  return std::clamp(h, o_.min_diagonal, o_.max_diagonal);
}

void LmController::count_iteration() {
  ++iterations_;
  if (stop_ == LmStop::kRunning && iterations_ >= o_.max_iterations) stop_ = LmStop::kMaxIterations;
}

void LmController::reject() {
  lambda_ *= nu_;
  nu_ *= 2.0;
  if (lambda_ > o_.max_lambda) stop_ = LmStop::kDampingLimit;
}

bool LmController::report_step(double new_cost, double predicted_reduction, double step_norm,
                               double x_norm) {
  if (done()) return false;
  if (!std::isfinite(new_cost) || !std::isfinite(predicted_reduction)) {
    report_failed_step();
    return false;
  }
  // Ceres tests the step size and the cost change of every candidate, accepted or not: a
  // step too small to matter means the minimum is reached either way.
  if (step_norm <= o_.parameter_tolerance * (x_norm + o_.parameter_tolerance)) {
    stop_ = LmStop::kParameterTolerance;
  }
  const double change = cost_ - new_cost;
  const bool accepted = predicted_reduction > 0.0 && change / predicted_reduction > o_.min_gain;
  if (stop_ == LmStop::kRunning && std::abs(change) <= o_.function_tolerance * cost_) {
    stop_ = LmStop::kFunctionTolerance;
  }
  if (accepted) {
    const double q = change / predicted_reduction;
    const double t = 2.0 * q - 1.0;
    lambda_ = std::max(o_.min_lambda, lambda_ * std::max(1.0 / 3.0, 1.0 - t * t * t));
    nu_ = 2.0;
    cost_ = new_cost;
    ++accepted_;
  } else {
    reject();
  }
  count_iteration();
  return accepted;
}

void LmController::report_failed_step() {
  if (done()) return;
  reject();
  count_iteration();
}

void LmController::set_gradient(double gradient_max) {
  if (stop_ != LmStop::kRunning) return;
  if (!std::isfinite(gradient_max)) {
    stop_ = LmStop::kNumericalFailure;
  } else if (gradient_max <= o_.gradient_tolerance) {
    stop_ = LmStop::kGradientTolerance;
  }
}

}  // namespace ale::optim
