// Pose sink HAL: where the daemon sends poses and status (LCM to the motion controller on the
// robot, a file or memory in replays and tests).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/base/frame_record.h"
#include "core/base/frame_state.h"
#include "core/base/status.h"

namespace ale::hal {

struct PoseEstimate {
  std::int64_t timestamp_ns = 0;  // exposure (capture) time, camera clock
  std::uint64_t frame_sequence = 0;
  TrackingState state = TrackingState::kNotInitialized;
  // Camera pose in the world (map) frame: position and unit quaternion (w, x, y, z).
  std::array<double, 3> p_wc{0, 0, 0};
  std::array<double, 4> q_wc{1, 0, 0, 0};
  // Body pose T_wb = T_wc * T_bc^-1 with the camera-to-body transform T_bc that was applied;
  // body_valid is false (and the body pose a copy of the camera's) when no extrinsics are known.
  bool body_valid = false;
  std::array<double, 3> p_bc{0, 0, 0};
  std::array<double, 4> q_bc{1, 0, 0, 0};
  std::array<double, 3> p_wb{0, 0, 0};
  std::array<double, 4> q_wb{1, 0, 0, 0};
  // Motion model: map frame, per second of camera time (zero until two poses are known).
  std::array<double, 3> velocity_w_mps{0, 0, 0};
  std::array<double, 3> angular_velocity_w_radps{0, 0, 0};
  int inliers = 0;        // map points the pose was optimised against
  int map_id = 0;         // bumped by each map reset (the loop stamps it)
  bool relocalized = false;
  // The pose from wheel odometry since the last posed frame (pose_t.odometry_only) and its
  // uncertainty, metres: state tracking while the odometry carries tracking through frames the
  // camera cannot track (slam.odometry.coast_s), then state lost.
  bool odometry_only = false;
  double position_sigma_m = 0.0;
};

// A memory pool's use so far, for the status message.
struct PoolUse {
  const char* name = "";  // a string literal
  std::uint64_t high_water = 0;
  std::uint64_t capacity = 0;
};

enum class CameraState { kStreaming, kTimeout, kReconnecting, kGone };
// "streaming", "timeout", "reconnecting", "gone"
const char* to_string(CameraState s);

// The recorder (recorder.dir): off, writing, or stopped by an error, a full disk or its cap.
enum class RecorderState { kOff, kRecording, kStopped };
// "off", "recording", "stopped"
const char* to_string(RecorderState s);

constexpr std::size_t kMaxStatusPools = 8;

struct StatusReport {
  std::int64_t timestamp_ns = 0;
  TrackingState state = TrackingState::kNotInitialized;
  BrightnessClass brightness = BrightnessClass::kNormal;
  float mean_intensity = 0;
  int features = 0;
  int inliers = 0;
  float frame_time_ms = 0;
  int keyframes = 0;
  int map_points = 0;
  int map_id = 0;
  int relocalisations = 0;  // frames posed by relocalisation after a loss (in the same map), since start
  float place_ms = 0;       // place recognition's time in this frame (SlamReport::place_ns)
  // Loop closing (SlamReport::loops_closed, loops_refused, loop_ns): loops closed and verified
  // loops refused by the correction bound since start, and its time in this frame.
  int loops_closed = 0;
  int loops_refused = 0;
  float loop_ms = 0;
  // Map merging (SlamReport::merges, merges_refused): maps joined since start (a keyframe of the
  // current map recognised a place of an older map kept since tracking was lost; the current map
  // moved into it, map_id is the older map's) and verified places of another map not joined.
  int merges = 0;
  int merges_refused = 0;
  std::array<PoolUse, kMaxStatusPools> pools{};
  std::size_t pool_count = 0;
  CameraState camera_state = CameraState::kStreaming;
  std::uint64_t camera_reconnects = 0;
  std::uint64_t frames_dropped = 0;
  std::uint64_t frames_skipped = 0;
  std::uint64_t frame_errors = 0;
  FrameTimings timings;  // per stage of the frame path
  int config_generation = 0;
  bool paused = false;
  std::uint64_t publish_errors = 0;
  std::uint64_t commands_received = 0;
  std::uint64_t commands_rejected = 0;
  RecorderState recorder_state = RecorderState::kOff;
  std::uint64_t frames_recorded = 0;      // in this run
  std::uint64_t frames_not_recorded = 0;  // delivered while recording was configured, not written
  // Wheel odometry samples handed to the SLAM core since start: kept, and refused by its checks
  // (not finite, time not increasing, a jump; slam::OdometryCounters).
  std::uint64_t odometry_accepted = 0;
  std::uint64_t odometry_refused = 0;
  // Map units per metre of camera travel by the odometry (slam::SlamReport::map_scale): 1 in a
  // metric map that kept its scale, 0 while unknown.
  double map_scale = 0.0;
  // Tracked frames the vision put beyond the odometry's 95 % gate (slip, spin, a stuck encoder).
  std::uint64_t odometry_disagreements = 0;
  // Map saves since start (map.save_period_s, SAVE_MAP, the end of the run): written, failed
  // (the previous file kept), and the last one's time, ms, whether it succeeded or not.
  std::uint64_t map_saves = 0;
  std::uint64_t map_save_failures = 0;
  float last_save_ms = 0;
  std::string last_error;
  std::string message;

  // Ignored beyond kMaxStatusPools.
  void add_pool(const char* name, std::uint64_t high_water, std::uint64_t capacity) {
    if (pool_count < pools.size()) pools[pool_count++] = {name, high_water, capacity};
  }
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
