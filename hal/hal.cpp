#include "hal/gpio.h"

namespace ale::hal {

const char* to_string(GpioLine line) {
  switch (line) {
    case GpioLine::kStatusLed: return "status_led";
    case GpioLine::kIrIlluminator: return "ir_illuminator";
  }
  return "unknown";
}

}  // namespace ale::hal
