// What the daemon does with a command from the motion controller, and the answer it gives.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "core/io/map_file.h"
#include "hal/command_channel.h"

namespace ale::app {

// The loop's state that commands change, and their counters for the status message.
struct LoopControl {
  bool paused = false;
  int map_resets = 0;  // resets asked for by command that succeeded
  std::uint64_t commands_received = 0;
  std::uint64_t commands_rejected = 0;  // answered with anything but kOk
};

// A map file written or read (FramePipeline::save_map / load_map): what it holds and the time it
// took, ms on the steady clock.
struct MapFileDone {
  ale::io::MapFileSummary file;
  double ms = 0.0;
  // A load asked for before the SLAM core exists: it is done when the first frame builds the core
  // (as map.load is), `file` and `ms` empty.
  bool waiting = false;
};

// What the map commands act on. An empty function answers kNotSupported.
struct MapCommands {
  // RESET_MAP: clears the map (the pipeline's reset_map()); an error is answered kFailed.
  std::function<Status()> reset;
  // SAVE_MAP / LOAD_MAP with a path: an error is answered kFailed with its reason.
  std::function<Result<MapFileDone>(const std::string& path)> save;
  std::function<Result<MapFileDone>(const std::string& path)> load;
  std::string save_path;  // map.save: SAVE_MAP's file when its argument is empty
  std::string load_path;  // map.load: LOAD_MAP's
};

// Applies `command` to `control` (pause, resume, log level) or to the map (reset, save, load) and
// says how it went. SAVE_MAP / LOAD_MAP without an argument and without a configured file are
// answered kBadArgument; unknown kinds kUnknownCommand, bytes that did not decode kMalformed.
// Never fails: every command gets a reply.
ale::hal::CommandReply handle_command(const ale::hal::Command& command, LoopControl& control, const MapCommands& map,
                                      std::int64_t now_ns);

}  // namespace ale::app
