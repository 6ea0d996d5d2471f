#include "hal/linux/monotonic_clock.h"

#include <time.h>

namespace ale::linux_hal {

std::int64_t MonotonicClock::now_ns() const {
  timespec t{};
  // Cannot fail for CLOCK_MONOTONIC with a valid pointer.
  clock_gettime(CLOCK_MONOTONIC, &t);
  return static_cast<std::int64_t>(t.tv_sec) * 1000000000 + static_cast<std::int64_t>(t.tv_nsec);
}

}  // namespace ale::linux_hal
