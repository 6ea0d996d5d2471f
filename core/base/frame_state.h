// Small enums shared by the core, the HAL's status reports and the tools.
#pragma once

namespace ale {

// Brightness class of a frame (spec section 1).
enum class BrightnessClass { kExtremelyDark, kDark, kNormal, kBright };
// "extremely_dark", "dark", "normal", "bright"
const char* to_string(BrightnessClass c);

enum class TrackingState { kNotInitialized, kInitializing, kTracking, kLost, kRelocalized };
// "not_initialized", "initializing", "tracking", "lost", "relocalized"
const char* to_string(TrackingState s);

}  // namespace ale
