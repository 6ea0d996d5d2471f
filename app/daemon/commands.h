// What the daemon does with a command from the motion controller, and the answer it gives.
#pragma once

#include <cstdint>
#include <functional>

#include "hal/command_channel.h"

namespace ale::app {

// The loop's state that commands change, and their counters for the status message.
struct LoopControl {
  bool paused = false;
  int map_resets = 0;  // resets asked for by command that succeeded
  std::uint64_t commands_received = 0;
  std::uint64_t commands_rejected = 0;  // answered with anything but kOk
};

// Clears the map (the pipeline's reset_map()); an error is answered kFailed.
using ResetMap = std::function<Status()>;

// Applies `command` to `control` (pause, resume, reset, log level) and says how it went. Save map
// is answered kNotSupported until maps can be saved; unknown kinds kUnknownCommand, bytes that
// did not decode kMalformed. Never fails: every command gets a reply.
ale::hal::CommandReply handle_command(const ale::hal::Command& command, LoopControl& control,
                                      const ResetMap& reset_map, std::int64_t now_ns);

}  // namespace ale::app
