#include "app/config.h"

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>

namespace ale::app {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

using Setter = std::function<Status(const std::string& value, const std::string& where)>;

Setter int_in(int* out, int lo, int hi) {
  return [=](const std::string& v, const std::string& where) -> Status {
    errno = 0;
    char* end = nullptr;
    const long x = std::strtol(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0' || errno != 0)
      return invalid_argument(where + ": '" + v + "' is not an integer");
    if (x < lo || x > hi)
      return invalid_argument(where + ": " + v + " is out of range [" + std::to_string(lo) + ", " +
                              std::to_string(hi) + "]");
    *out = static_cast<int>(x);
    return {};
  };
}

Setter double_in(double* out, double lo, double hi) {
  return [=](const std::string& v, const std::string& where) -> Status {
    errno = 0;
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (v.empty() || *end != '\0' || errno != 0 || x != x)
      return invalid_argument(where + ": '" + v + "' is not a number");
    if (x < lo || x > hi)
      return invalid_argument(where + ": " + v + " is out of range [" + std::to_string(lo) + ", " +
                              std::to_string(hi) + "]");
    *out = x;
    return {};
  };
}

Setter string_of(std::string* out) {
  return [=](const std::string& v, const std::string&) -> Status {
    *out = v;
    return {};
  };
}

Setter one_of(std::string* out, std::initializer_list<const char*> allowed) {
  std::vector<std::string> options(allowed.begin(), allowed.end());
  return [=](const std::string& v, const std::string& where) -> Status {
    for (const std::string& o : options)
      if (v == o) {
        *out = v;
        return {};
      }
    std::string list;
    for (const std::string& o : options) list += (list.empty() ? "" : "|") + o;
    return invalid_argument(where + ": '" + v + "' is not one of " + list);
  };
}

Setter mode_of(ale::features::ExtractorMode* out) {
  return [=](const std::string& v, const std::string& where) -> Status {
    Result<ale::features::ExtractorMode> m = ale::features::parse_extractor_mode(v);
    if (!m.ok()) return invalid_argument(where + ": " + m.status().message());
    *out = *m;
    return {};
  };
}

Setter boolean(bool* out) {
  return [=](const std::string& v, const std::string& where) -> Status {
    if (v == "true" || v == "1" || v == "yes") *out = true;
    else if (v == "false" || v == "0" || v == "no") *out = false;
    else return invalid_argument(where + ": '" + v + "' is not a boolean (true/false)");
    return {};
  };
}

std::map<std::string, Setter> schema(DaemonConfig& c) {
  return {
      {"camera.source", one_of(&c.camera.source, {"v4l2", "replay"})},
      {"camera.device", string_of(&c.camera.device)},
      {"camera.replay_path", string_of(&c.camera.replay_path)},
      {"camera.width", int_in(&c.camera.width, 16, 4096)},
      {"camera.height", int_in(&c.camera.height, 16, 4096)},
      {"camera.fps", int_in(&c.camera.fps, 1, 120)},
      {"camera.buffers", int_in(&c.camera.buffers, 2, 32)},
      {"camera.acquire_timeout_ms", int_in(&c.camera.acquire_timeout_ms, 10, 60000)},
      {"camera.max_consecutive_errors", int_in(&c.camera.max_consecutive_errors, 1, 100000)},
      {"lcm.url", string_of(&c.lcm.url)},
      {"lcm.pose_channel", string_of(&c.lcm.pose_channel)},
      {"lcm.status_channel", string_of(&c.lcm.status_channel)},
      {"gpio.chip", string_of(&c.gpio.chip)},
      {"gpio.status_led", int_in(&c.gpio.status_led, -1, 1023)},
      {"gpio.ir_illuminator", int_in(&c.gpio.ir_illuminator, -1, 1023)},
      {"gpio.active_low", boolean(&c.gpio.active_low)},
      {"daemon.max_frames", int_in(&c.max_frames, 0, 1 << 30)},
      {"daemon.frame_log", string_of(&c.frame_log)},
      {"features.mode", mode_of(&c.features.mode)},
      {"features.num_features", int_in(&c.features.num_features, 1, 10000)},
      {"features.num_levels", int_in(&c.features.num_levels, 1, ale::features::kMaxLevels)},
      {"features.scale_factor", double_in(&c.features.scale_factor, 1.01, 4)},
      {"features.cell_size_px", int_in(&c.features.cell_size_px, 8, 256)},
      {"features.t_high", int_in(&c.features.t_high, 1, 254)},
      {"features.t_higher", int_in(&c.features.t_higher, 1, 254)},
      {"features.t_low", int_in(&c.features.t_low, 1, 254)},
      {"enhance.t_very_low", double_in(&c.features.enhance.grading.t_very_low, 0, 255)},
      {"enhance.t_low", double_in(&c.features.enhance.grading.t_low, 0, 255)},
      {"enhance.t_high", double_in(&c.features.enhance.grading.t_high, 0, 255)},
      {"enhance.hysteresis", double_in(&c.features.enhance.grading.hysteresis, 0, 64)},
      {"enhance.gamma_cdf_point", int_in(&c.features.enhance.gamma.cdf_point, 0, 255)},
      {"enhance.gamma_alpha", double_in(&c.features.enhance.gamma.alpha, 1e-3, 1)},
      {"enhance.gamma_min", double_in(&c.features.enhance.gamma.gamma_min, 0.05, 1)},
      {"enhance.clahe_tile_base", double_in(&c.features.enhance.clahe.tile_base, 0, 4096)},
      {"enhance.clahe_tile_scale", double_in(&c.features.enhance.clahe.tile_scale, 0, 4096)},
      {"enhance.clahe_tile_min", int_in(&c.features.enhance.clahe.tile_min, 8, 4096)},
      {"enhance.clahe_clip_base", double_in(&c.features.enhance.clahe.clip_base, 0, 256)},
      {"enhance.clahe_clip_contrast", double_in(&c.features.enhance.clahe.clip_contrast, 0, 256)},
      {"enhance.clahe_clip_min", double_in(&c.features.enhance.clahe.clip_min, 0, 256)},
      {"enhance.clahe_clip_max", double_in(&c.features.enhance.clahe.clip_max, 0, 256)},
  };
}

}  // namespace

Status parse_config(const std::string& text, const std::string& origin, DaemonConfig& config) {
  DaemonConfig parsed = config;  // the caller's config changes only if the whole file is valid
  const std::map<std::string, Setter> keys = schema(parsed);
  std::istringstream in(text);
  std::string line;
  std::string section;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string where_line = origin + ":" + std::to_string(line_no);
    const auto hash = line.find('#');
    line = trim(hash == std::string::npos ? line : line.substr(0, hash));
    if (line.empty()) continue;
    if (line.front() == '[') {
      if (line.back() != ']' || line.size() < 3) return invalid_argument(where_line + ": malformed section header");
      section = trim(line.substr(1, line.size() - 2));
      continue;
    }
    const auto eq = line.find('=');
    if (eq == std::string::npos) return invalid_argument(where_line + ": expected 'key = value'");
    const std::string key = trim(line.substr(0, eq));
    std::string value = trim(line.substr(eq + 1));
    if (value.size() >= 2 && value.front() == '"' && value.back() == '"') value = value.substr(1, value.size() - 2);
    const std::string full = section.empty() ? key : section + "." + key;
    auto it = keys.find(full);
    if (it == keys.end()) return invalid_argument(where_line + ": unknown key '" + full + "'");
    ALE_RETURN_IF_ERROR(it->second(value, where_line + ": " + full));
  }
  ALE_RETURN_IF_ERROR(validate_config(parsed));
  config = parsed;
  return {};
}

Status load_config(const std::string& path, DaemonConfig& config) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return not_found("config file " + path + " cannot be opened");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_config(ss.str(), path, config);
}

Status validate_config(const DaemonConfig& c) {
  if (c.camera.source == "replay" && c.camera.replay_path.empty())
    return invalid_argument("camera.replay_path: required when camera.source = replay");
  if (c.lcm.pose_channel.empty() || c.lcm.status_channel.empty())
    return invalid_argument("lcm.pose_channel / lcm.status_channel must not be empty");
  if ((c.gpio.status_led >= 0 || c.gpio.ir_illuminator >= 0) && c.gpio.chip.empty())
    return invalid_argument("gpio.chip: required when a GPIO line offset is set");
  if (Status s = ale::features::validate(c.features); !s.ok()) return invalid_argument("features: " + s.message());
  return {};
}

}  // namespace ale::app
