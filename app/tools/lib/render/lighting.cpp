#include "app/tools/lib/render/lighting.h"

#include <algorithm>
#include <cmath>

namespace ale::render {

namespace {
constexpr LightProfile kAll[] = {LightProfile::kBright, LightProfile::kNormalBright, LightProfile::kNormal,
                                 LightProfile::kNormalDark, LightProfile::kDark, LightProfile::kOffOn,
                                 LightProfile::kSunlit, LightProfile::kDimming};
}

const char* to_string(LightProfile p) {
  switch (p) {
    case LightProfile::kBright: return "bright";
    case LightProfile::kNormalBright: return "normal_bright";
    case LightProfile::kNormal: return "normal";
    case LightProfile::kNormalDark: return "normal_dark";
    case LightProfile::kDark: return "dark";
    case LightProfile::kOffOn: return "off_on";
    case LightProfile::kSunlit: return "sunlit";
    case LightProfile::kDimming: return "dimming";
  }
  return "?";
}

std::string light_profile_names() {
  std::string s;
  for (LightProfile p : kAll) {
    if (!s.empty()) s += ", ";
    s += to_string(p);
  }
  return s;
}

Result<LightProfile> parse_light_profile(std::string_view name) {
  for (LightProfile p : kAll)
    if (name == to_string(p)) return p;
  return invalid_argument("unknown light profile '" + std::string(name) + "' (expected one of " +
                          light_profile_names() + ")");
}

LightState light_at(LightProfile profile, double fraction) {
  LightState s;
  const double f = std::clamp(fraction, 0.0, 1.0);
  switch (profile) {
    case LightProfile::kBright: s.room_lux = kBrightLux; break;
    case LightProfile::kNormalBright: s.room_lux = kNormalBrightLux; break;
    case LightProfile::kNormal: s.room_lux = kNormalLux; break;
    case LightProfile::kNormalDark: s.room_lux = kNormalDarkLux; break;
    case LightProfile::kDark: s.room_lux = kDarkLux; break;
    case LightProfile::kOffOn:
      s.room_lux = kNormalLux;
      s.lamps_on = !(f >= 0.3 && f < 0.6);
      break;
    case LightProfile::kSunlit:
      s.room_lux = kNormalLux;
      s.sun_lux = 20000.0f;
      break;
    case LightProfile::kDimming:
      s.room_lux = static_cast<float>(300.0 * std::pow(1.0 / 300.0, f));
      break;
  }
  return s;
}

}  // namespace ale::render
