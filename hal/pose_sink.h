// Pose sink HAL: where the daemon sends poses and status (LCM to the motion controller on the
// robot, a file or memory in replays and tests).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/base/frame_state.h"
#include "core/base/status.h"

namespace ale::hal {

struct PoseEstimate {
  std::int64_t timestamp_ns = 0;
  std::uint64_t frame_sequence = 0;
  TrackingState state = TrackingState::kNotInitialized;
  // Camera pose in the world (map) frame: position and unit quaternion (w, x, y, z).
  std::array<double, 3> p_wc{0, 0, 0};
  std::array<double, 4> q_wc{1, 0, 0, 0};
};

struct StatusReport {
  std::int64_t timestamp_ns = 0;
  TrackingState state = TrackingState::kNotInitialized;
  BrightnessClass brightness = BrightnessClass::kNormal;
  float mean_intensity = 0;
  int features = 0;
  int inliers = 0;
  float frame_time_ms = 0;
  std::uint64_t frames_dropped = 0;
  std::string message;
};

class PoseSink {
 public:
  virtual ~PoseSink() = default;
  virtual Status publish(const PoseEstimate& pose) = 0;
  virtual Status publish(const StatusReport& report) = 0;
};

class NullPoseSink final : public PoseSink {
 public:
  Status publish(const PoseEstimate&) override { return {}; }
  Status publish(const StatusReport&) override { return {}; }
};

// Keeps everything published, for tests.
class FakePoseSink final : public PoseSink {
 public:
  Status publish(const PoseEstimate& pose) override {
    poses.push_back(pose);
    return {};
  }
  Status publish(const StatusReport& report) override {
    reports.push_back(report);
    return {};
  }
  std::vector<PoseEstimate> poses;
  std::vector<StatusReport> reports;
};

}  // namespace ale::hal
