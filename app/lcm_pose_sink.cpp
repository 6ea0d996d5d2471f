#include "app/lcm_pose_sink.h"

#include <lcm/lcm-cpp.hpp>

#include "ale_lcm/pose_t.hpp"
#include "ale_lcm/status_t.hpp"

namespace ale::app {

Result<std::unique_ptr<LcmPoseSink>> LcmPoseSink::open(const std::string& url, std::string pose_channel,
                                                       std::string status_channel) {
  auto l = std::make_unique<lcm::LCM>(url);
  if (!l->good()) return unavailable("LCM cannot be set up on '" + url + "'");
  return std::unique_ptr<LcmPoseSink>(
      new LcmPoseSink(std::move(l), std::move(pose_channel), std::move(status_channel)));
}

LcmPoseSink::LcmPoseSink(std::unique_ptr<lcm::LCM> l, std::string pose_channel, std::string status_channel)
    : lcm_(std::move(l)), pose_channel_(std::move(pose_channel)), status_channel_(std::move(status_channel)) {}

LcmPoseSink::~LcmPoseSink() = default;

Status LcmPoseSink::publish(const ale::hal::PoseEstimate& pose) {
  ale_lcm::pose_t msg;
  msg.timestamp_ns = pose.timestamp_ns;
  msg.frame_sequence = static_cast<int64_t>(pose.frame_sequence);
  msg.state = static_cast<int8_t>(pose.state);
  for (int i = 0; i < 3; ++i) msg.position[i] = pose.p_wc[static_cast<std::size_t>(i)];
  for (int i = 0; i < 4; ++i) msg.orientation[i] = pose.q_wc[static_cast<std::size_t>(i)];
  if (lcm_->publish(pose_channel_, &msg) != 0) return io_error("LCM publish on " + pose_channel_ + " failed");
  return {};
}

Status LcmPoseSink::publish(const ale::hal::StatusReport& report) {
  ale_lcm::status_t msg;
  msg.timestamp_ns = report.timestamp_ns;
  msg.state = static_cast<int8_t>(report.state);
  msg.brightness_class = static_cast<int8_t>(report.brightness);
  msg.mean_intensity = report.mean_intensity;
  msg.features = report.features;
  msg.inliers = report.inliers;
  msg.frame_time_ms = report.frame_time_ms;
  msg.frames_dropped = static_cast<int64_t>(report.frames_dropped);
  msg.message = report.message;
  if (lcm_->publish(status_channel_, &msg) != 0) return io_error("LCM publish on " + status_channel_ + " failed");
  return {};
}

int LcmPoseSink::fd() const { return lcm_->getFileno(); }

Status LcmPoseSink::handle() {
  if (lcm_->handleTimeout(0) < 0) return io_error("LCM handle failed");
  return {};
}

}  // namespace ale::app
