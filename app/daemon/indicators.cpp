#include "app/daemon/indicators.h"

namespace ale::app {
namespace {

constexpr std::int64_t kMsNs = 1000000;

}  // namespace

const char* to_string(LedPattern p) {
  switch (p) {
    case LedPattern::kOff: return "off";
    case LedPattern::kTracking: return "tracking";
    case LedPattern::kInitializing: return "initializing";
    case LedPattern::kLost: return "lost";
    case LedPattern::kError: return "error";
  }
  return "unknown";
}

LedPattern led_pattern_for(TrackingState state) {
  switch (state) {
    case TrackingState::kTracking:
    case TrackingState::kRelocalized: return LedPattern::kTracking;
    case TrackingState::kNotInitialized:
    case TrackingState::kInitializing: return LedPattern::kInitializing;
    case TrackingState::kLost: return LedPattern::kLost;
  }
  return LedPattern::kError;
}

bool led_lit(LedPattern p, std::int64_t t_ns) {
  // Camera clocks start anywhere; the phase within the second is all a pattern needs.
  const std::int64_t ms = ((t_ns / kMsNs) % 1000 + 1000) % 1000;
  switch (p) {
    case LedPattern::kOff: return false;
    case LedPattern::kTracking: return true;
    case LedPattern::kInitializing: return ms < 500;
    case LedPattern::kLost: return (ms % 250) < 125;
    case LedPattern::kError: return ms < 100 || (ms >= 200 && ms < 300);
  }
  return false;
}

void IrIlluminatorControl::configure(const GpioConfig& c) {
  on_after_ = c.ir_on_dark_frames;
  off_after_ = c.ir_off_normal_frames;
  min_toggle_ns_ = static_cast<std::int64_t>(c.ir_min_toggle_ms) * kMsNs;
}

bool IrIlluminatorControl::update(BrightnessClass c, std::int64_t t_ns) {
  if (c == BrightnessClass::kExtremelyDark) {
    ++dark_run_;
    normal_run_ = 0;
  } else if (c == BrightnessClass::kNormal || c == BrightnessClass::kBright) {
    ++normal_run_;
    dark_run_ = 0;
  } else {
    dark_run_ = 0;
    normal_run_ = 0;
  }
  const bool want = on_ ? normal_run_ < off_after_ : dark_run_ >= on_after_;
  const bool may_toggle = !toggled_ || t_ns - last_toggle_ns_ >= min_toggle_ns_;
  if (want != on_ && may_toggle) {
    on_ = want;
    toggled_ = true;
    last_toggle_ns_ = t_ns;
    ++toggles_;
  }
  return on_;
}

Status Indicators::set(ale::hal::GpioLine line, bool on, int& level) {
  if (level == (on ? 1 : 0)) return {};
  level = on ? 1 : 0;
  Status s = gpio_.set(line, on);
  if (s.code() == StatusCode::kUnsupported) return {};
  return s;
}

Status Indicators::show(LedPattern p, std::int64_t t_ns) {
  pattern_ = p;
  return set(ale::hal::GpioLine::kStatusLed, led_lit(p, t_ns), led_level_);
}

Status Indicators::on_frame(TrackingState state, BrightnessClass brightness, std::int64_t t_ns) {
  Status led = show(led_pattern_for(state), t_ns);
  Status ir = set(ale::hal::GpioLine::kIrIlluminator, ir_.update(brightness, t_ns), ir_level_);
  return led.ok() ? ir : led;
}

Status Indicators::on_error(std::int64_t t_ns) { return show(LedPattern::kError, t_ns); }

Status Indicators::off() {
  pattern_ = LedPattern::kOff;
  Status led = set(ale::hal::GpioLine::kStatusLed, false, led_level_);
  Status ir = set(ale::hal::GpioLine::kIrIlluminator, false, ir_level_);
  return led.ok() ? ir : led;
}

}  // namespace ale::app
