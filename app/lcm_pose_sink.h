// Publishes poses and status over LCM to the sweeper's motion controller, and receives its
// commands (ale_lcm.command_t) and answers them (ale_lcm.command_reply_t).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/slam/odometry.h"
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

// The command that `size` received bytes on `channel` carry: an ale_lcm.command_t's fields, or
// malformed (with `error` naming the channel) when they are not one.
ale::hal::Command decode_command(const void* data, std::size_t size, const std::string& channel);

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

  // Receives ale_lcm.odometry_t on `channel` (empty: none) from now on; receive() collects them.
  Status subscribe_odometry(const std::string& channel);
  // Appends the samples received since the last call, in arrival order; returns how many
  // messages on the channel did not decode (the first is logged).
  std::uint64_t take_odometry(std::vector<ale::slam::OdometrySample>& out);

  lcm::LCM& lcm() { return *lcm_; }

 private:
  LcmPoseSink(std::unique_ptr<lcm::LCM> lcm, LcmChannels channels);
  void on_command(const lcm::ReceiveBuffer* buffer, const std::string& channel);
  // LCM calls this plain function (GCC 12's -fsanitize=vptr miscompiles LCM's member-function
  // dispatch: toolchains/host-asan.cmake).
  static void on_command_of(const lcm::ReceiveBuffer* buffer, const std::string& channel, LcmPoseSink* self) {
    self->on_command(buffer, channel);
  }
  void on_odometry(const lcm::ReceiveBuffer* buffer, const std::string& channel);
  static void on_odometry_of(const lcm::ReceiveBuffer* buffer, const std::string& channel, LcmPoseSink* self) {
    self->on_odometry(buffer, channel);
  }

  std::unique_ptr<lcm::LCM> lcm_;
  LcmChannels channels_;
  lcm::Subscription* command_subscription_ = nullptr;  // owned by lcm_
  std::vector<ale::hal::Command> received_;
  lcm::Subscription* odometry_subscription_ = nullptr;  // owned by lcm_
  std::vector<ale::slam::OdometrySample> odometry_;
  std::uint64_t odometry_malformed_ = 0;  // since the last take_odometry()
  bool odometry_malformed_logged_ = false;
};

}  // namespace ale::app
