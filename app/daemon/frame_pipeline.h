// The per-frame work between camera and pose sink: the firmware's whole path
// (core/slam/slam_pipeline.h: the ORB front end with the ALE lighting-adaptive enhancement, then
// tracking and inline local mapping), turned into the pose, status and frame-log records the daemon
// publishes.
#pragma once

#include <memory>
#include <string>

#include "app/config.h"
#include "app/daemon/commands.h"
#include "core/base/frame_log.h"
#include "core/base/image.h"
#include "core/enhance/enhancer.h"
#include "core/frontend/frame_path.h"
#include "core/place/vocabulary.h"
#include "core/slam/slam_pipeline.h"
#include "hal/camera.h"
#include "hal/pose_sink.h"

namespace ale::app {

// A processed frame, made once: FramePipeline::process fills it in place from the SLAM core's
// report (read by reference), the frame loop adds what only it knows (the camera's pool, the frame
// time, its counters) and publishes `pose` and `status` themselves; the frame log and the
// trajectory file read the same record. Each figure has one place: the map's id, size and the
// stage times (each stage of the frame path, the SLAM core's last) are in `status` (the map id
// also in `pose`, which is published with it).
struct FrameRecord {
  ale::hal::PoseEstimate pose;
  ale::hal::StatusReport status;
  ale::enhance::EnhanceReport enhance;
  bool map_reset = false;  // this frame started a new map: a new trajectory segment
  int resets = 0;
  int matches = 0;
};

class FramePipeline {
 public:
  // calibration: the lens of the frames (Board::calibration); width/height 0 when the first frame
  // gives them. `config` is one validate_config accepted (it is not checked again here); the core
  // refuses a bad one when the path is built (here, or at the first frame when that gives the
  // size). kInvalidArgument without focal lengths.
  Status configure(const DaemonConfig& config, const ale::hal::CameraCalibration& calibration);
  // kInvalidArgument for a frame the pipeline cannot take (another size than the first, a
  // timestamp that does not increase); nothing changes then and the caller may go on.
  Status process(const ale::hal::Frame& frame, FrameRecord& record);
  // Starts a new map; the next frames initialise again.
  void reset_map();
  // The last frame made a keyframe: the next one runs its deferred local BA (the frame loop
  // keeps a periodic save off that frame).
  bool keyframe_inserted() const { return path_ && path_->report().keyframe_inserted; }
  // The map file (core/io/map_file.h) through the SLAM core, timed, with a log line saying what
  // happened. save_map: kUnavailable before the core exists (the first frame builds it).
  Result<MapFileDone> save_map(const std::string& path);
  // Loads `path` in place of every map held (the core's load_map: checked whole first, a refused
  // file changes nothing); before the core exists the file waits for it (as map.load does) and
  // the answer is `waiting`.
  Result<MapFileDone> load_map(const std::string& path);
  // The enhancement parameters (features.enhance: grading thresholds, gamma, level CLAHE) from the
  // next frame on, the map and the held brightness class kept (a SIGHUP reload).
  // kInvalidArgument naming the bad key; nothing changes then.
  Status set_enhance(const ale::enhance::EnhanceParams& params);
  const std::vector<ale::features::Keypoint>& keypoints() const;
  // One wheel odometry sample for the SLAM core (SlamSystem::add_odometry), in the MCU's order.
  // Before the core is built (the first frame gives the size) the last slam.odometry.capacity
  // samples wait for it. A refused sample is counted by the core; the first of each kind (not
  // finite, time not increasing, a jump) is logged, the rest only counted.
  void add_odometry(const ale::slam::OdometrySample& sample);
  // The core's odometry counters since start (zero before the core is built).
  ale::slam::OdometryCounters odometry_counters() const;
  // Keep the poses relative to keyframes for the end of the run (SlamSystem::record_trajectory);
  // set before the first frame.
  void record_trajectory(bool on) { record_trajectory_ = on; }
  // The run's trajectory with every frame composed with its keyframe's final pose; nullptr before
  // the first frame.
  const ale::slam::RefinedTrajectory* resolve_trajectory() { return path_ ? &path_->resolve_trajectory() : nullptr; }

 private:
  Status start(int width, int height);
  // map.load at start: a missing file starts an empty map; a refused one is moved aside to
  // PATH.refused and the backup PATH.bak is tried. Never fails: the robot runs without a map.
  void load_at_start(const std::string& path);

  ale::features::ExtractorConfig features_;
  ale::slam::SlamParams slam_;
  std::shared_ptr<const ale::place::Vocabulary> vocabulary_;
  ale::hal::CameraCalibration calibration_;
  std::unique_ptr<ale::slam::SlamPipeline> path_;  // built for the first frame's size
  bool record_trajectory_ = false;
  std::string map_load_;  // map.load, or a LOAD_MAP before the core existed
  std::vector<ale::slam::OdometrySample> odometry_waiting_;  // until path_ is built
  bool odometry_logged_[3] = {false, false, false};           // not finite, not increasing, jump
  int merges_logged_ = 0;          // SlamReport::merges when last logged
  int merges_refused_logged_ = 0;  // and merges_refused
};

// Place recognition's vocabulary for daemon.vocabulary: builtin, none (nullptr) or a file;
// kNotFound / kInvalidArgument naming the file and what is wrong with it.
Result<std::shared_ptr<const ale::place::Vocabulary>> load_vocabulary(const std::string& setting);

// The camera model of a calibration whose image size is width x height.
Result<ale::geometry::Camera> camera_of(const ale::hal::CameraCalibration& calibration, int width, int height);

// The frame-log row of a processed frame (core/base/frame_log.h, read by ale-eval --report).
FrameLogRow frame_log_row(const FrameRecord& record);

}  // namespace ale::app
