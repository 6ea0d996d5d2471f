#include "app/daemon/frame_selector.h"

#include <cmath>

namespace ale::app {

void FrameSelector::configure(double process_fps) {
  period_ns_ = process_fps > 0 ? static_cast<std::int64_t>(std::llround(1e9 / process_fps)) : 0;
  started_ = false;
}

bool FrameSelector::take(std::int64_t t_ns) {
  if (period_ns_ == 0) return true;
  if (!started_ || t_ns - next_due_ns_ > period_ns_) {
    started_ = true;
    next_due_ns_ = t_ns + period_ns_;
    return true;
  }
  if (t_ns < next_due_ns_ - period_ns_ / 4) return false;
  next_due_ns_ += period_ns_;
  return true;
}

}  // namespace ale::app
