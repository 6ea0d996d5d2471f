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
// Whether a frame in this state has a pose: tracked, or relocalised (the first pose after a loss).
constexpr bool has_pose(TrackingState s) { return s == TrackingState::kTracking || s == TrackingState::kRelocalized; }

}  // namespace ale
