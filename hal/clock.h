// Clock HAL. On the robot a monotonic clock; in a replay the recorded timestamps drive time, so a
// replay runs as fast as the CPU allows and gives the same result every time.
#pragma once

#include <cstdint>

namespace ale::hal {

class Clock {
 public:
  virtual ~Clock() = default;
  virtual std::int64_t now_ns() const = 0;
};

// A clock that only moves when told to: the replay clock and the clock of tests.
class ManualClock final : public Clock {
 public:
  explicit ManualClock(std::int64_t start_ns = 0) : now_ns_(start_ns) {}
  std::int64_t now_ns() const override { return now_ns_; }
  // Time never goes backwards: an earlier value is ignored and false returned.
  bool set_ns(std::int64_t t_ns) {
    if (t_ns < now_ns_) return false;
    now_ns_ = t_ns;
    return true;
  }
  void advance_ns(std::int64_t dt_ns) { if (dt_ns > 0) now_ns_ += dt_ns; }

 private:
  std::int64_t now_ns_;
};

}  // namespace ale::hal
