// The robot's clock: CLOCK_MONOTONIC, the clock V4L2 stamps frames with, so frame times and
// now_ns() can be compared directly.
#pragma once

#include <cstdint>

#include "hal/clock.h"

namespace ale::linux_hal {

class MonotonicClock final : public hal::Clock {
 public:
  std::int64_t now_ns() const override;
};

}  // namespace ale::linux_hal
