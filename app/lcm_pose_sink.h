// Publishes poses and status over LCM to the sweeper's motion controller, and receives its
// commands (ale_lcm.command_t) and answers them (ale_lcm.command_reply_t).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "hal/command_channel.h"
#include "hal/pose_sink.h"

namespace lcm {
class LCM;
class ReceiveBuffer;
class Subscription;
}  // namespace lcm

namespace ale::app {

struct LcmChannels {
  std::string pose = "ALE_POSE";
  std::string status = "ALE_STATUS";
  std::string command = "ALE_COMMAND";  // empty: no commands are received
  std::string reply = "ALE_COMMAND_REPLY";
};

class LcmPoseSink final : public ale::hal::PoseSink, public ale::hal::CommandChannel {
 public:
  // kUnavailable (naming the URL) when LCM cannot be set up on `url` (tests use memq:// or
  // file://LOG?mode=w).
  static Result<std::unique_ptr<LcmPoseSink>> open(const std::string& url, LcmChannels channels);
  ~LcmPoseSink() override;

  // kIoError naming the channel when LCM refuses the message.
  Status publish(const ale::hal::PoseEstimate& pose) override;
  Status publish(const ale::hal::StatusReport& report) override;

  // LCM's file descriptor, for the daemon's poll(); receive() drains it.
  int poll_fd() const override;
  Status receive(std::vector<ale::hal::Command>& out) override;
  Status reply(const ale::hal::CommandReply& reply) override;

  // New channel names (a configuration reload); the command subscription moves with them.
  Status set_channels(LcmChannels channels);

  lcm::LCM& lcm() { return *lcm_; }

 private:
  LcmPoseSink(std::unique_ptr<lcm::LCM> lcm, LcmChannels channels);
  void on_command(const lcm::ReceiveBuffer* buffer, const std::string& channel);
  // LCM calls this plain function (GCC 12's -fsanitize=vptr miscompiles LCM's member-function
  // dispatch: toolchains/host-asan.cmake).
  static void on_command_of(const lcm::ReceiveBuffer* buffer, const std::string& channel, LcmPoseSink* self) {
    self->on_command(buffer, channel);
  }

  std::unique_ptr<lcm::LCM> lcm_;
  LcmChannels channels_;
  lcm::Subscription* command_subscription_ = nullptr;  // owned by lcm_
  std::vector<ale::hal::Command> received_;
};

}  // namespace ale::app
