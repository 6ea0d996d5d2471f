// Publishes poses and status over LCM to the sweeper's motion controller.
#pragma once

#include <memory>
#include <string>

#include "hal/pose_sink.h"

namespace lcm {
class LCM;
}

namespace ale::app {

class LcmPoseSink final : public ale::hal::PoseSink {
 public:
  // kUnavailable (naming the URL) when LCM cannot be set up on `url` (tests use memq://).
  static Result<std::unique_ptr<LcmPoseSink>> open(const std::string& url, std::string pose_channel,
                                                   std::string status_channel);
  ~LcmPoseSink() override;

  Status publish(const ale::hal::PoseEstimate& pose) override;
  Status publish(const ale::hal::StatusReport& report) override;
  // LCM's file descriptor, for the daemon's poll(); handle() drains it.
  int fd() const;
  Status handle();
  lcm::LCM& lcm() { return *lcm_; }

 private:
  LcmPoseSink(std::unique_ptr<lcm::LCM> lcm, std::string pose_channel, std::string status_channel);
  std::unique_ptr<lcm::LCM> lcm_;
  std::string pose_channel_;
  std::string status_channel_;
};

}  // namespace ale::app
