// SIGHUP: which keys of a reloaded configuration the running daemon takes over, and which wait
// for a restart.
#pragma once

#include <string>
#include <vector>

#include "app/config.h"

namespace ale::app {

// Keys that change while the daemon runs: log.*, the LCM channels, the IR thresholds, the
// camera's timeout, error and reconnect settings, the enhancement parameters (features.enhance.*:
// grading thresholds, gamma, level CLAHE) and slam.process_fps. Everything else (the camera's
// device, size and rate, lcm.url, the rest of features.* and slam.*, daemon.*, recorder.*) needs a
// restart.
bool runtime_key(const std::string& key);

struct ReloadPlan {
  DaemonConfig effective;                   // the running configuration with the runtime keys taken over
  std::vector<std::string> applied;         // "key = value" taken over
  std::vector<std::string> needs_restart;   // "key = value" kept at the running value
};

// Compares the running configuration with a freshly loaded (and validated) one.
ReloadPlan plan_reload(const DaemonConfig& running, const DaemonConfig& loaded);

}  // namespace ale::app
