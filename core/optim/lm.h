// A small Levenberg-Marquardt controller shared by the bundle adjuster, the motion-only
// optimiser and the pose graph. It owns no problem data: the caller linearises, solves the
// damped normal equations (H + lambda * D) dx = -g with D = clamp_diagonal(diag(H)) (Marquardt's
// scaling, what Ceres does), evaluates the candidate's cost and reports it here; the controller
// decides acceptance, the next damping and when to stop.
//
// Damping follows Nielsen (the rule Ceres' LEVENBERG_MARQUARDT uses): with gain ratio
// q = actual / predicted reduction, an accepted step (q > min_gain) scales lambda by
// max(1/3, 1 - (2q - 1)^3) and resets nu = 2; a rejected one scales lambda by nu and doubles nu.
// Stops (same tests as Ceres, so final costs are comparable): relative cost change below
// function_tolerance, step below parameter_tolerance * (|x| + parameter_tolerance), max gradient
// component below gradient_tolerance, lambda above max_lambda (no decrease possible), or
// max_iterations trial steps (rejected ones count, as in Ceres).
#pragma once

namespace ale::optim {

struct LmOptions {
  int max_iterations = 50;
  double initial_lambda = 1e-4;  // Ceres' default trust radius 1e4
  double min_lambda = 1e-16;     // lambda never goes below (Ceres' max radius 1e16)
  double max_lambda = 1e32;      // above: stop, no step decreases the cost
  double function_tolerance = 1e-6;
  double parameter_tolerance = 1e-8;
  double gradient_tolerance = 1e-10;
  double min_gain = 1e-3;  // accept a step when actual/predicted reduction exceeds this
  double min_diagonal = 1e-6, max_diagonal = 1e32;  // clamp of D's entries
};

enum class LmStop {
  kRunning,
  kFunctionTolerance,
  kParameterTolerance,
  kGradientTolerance,
  kDampingLimit,     // lambda > max_lambda: converged as far as the model allows
  kMaxIterations,    // not converged
  kNumericalFailure  // non-finite cost or gradient at the start
};

const char* to_string(LmStop stop);
// True for the stops that mean "at a minimum" (the tolerance and damping-limit stops).
bool converged(LmStop stop);

class LmController {
 public:
  // Starts a run at a linearisation point of cost `cost` and max-norm gradient `gradient_max`.
  void start(const LmOptions& options, double cost, double gradient_max);

  double lambda() const { return lambda_; }
  // D's entry for a Hessian diagonal entry h (Marquardt scaling, clamped).
  double damping_diagonal(double h) const;

  // Reports a solved trial step: the candidate's cost, the reduction the linear model predicted
  // (0.5 dx^T (lambda D dx - g) > 0), |dx| and |x|. Returns true when the step is accepted: the
  // caller keeps the candidate and relinearises (then calls set_gradient); false: the caller
  // restores the previous state and solves again with the new lambda().
  bool report_step(double new_cost, double predicted_reduction, double step_norm, double x_norm);
  // The damped system could not be solved (not positive definite) or the candidate's cost is not
  // finite: counts as a rejected step.
  void report_failed_step();
  // Gradient at the new linearisation point after an accepted step.
  void set_gradient(double gradient_max);

  bool done() const { return stop_ != LmStop::kRunning; }
  LmStop stop() const { return stop_; }
  int iterations() const { return iterations_; }
  int accepted_steps() const { return accepted_; }
  double cost() const { return cost_; }
  double initial_cost() const { return initial_cost_; }

 private:
  void reject();
  void count_iteration();

  LmOptions o_;
  double lambda_ = 1e-4;
  double nu_ = 2.0;
  double cost_ = 0.0, initial_cost_ = 0.0;
  int iterations_ = 0, accepted_ = 0;
  LmStop stop_ = LmStop::kRunning;
};

}  // namespace ale::optim
