#include "app/daemon/commands.h"

#include "app/daemon/log.h"

namespace ale::app {
namespace {

using ale::hal::CommandKind;
using ale::hal::CommandResult;

void answer(ale::hal::CommandReply& r, CommandResult result, std::string message) {
  r.result = result;
  r.message = std::move(message);
}

}  // namespace

ale::hal::CommandReply handle_command(const ale::hal::Command& c, LoopControl& control, const ResetMap& reset_map,
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
        Status s = reset_map ? reset_map() : unsupported("this pipeline has no map to reset");
        if (s.ok()) {
          ++control.map_resets;
          answer(r, CommandResult::kOk, "map reset: the next frames start a new map");
        } else {
          answer(r, s.code() == StatusCode::kUnsupported ? CommandResult::kNotSupported : CommandResult::kFailed,
                 s.to_string());
        }
        break;
      }
      case CommandKind::kSaveMap:
        answer(r, CommandResult::kNotSupported, "saving maps is not supported yet");
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
    log_message(LogLevel::kInfo, "command %lld (kind %d) done", static_cast<long long>(c.id), c.kind);
  }
  return r;
}

}  // namespace ale::app
