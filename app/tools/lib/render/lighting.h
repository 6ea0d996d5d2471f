// Lighting profiles: how the room's light changes over a rendered sequence.
//
// The five levels of the article (bright, normal_bright, normal, normal_dark, dark) are constant
// illuminances chosen against the camera's exposure range (docs/rendering.md): the auto-exposure
// brings `normal` to its target, cannot darken `normal_bright` and `bright` below its shortest
// (anti-banding) exposure, and runs out of exposure and gain for `normal_dark` and `dark`.
#pragma once

#include <string>
#include <string_view>

#include "core/base/status.h"

namespace ale::render {

enum class LightProfile { kBright, kNormalBright, kNormal, kNormalDark, kDark, kOffOn, kSunlit, kDimming };

// "bright", "normal_bright", "normal", "normal_dark", "dark", "off_on", "sunlit", "dimming".
const char* to_string(LightProfile p);
Result<LightProfile> parse_light_profile(std::string_view name);
// All profile names, comma separated, for messages.
std::string light_profile_names();

// The light at one instant.
struct LightState {
  float room_lux = 150.0f;  // mean illuminance on the floor when the lamps are on
  bool lamps_on = true;
  float off_lux = 2.0f;     // uniform light left when the lamps are off (street light, standby LEDs)
  float sun_lux = 0.0f;     // extra illuminance inside the floor's sun patch
};

// Illuminance of the constant profiles, lux.
constexpr float kBrightLux = 1500.0f;
constexpr float kNormalBrightLux = 700.0f;
constexpr float kNormalLux = 150.0f;
constexpr float kNormalDarkLux = 4.0f;
constexpr float kDarkLux = 1.0f;

// The light of `profile` at `fraction` in [0, 1] of the sequence:
// - off_on: normal, lamps off from 30 % to 60 % of the sequence, on again after;
// - sunlit: normal plus 20000 lux of sun in the floor patch (saturates at any exposure the
//   room allows);
// - dimming: from 300 lux down to 1 lux, exponentially (a steady fraction per second).
LightState light_at(LightProfile profile, double fraction);

}  // namespace ale::render
