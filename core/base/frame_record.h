// The per-frame timing record of the frame path: one entry per stage, in the order they ran, from
// a monotonic clock the owner may replace (a replay or a test injects its own, so that the record
// is deterministic too). Timing only reads the clock: it changes no result.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

namespace ale {

// Nanoseconds from a monotonic clock.
using MonotonicClock = std::int64_t (*)();
// std::chrono::steady_clock.
std::int64_t steady_clock_ns();

constexpr std::size_t kMaxFrameStages = 16;

struct StageTime {
  const char* name = "";  // a string literal of the stage
  std::int64_t ns = 0;
};

struct FrameTimings {
  std::array<StageTime, kMaxFrameStages> stage{};
  std::size_t count = 0;

  void clear() { count = 0; }
  // Ignored beyond kMaxFrameStages (the path refuses more stages than that).
  void add(const char* name, std::int64_t ns) {
    if (count < stage.size()) stage[count++] = {name, ns};
  }
  std::int64_t total_ns() const {
    std::int64_t sum = 0;
    for (std::size_t i = 0; i < count; ++i) sum += stage[i].ns;
    return sum;
  }
};

}  // namespace ale
