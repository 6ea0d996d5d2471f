#include "app/daemon/reload.h"

#include <utility>

namespace ale::app {
namespace {

std::vector<std::pair<std::string, std::string>> key_values(const DaemonConfig& c) {
  std::vector<std::pair<std::string, std::string>> out;
  for_each_field(config_table(), &c, "", [&](const std::string& key, const ConfigField& f, const void* owner) {
    out.emplace_back(key, format_field(f, owner));
  });
  return out;
}

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

}  // namespace

bool runtime_key(const std::string& key) {
  for (const char* prefix : {"log.", "lcm.pose_channel", "lcm.status_channel", "lcm.command_channel",
                             "lcm.reply_channel", "gpio.ir_on_dark_frames", "gpio.ir_off_normal_frames",
                             "gpio.ir_min_toggle_ms", "camera.acquire_timeout_ms", "camera.max_consecutive_errors",
                             "camera.reconnect_", "features.enhance.", "slam.process_fps", "map.save"})
    if (starts_with(key, prefix)) return true;
  return false;
}

ReloadPlan plan_reload(const DaemonConfig& running, const DaemonConfig& loaded) {
  ReloadPlan plan;
  plan.effective = running;
  const auto before = key_values(running);
  const auto after = key_values(loaded);
  for (std::size_t i = 0; i < before.size() && i < after.size(); ++i) {
    if (before[i].second == after[i].second) continue;
    const std::string& key = after[i].first;
    if (!runtime_key(key)) {
      plan.needs_restart.push_back(key + " = " + after[i].second);
      continue;
    }
    // The value came out of format_field of a validated config: it parses back.
    (void)set_field(config_table(), &plan.effective, key, after[i].second, "reload");
    plan.applied.push_back(key + " = " + after[i].second);
  }
  return plan;
}

}  // namespace ale::app
