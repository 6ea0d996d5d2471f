// The status LED and the IR illuminator: what the daemon shows and switches on its GPIO lines.
// Pure state machines fed with times, so they are tested without hardware or a clock.
#pragma once

#include <cstdint>

#include "app/config.h"
#include "core/base/frame_state.h"
#include "hal/gpio.h"

namespace ale::app {

// What the LED says. Solid while tracking; one slow blink (1 Hz) while initialising; fast
// blinking (4 Hz) when lost; two short flashes every second on an error (camera lost).
enum class LedPattern { kOff, kTracking, kInitializing, kLost, kError };
const char* to_string(LedPattern p);
LedPattern led_pattern_for(TrackingState state);
// Whether the LED is lit at time t_ns under pattern p (patterns repeat each second).
bool led_lit(LedPattern p, std::int64_t t_ns);

// IR illuminator hysteresis: on after `on_after` consecutive extremely dark frames, off after
// `off_after` consecutive normal or bright ones; a dark frame keeps the state and breaks both
// runs. Never toggles twice within `min_toggle_ns`: a run that completes sooner waits, and the
// switch happens at the first frame past the period whose run still holds.
class IrIlluminatorControl {
 public:
  explicit IrIlluminatorControl(const GpioConfig& config) { configure(config); }
  // New thresholds (a configuration reload); the state and the runs so far are kept.
  void configure(const GpioConfig& config);
  // Returns whether the illuminator should be on after a frame of class c at time t_ns.
  bool update(BrightnessClass c, std::int64_t t_ns);
  bool on() const { return on_; }
  int toggles() const { return toggles_; }

 private:
  int on_after_ = 1;
  int off_after_ = 1;
  std::int64_t min_toggle_ns_ = 0;
  bool on_ = false;
  bool toggled_ = false;
  std::int64_t last_toggle_ns_ = 0;
  int dark_run_ = 0;
  int normal_run_ = 0;
  int toggles_ = 0;
};

// Drives both lines; writes a line only when its level changes. Lines the board lacks
// (kUnsupported) are ignored; any other failure is returned once per write.
class Indicators {
 public:
  Indicators(ale::hal::Gpio& gpio, const GpioConfig& config) : gpio_(gpio), ir_(config) {}
  void configure(const GpioConfig& config) { ir_.configure(config); }
  // After each processed frame: the LED from the tracking state, the IR from the brightness.
  Status on_frame(TrackingState state, BrightnessClass brightness, std::int64_t t_ns);
  // While the camera is away.
  Status on_error(std::int64_t t_ns);
  // Both lines off (the loop ends).
  Status off();
  LedPattern pattern() const { return pattern_; }
  const IrIlluminatorControl& ir() const { return ir_; }

 private:
  Status set(ale::hal::GpioLine line, bool on, int& level);
  Status show(LedPattern p, std::int64_t t_ns);

  ale::hal::Gpio& gpio_;
  IrIlluminatorControl ir_;
  LedPattern pattern_ = LedPattern::kOff;
  int led_level_ = -1;  // -1: never written
  int ir_level_ = -1;
};

}  // namespace ale::app
