// GPIO HAL: the few output lines the firmware drives.
#pragma once

#include <string>

#include "core/base/status.h"

namespace ale::hal {

enum class GpioLine { kStatusLed, kIrIlluminator };
const char* to_string(GpioLine line);

class Gpio {
 public:
  virtual ~Gpio() = default;
  // kUnsupported when the board has no such line.
  virtual Status set(GpioLine line, bool on) = 0;
  virtual std::string describe() const = 0;
};

// Boards without the lines: every set() succeeds and does nothing.
class NullGpio final : public Gpio {
 public:
  Status set(GpioLine, bool) override { return {}; }
  std::string describe() const override { return "null gpio"; }
};

// Remembers what was set, for tests.
class FakeGpio final : public Gpio {
 public:
  Status set(GpioLine line, bool on) override {
    (line == GpioLine::kStatusLed ? led_ : ir_) = on;
    ++writes_;
    return {};
  }
  std::string describe() const override { return "fake gpio"; }
  bool state(GpioLine line) const { return line == GpioLine::kStatusLed ? led_ : ir_; }
  int writes() const { return writes_; }

 private:
  bool led_ = false;
  bool ir_ = false;
  int writes_ = 0;
};

}  // namespace ale::hal
