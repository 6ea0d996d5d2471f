#include "app/daemon/commands.h"

#include <cstdio>

#include "app/daemon/log.h"

namespace ale::app {
namespace {

using ale::hal::CommandKind;
using ale::hal::CommandResult;

void answer(ale::hal::CommandReply& r, CommandResult result, std::string message) {
  r.result = result;
  r.message = std::move(message);
}

// kNotSupported for an action the loop did not give, kFailed for any other error.
void refuse(ale::hal::CommandReply& r, const Status& s) {
  answer(r, s.code() == StatusCode::kUnsupported ? CommandResult::kNotSupported : CommandResult::kFailed, s.to_string());
}

std::string describe(const MapFileDone& done) {
  char text[160];
  std::snprintf(text, sizeof text, "%d keyframes, %d landmarks in %d map(s), %llu bytes, %.1f ms", done.file.keyframes,
                done.file.landmarks, done.file.maps, static_cast<unsigned long long>(done.file.bytes), done.ms);
  return text;
}

// SAVE_MAP / LOAD_MAP: the argument's file, or the configured one.
void map_file(const ale::hal::Command& c, const MapCommands& map, ale::hal::CommandReply& r) {
  const bool save = static_cast<CommandKind>(c.kind) == CommandKind::kSaveMap;
  const auto& action = save ? map.save : map.load;
  const std::string& path = c.argument.empty() ? (save ? map.save_path : map.load_path) : c.argument;
  if (!action) return refuse(r, unsupported(save ? "this pipeline cannot save maps" : "this pipeline cannot load maps"));
  if (path.empty())
    return answer(r, CommandResult::kBadArgument,
                  save ? "no path given and map.save is not set" : "no path given and map.load is not set");
  Result<MapFileDone> done = action(path);
  if (!done.ok()) {
    refuse(r, done.status());
    r.message = (save ? "map not saved to " + path + ": " + r.message + "; the previous file is kept"
                      : "map file " + path + " not loaded: " + r.message + "; the map is as it was");
  } else if (done->waiting) {
    r.message = "map file " + path + " will be loaded when the SLAM core starts (the first frame)";
  } else if (save) {
    r.message = "map saved to " + path + ": " + describe(*done);
  } else {
    r.message = "map loaded from " + path + ": " + describe(*done) +
                (done->file.keyframes > 0 ? "; relocalising in map " + std::to_string(done->file.current_map)
                                          : "; no keyframe in it: the next frames start a map");
  }
}

}  // namespace

ale::hal::CommandReply handle_command(const ale::hal::Command& c, LoopControl& control, const MapCommands& map,
                                      std::int64_t now_ns) {
  ale::hal::CommandReply r;
  r.timestamp_ns = now_ns;
  r.id = c.id;
  r.kind = c.kind;
  ++control.commands_received;
  if (c.malformed) {
    answer(r, CommandResult::kMalformed, c.error);
  } else {
    switch (static_cast<CommandKind>(c.kind)) {
      case CommandKind::kResetMap: {
        Status s = map.reset ? map.reset() : unsupported("this pipeline has no map to reset");
        if (s.ok()) {
          ++control.map_resets;
          answer(r, CommandResult::kOk, "map reset: the next frames start a new map");
        } else {
          refuse(r, s);
        }
        break;
      }
      case CommandKind::kSaveMap:
      case CommandKind::kLoadMap:
        map_file(c, map, r);
        break;
      case CommandKind::kPause:
        control.paused = true;
        break;
      case CommandKind::kResume:
        control.paused = false;
        break;
      case CommandKind::kSetLogLevel: {
        auto level = parse_log_level(c.argument);
        if (level.ok())
          set_log_level(*level);
        else
          answer(r, CommandResult::kBadArgument, level.status().message());
        break;
      }
      default:
        answer(r, CommandResult::kUnknownCommand, "command " + std::to_string(c.kind) + " is unknown");
        break;
    }
  }
  if (r.result != CommandResult::kOk) {
    ++control.commands_rejected;
    log_message(LogLevel::kWarning, "command %lld (kind %d) answered %s: %s", static_cast<long long>(c.id), c.kind,
                to_string(r.result), r.message.c_str());
  } else {
    log_message(LogLevel::kInfo, "command %lld (kind %d) done%s%s", static_cast<long long>(c.id), c.kind,
                r.message.empty() ? "" : ": ", r.message.c_str());
  }
  return r;
}

}  // namespace ale::app
