#include "core/base/frame_state.h"

namespace ale {

const char* to_string(BrightnessClass c) {
  switch (c) {
    case BrightnessClass::kExtremelyDark: return "extremely_dark";
    case BrightnessClass::kDark: return "dark";
    case BrightnessClass::kNormal: return "normal";
    case BrightnessClass::kBright: return "bright";
  }
  return "unknown";
}

const char* to_string(TrackingState s) {
  switch (s) {
    case TrackingState::kNotInitialized: return "not_initialized";
    case TrackingState::kInitializing: return "initializing";
    case TrackingState::kTracking: return "tracking";
    case TrackingState::kLost: return "lost";
    case TrackingState::kRelocalized: return "relocalized";
  }
  return "unknown";
}

}  // namespace ale
