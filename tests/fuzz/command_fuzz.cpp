// A command as the daemon receives it from LCM (app/lcm_pose_sink.h decode_command(): the bytes
// of an ale_lcm.command_t through lcm-gen's decode()) and what the daemon does with it
// (app/daemon/commands.h handle_command()). Every input gets a reply; bytes that do not decode
// are answered kMalformed, and the reply names the command it answers.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "app/daemon/commands.h"
#include "app/daemon/log.h"
#include "app/lcm_pose_sink.h"

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ale;
  // A SET_LOG_LEVEL of an earlier input must not make this one's messages flood the run.
  app::set_log_level(app::LogLevel::kError);
  const hal::Command command = app::decode_command(data, size, "ALE_COMMAND");
  app::LoopControl control;
  int resets = 0, files = 0;
  app::MapCommands map;
  map.reset = [&resets]() -> Status {
    ++resets;
    return {};
  };
  // SAVE_MAP / LOAD_MAP: the path is taken, nothing is written or read here
  const auto file = [&files](const std::string& path) -> Result<app::MapFileDone> {
    ++files;
    if (path.empty()) return invalid_argument("an empty path reached the map callback");
    return app::MapFileDone{};
  };
  map.save = file;
  map.load = file;
  const hal::CommandReply reply = app::handle_command(command, control, map, 1);
  check(reply.id == command.id && reply.kind == command.kind);
  check(!command.malformed || reply.result == hal::CommandResult::kMalformed);
  check(control.commands_received == 1 && control.map_resets == resets);
  check(files <= 1 && (files == 0 || reply.result == hal::CommandResult::kOk));
  return 0;
}
