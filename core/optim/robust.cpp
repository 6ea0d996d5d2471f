#include "core/optim/robust.h"

#include <cmath>

namespace ale::optim {

void RobustKernel::evaluate(double s, double* rho_s, double* weight) const {
  const double d2 = delta * delta;
  switch (kind) {
    case RobustKind::kNone:
      *rho_s = s;
      *weight = 1.0;
      return;
    case RobustKind::kHuber:
      if (s <= d2) {
        *rho_s = s;
        *weight = 1.0;
      } else {
        const double r = std::sqrt(s);
        *rho_s = 2.0 * delta * r - d2;
        *weight = delta / r;
      }
      return;
    case RobustKind::kCauchy: {
      const double q = 1.0 + s / d2;
      *rho_s = d2 * std::log(q);
      *weight = 1.0 / q;
      return;
    }
    case RobustKind::kTukey:
      if (s <= d2) {
        const double q = 1.0 - s / d2;
        *rho_s = d2 / 3.0 * (1.0 - q * q * q);
        *weight = q * q;
      } else {
        *rho_s = d2 / 3.0;
        *weight = 0.0;
      }
      return;
  }
  *rho_s = s;
  *weight = 1.0;
}

double RobustKernel::rho(double s) const {
  double r = 0.0, w = 0.0;
  evaluate(s, &r, &w);
  return r;
}

double RobustKernel::d_rho(double s) const {
  double r = 0.0, w = 0.0;
  evaluate(s, &r, &w);
  return w;
}

}  // namespace ale::optim
