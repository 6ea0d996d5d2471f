// Command channel HAL: requests from the motion controller to the daemon (LCM on the robot, a
// queue in tests) and the daemon's answer to each.
#pragma once

#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "core/base/status.h"

namespace ale::hal {

// The wire values of ale_lcm.command_t.command.
enum class CommandKind : std::int8_t {
  kResetMap = 1, kSaveMap = 2, kPause = 3, kResume = 4, kSetLogLevel = 5, kLoadMap = 6
};
// The wire values of ale_lcm.command_reply_t.result.
enum class CommandResult : std::int8_t {
  kOk = 0, kUnknownCommand = 1, kBadArgument = 2, kNotSupported = 3, kFailed = 4, kMalformed = 5
};
// "ok", "unknown_command", ...
const char* to_string(CommandResult r);

struct Command {
  std::int64_t id = -1;
  std::int8_t kind = 0;   // raw: a value outside CommandKind is answered kUnknownCommand
  std::string argument;
  bool malformed = false; // the bytes received did not decode; `error` says why
  std::string error;
};

struct CommandReply {
  std::int64_t timestamp_ns = 0;
  std::int64_t id = -1;
  std::int8_t kind = 0;
  CommandResult result = CommandResult::kOk;
  std::string message;
};

class CommandChannel {
 public:
  virtual ~CommandChannel() = default;
  // Readable when commands may be waiting, for poll(); -1 when there is none.
  virtual int poll_fd() const { return -1; }
  // Appends every command that arrived since the last call; never blocks.
  virtual Status receive(std::vector<Command>& out) = 0;
  virtual Status reply(const CommandReply& reply) = 0;
};

// Commands queued by a test; replies kept.
class FakeCommandChannel final : public CommandChannel {
 public:
  Status receive(std::vector<Command>& out) override {
    if (!pending.empty()) {
      out.push_back(pending.front());
      pending.pop_front();
    }
    return {};
  }
  Status reply(const CommandReply& r) override {
    replies.push_back(r);
    return {};
  }
  std::deque<Command> pending;  // one is handed out per receive()
  std::vector<CommandReply> replies;
};

}  // namespace ale::hal
