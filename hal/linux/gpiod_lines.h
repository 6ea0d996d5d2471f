// The robot's output lines (status LED, IR illuminator) through libgpiod 1.6 (the character
// device API; Debian bookworm ships 1.6.3).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/base/status.h"
#include "hal/gpio.h"

struct gpiod_chip;
struct gpiod_line;

namespace ale::linux_hal {

// Where one line is: `chip` is a path (/dev/gpiochip0), a name (gpiochip0), a number (0) or a
// label (1c20800.pinctrl); gpiodetect lists them and gpioinfo lists each chip's offsets.
struct GpioLineMapping {
  std::string chip;
  unsigned offset = 0;
  bool active_low = false;  // set(line, true) drives the pin low
};

// Lines left unset are not on this board: set() on them gives kUnsupported.
struct GpiodLinesOptions {
  std::optional<GpioLineMapping> status_led;
  std::optional<GpioLineMapping> ir_illuminator;
  std::string consumer = "ale-slamd";  // shown by gpioinfo while the lines are held
};

class GpiodLines final : public hal::Gpio {
 public:
  // Requests every mapped line as an output, initially off, so a wrong mapping fails at start-up.
  // kNotFound when a chip does not exist, kInvalidArgument when it is not a GPIO chip, the offset
  // is out of range or two lines share a pin, kUnavailable when another process holds the line.
  static Result<std::unique_ptr<GpiodLines>> open(const GpiodLinesOptions& options);
  // Turns the lines off and gives them back.
  ~GpiodLines() override;
  GpiodLines(const GpiodLines&) = delete;
  GpiodLines& operator=(const GpiodLines&) = delete;

  Status set(hal::GpioLine line, bool on) override;
  std::string describe() const override;

 private:
  struct Held {
    hal::GpioLine line;
    GpioLineMapping mapping;
    gpiod_chip* chip = nullptr;
    gpiod_line* handle = nullptr;
  };
  GpiodLines() = default;
  Status request(hal::GpioLine line, const GpioLineMapping& mapping, const std::string& consumer);

  std::vector<Held> held_;
};

}  // namespace ale::linux_hal
