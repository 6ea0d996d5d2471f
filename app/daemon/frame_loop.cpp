#include "app/daemon/frame_loop.h"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "app/daemon/commands.h"
#include "app/daemon/frame_pipeline.h"
#include "app/daemon/frame_selector.h"
#include "app/daemon/indicators.h"
#include "app/daemon/log.h"
#include "app/daemon/pose_frames.h"
#include "app/daemon/reload.h"
#include "app/daemon/trajectory_file.h"
#include "core/base/frame_record.h"

namespace ale::app {
namespace {

using ale::hal::CameraState;

enum class Wake { kFrame, kStop, kTimeout };

constexpr std::int64_t kMsNs = 1000000;

class FrameLoop {
 public:
  FrameLoop(const DaemonConfig& config, LoopDeps& deps, RunSummary& summary)
      : config_(config), deps_(deps), summary_(summary), camera_(&deps.camera), selector_(config.slam.process_fps),
        indicators_(deps.gpio, config.gpio) {}
  Status run();

 private:
  std::int64_t now_ns() const;
  bool wait(std::int64_t wait_ns);
  Wake wait_for_frame(int timeout_ms);
  void drain_commands();
  void reload();
  void count(const Status& published);
  void publish_status();
  void set_camera_state(CameraState state);
  void show(const Status& gpio_result);
  // Ok when a camera streams again or a stop request came (summary_.stopped_by_signal); the
  // reason to end the loop when the camera is not back after the give-up time.
  Status reconnect(const Status& why);
  // Processes and releases the frame; `released` says how giving the buffer back went.
  Status process(const ale::hal::Frame& frame, Status& released);
  // After the camera failed: reopen it when the board can (ok: go on), else the reason to end.
  Status camera_lost(const Status& why);
  // T_bc from the camera's calibration when daemon.body_frame asks for it.
  void read_extrinsics();
  // recorder.dir: starts the recorder with its first sequence.
  void start_recorder();
  // Logs what the recorder's thread reported.
  void drain_recorder();
  // Hands the samples to the core and to the recorder.
  void add_odometry(const std::vector<ale::slam::OdometrySample>& samples);
  // A map file saved (save) or loaded through the pipeline between two frames, timed: a save is
  // counted for the status, and the time is added to the next processed frame's.
  Result<MapFileDone> map_file(bool save, const std::string& path);
  // map.save_period_s: saves map.save once the period has passed since the last save, the
  // current map has keyframes and the frame just processed made none.
  void save_when_due();

  DaemonConfig config_;  // a copy: a reload changes it
  LoopDeps& deps_;
  RunSummary& summary_;
  ale::hal::Camera* camera_;  // null while a lost camera is being reopened
  FramePipeline pipeline_;
  FrameLogWriter log_;
  TrajectoryFile trajectory_;
  FrameSelector selector_;
  Indicators indicators_;
  LoopControl control_;
  FrameRecord record_;  // its status is the last one, republished on camera and pause events
  CameraState camera_state_ = CameraState::kStreaming;
  std::int64_t last_frame_ns_ = 0;  // now_ns() of the last frame delivered (or of the start)
  std::optional<RigidTransform> T_bc_;  // daemon.body_frame = calibration
  ale::hal::PoseEstimate previous_pose_;
  std::vector<ale::hal::Command> commands_;
  std::vector<ale::slam::OdometrySample> odometry_;  // received over LCM, being handed over
  std::uint64_t odometry_malformed_ = 0;             // LCM messages that were not an odometry_t
  bool gpio_warned_ = false;
  std::unique_ptr<Recorder> recorder_;  // recorder.dir set
  std::int64_t last_save_ns_ = 0;       // now_ns() of the last save, or of the start
  float last_save_ms_ = 0.0f;           // the last save's time, whether it succeeded or not
  // The time of the map file work since the last frame the camera delivered, -1 when there was
  // none: it delayed the next frame, and the next processed frame's time counts it.
  std::int64_t map_file_ns_ = -1;
};

std::int64_t FrameLoop::now_ns() const {
  if (deps_.clock != nullptr) return deps_.clock->now_ns();
  return steady_clock_ns();
}

bool FrameLoop::wait(std::int64_t wait_ns) {
  if (deps_.wait) return deps_.wait(wait_ns);
  // A reload request is served during the wait, which then goes on to its end.
  const std::int64_t end_ns = steady_clock_ns() + wait_ns;
  for (std::int64_t left_ns = wait_ns; left_ns > 0; left_ns = end_ns - steady_clock_ns()) {
    pollfd fds[2] = {{deps_.stop_fd, POLLIN, 0}, {deps_.reload_fd, POLLIN, 0}};
    const int ready = ::poll(fds, 2, static_cast<int>(std::min<std::int64_t>((left_ns + kMsNs - 1) / kMsNs, 1 << 30)));
    if (ready <= 0) continue;  // timeout (or EINTR): the loop condition decides
    if ((fds[0].revents & POLLIN) != 0) return true;
    if ((fds[1].revents & POLLIN) != 0) reload();
  }
  return false;
}

// Waits on the camera's descriptor, the stop descriptor and the command channel's together, so a
// stop request or a command is seen at once even while the camera is silent. A camera without a
// descriptor (a replay) does its own waiting in acquire(), and the others are only peeked at.
Wake FrameLoop::wait_for_frame(int timeout_ms) {
  pollfd fds[4];
  const int cam_fd = camera_->poll_fd();
  fds[0] = pollfd{deps_.stop_fd, POLLIN, 0};
  fds[1] = pollfd{deps_.commands != nullptr ? deps_.commands->poll_fd() : -1, POLLIN, 0};
  fds[2] = pollfd{cam_fd, POLLIN, 0};  // negative fds are ignored
  fds[3] = pollfd{deps_.reload_fd, POLLIN, 0};
  const int ready = ::poll(fds, 4, cam_fd >= 0 ? timeout_ms : 0);
  if (ready > 0 && (fds[0].revents & POLLIN) != 0) return Wake::kStop;
  if (ready > 0 && (fds[3].revents & POLLIN) != 0) reload();
  // A channel without a descriptor is asked every time (receive() never blocks).
  if (fds[1].fd < 0 || (ready > 0 && (fds[1].revents & POLLIN) != 0)) drain_commands();
  if (cam_fd < 0) return Wake::kFrame;
  // Readable, or an error condition that acquire() will turn into a reason.
  if (ready > 0 && fds[2].revents != 0) return Wake::kFrame;
  return ready == 0 ? Wake::kTimeout : Wake::kFrame;
}

void FrameLoop::count(const Status& published) {
  if (published.ok()) return;
  ++summary_.publish_errors;
  log_message(LogLevel::kError, "publish error: %s", published.to_string().c_str());
}

void FrameLoop::drain_commands() {
  if (deps_.commands == nullptr) return;
  MapCommands map_commands;
  map_commands.reset = [this] {
    pipeline_.reset_map();
    return Status{};
  };
  map_commands.save = [this](const std::string& path) { return map_file(true, path); };
  map_commands.load = [this](const std::string& path) { return map_file(false, path); };
  map_commands.save_path = config_.map.save;
  map_commands.load_path = config_.map.load;
  commands_.clear();
  count(deps_.commands->receive(commands_));
  for (const ale::hal::Command& c : commands_) {
    const ale::hal::CommandReply reply = handle_command(c, control_, map_commands, now_ns());
    count(deps_.commands->reply(reply));
  }
  summary_.commands = control_.commands_received;
  summary_.commands_rejected = control_.commands_rejected;
  if (deps_.take_odometry) {
    odometry_.clear();
    odometry_malformed_ += deps_.take_odometry(odometry_);
    add_odometry(odometry_);
  }
}

void FrameLoop::reload() {
  // Drain the request (a signalfd's siginfo, or an eventfd's counter in tests): one reload for
  // however many signals arrived.
  char buffer[128];
  while (::read(deps_.reload_fd, buffer, sizeof buffer) > 0) {
  }
  if (!deps_.load_config) return;
  DaemonConfig loaded;
  Status s = deps_.load_config(loaded);
  ReloadPlan plan;
  if (s.ok()) {
    plan = plan_reload(config_, loaded);
    s = validate_config(plan.effective);
  }
  // The pipeline's enhancement first: valid by now, and put back should what follows fail.
  const bool enhance_changed =
      s.ok() && std::any_of(plan.applied.begin(), plan.applied.end(),
                            [](const std::string& key) { return key.rfind("features.enhance.", 0) == 0; });
  if (enhance_changed) s = pipeline_.set_enhance(plan.effective.features.enhance);
  if (s.ok() && deps_.apply_config) s = deps_.apply_config(plan.effective);
  if (s.ok()) s = configure_log(plan.effective.log.level, plan.effective.log.target);
  if (!s.ok() && enhance_changed) (void)pipeline_.set_enhance(config_.features.enhance);
  if (!s.ok()) {
    ++summary_.reloads_refused;
    log_message(LogLevel::kError, "configuration reload refused, generation %d kept: %s", summary_.config_generation,
                s.to_string().c_str());
    return;
  }
  for (const std::string& key : plan.needs_restart)
    log_message(LogLevel::kWarning, "reload: %s needs a restart; the running value is kept", key.c_str());
  if (plan.effective.slam.process_fps != config_.slam.process_fps) selector_.configure(plan.effective.slam.process_fps);
  config_ = plan.effective;
  indicators_.configure(config_.gpio);
  ++summary_.config_generation;
  std::string applied;
  for (const std::string& key : plan.applied) applied += (applied.empty() ? "" : ", ") + key;
  log_message(LogLevel::kInfo, "configuration generation %d: %s", summary_.config_generation,
              applied.empty() ? "nothing changed" : applied.c_str());
  publish_status();
}

void FrameLoop::publish_status() {
  ale::hal::StatusReport& s = record_.status;
  s.camera_state = camera_state_;
  s.camera_reconnects = summary_.camera_reconnects;
  s.frames_skipped = summary_.frames_skipped;
  s.frame_errors = summary_.frame_errors;
  if (camera_ != nullptr) s.frames_dropped = camera_->stats().dropped;
  s.paused = control_.paused;
  s.commands_received = control_.commands_received;
  s.commands_rejected = control_.commands_rejected;
  if (recorder_) {
    drain_recorder();  // a recorder error is the status' last error at once
    recorder_->counters(s);
  }
  s.last_error = last_error();
  s.publish_errors = summary_.publish_errors;  // those before this one
  s.config_generation = summary_.config_generation;
  const ale::slam::OdometryCounters odometry = pipeline_.odometry_counters();
  s.odometry_accepted = summary_.odometry_accepted = odometry.accepted;
  s.odometry_refused = summary_.odometry_refused = odometry.refused() + odometry_malformed_;
  s.map_saves = summary_.map_saves;
  s.map_save_failures = summary_.map_save_failures;
  s.last_save_ms = last_save_ms_;
  count(deps_.sink.publish(s));
  if (summary_.first_status_ns < 0 && deps_.start_ns > 0) {
    summary_.first_status_ns = steady_clock_ns() - deps_.start_ns;
    log_message(LogLevel::kInfo, "first status published %.1f ms after start",
                static_cast<double>(summary_.first_status_ns) / 1e6);
  }
}

void FrameLoop::set_camera_state(CameraState state) {
  if (state == camera_state_) return;
  log_message(state == CameraState::kStreaming ? LogLevel::kInfo : LogLevel::kWarning, "camera %s",
              ale::hal::to_string(state));
  camera_state_ = state;
  publish_status();
}

void FrameLoop::show(const Status& gpio_result) {
  if (gpio_result.ok() || gpio_warned_) return;
  gpio_warned_ = true;  // once: a broken line would otherwise log every frame
  log_message(LogLevel::kWarning, "gpio: %s", gpio_result.to_string().c_str());
}

Status FrameLoop::reconnect(const Status& why) {
  log_message(LogLevel::kError, "camera lost (%s); reopening it, the map is kept", why.to_string().c_str());
  (void)camera_->stop();  // a device that is gone refuses STREAMOFF: nothing more to do with it
  camera_ = nullptr;
  set_camera_state(CameraState::kReconnecting);
  std::int64_t delay_ns = static_cast<std::int64_t>(config_.camera.reconnect_initial_ms) * kMsNs;
  Status last = why;
  for (;;) {
    // The give-up time runs from the last frame, so a camera that reopens but never delivers is
    // given up as well; it is read on every try, as a reload during a wait may have changed it.
    const std::int64_t give_up_ns = static_cast<std::int64_t>(config_.camera.reconnect_give_up_ms) * kMsNs;
    const std::int64_t away_ns = now_ns() - last_frame_ns_;
    if (away_ns >= give_up_ns) {
      set_camera_state(CameraState::kGone);
      return unavailable(why.message() + "; the camera is not back after " + std::to_string(away_ns / kMsNs) +
                         " ms (camera.reconnect_give_up_ms = " + std::to_string(config_.camera.reconnect_give_up_ms) +
                         "): " + last.message());
    }
    show(indicators_.on_error(now_ns()));
    if (wait(delay_ns)) {
      summary_.stopped_by_signal = true;
      return {};
    }
    drain_commands();
    Result<ale::hal::Camera*> reopened = deps_.reopen_camera();
    last = reopened.ok() ? (*reopened)->start() : reopened.status();
    if (last.ok()) {
      camera_ = *reopened;
      read_extrinsics();
      if (recorder_) recorder_->new_sequence(deps_.calibration);  // a new camera session
      ++summary_.camera_reconnects;
      set_camera_state(CameraState::kStreaming);
      return {};
    }
    log_message(LogLevel::kWarning, "camera not back after %lld ms: %s",
                static_cast<long long>((now_ns() - last_frame_ns_) / kMsNs), last.to_string().c_str());
    publish_status();  // still reconnecting: the controller sees the daemon is alive
    delay_ns = std::min(2 * delay_ns, static_cast<std::int64_t>(config_.camera.reconnect_max_ms) * kMsNs);
  }
}

void FrameLoop::start_recorder() {
  if (config_.recorder.dir.empty()) return;
  RecorderOptions o;
  o.dir = config_.recorder.dir;
  o.max_bytes = static_cast<std::uint64_t>(config_.recorder.max_mb) << 20;
  o.queue_frames = config_.recorder.queue_frames;
  o.png = io::PngWriteOptions{config_.recorder.png_compression, false};
  // A camera without a descriptor to wait on (a replay) is not real time: the loop may wait for
  // the writer, and the recording is complete.
  o.wait_when_full = camera_->poll_fd() < 0;
  o.odometry = deps_.odometry_sensor;
  recorder_ = std::make_unique<Recorder>(o, deps_.record_writer);
  recorder_->start();
  recorder_->new_sequence(deps_.calibration);
}

void FrameLoop::add_odometry(const std::vector<ale::slam::OdometrySample>& samples) {
  for (const ale::slam::OdometrySample& sample : samples) pipeline_.add_odometry(sample);
  if (recorder_) recorder_->submit_odometry(samples);  // as received, before the core's checks
}

Result<MapFileDone> FrameLoop::map_file(bool save, const std::string& path) {
  const std::int64_t start_ns = steady_clock_ns();
  Result<MapFileDone> done = save ? pipeline_.save_map(path) : pipeline_.load_map(path);
  const std::int64_t took_ns = steady_clock_ns() - start_ns;
  map_file_ns_ = std::max<std::int64_t>(map_file_ns_, 0) + took_ns;
  if (!save) {
    if (done.ok()) trajectory_.start_segment();
    return done;
  }
  last_save_ns_ = now_ns();
  last_save_ms_ = static_cast<float>(static_cast<double>(took_ns) / 1e6);
  if (done.ok()) {
    ++summary_.map_saves;
    summary_.save.add(took_ns);
  } else if (done.status().code() != StatusCode::kUnavailable) {  // kUnavailable: no map yet, nothing to save
    ++summary_.map_save_failures;
  }
  return done;
}

void FrameLoop::save_when_due() {
  if (config_.map.save_period_s <= 0.0 || config_.map.save.empty()) return;
  if (static_cast<double>(now_ns() - last_save_ns_) < config_.map.save_period_s * 1e9) return;
  // A current map without keyframes (not initialised yet, just reset) waits: saved, it would push
  // the last good file out of PATH.bak.
  if (record_.status.keyframes == 0) return;
  // After a keyframe the next frame runs its local BA (slam.mapping.defer_ba): the save's time,
  // counted in that frame, would come on top of it. The frame after will do.
  if (pipeline_.keyframe_inserted()) return;
  (void)map_file(true, config_.map.save);  // a failure is logged and counted; tried again a period later
}

void FrameLoop::drain_recorder() {
  for (const RecorderEvent& e : recorder_->take_events()) log_message(e.level, "%s", e.message.c_str());
}

void FrameLoop::read_extrinsics() {
  if (config_.daemon.body_frame != "calibration") return;
  Result<ale::hal::CameraCalibration> calibration = camera_->calibration();
  T_bc_ = calibration.ok() ? rigid_from_row_major(calibration->T_BS) : std::nullopt;
  if (!T_bc_)
    log_message(LogLevel::kWarning, "daemon.body_frame = calibration, but %s: %s; publishing camera poses only",
                camera_->describe().c_str(),
                calibration.ok() ? "its T_BS is not a rigid transform" : calibration.status().message().c_str());
}

Status FrameLoop::camera_lost(const Status& why) {
  if (!deps_.reopen_camera) return why;
  return reconnect(why);
}

Status FrameLoop::process(const ale::hal::Frame& frame, Status& released) {
  const auto t0 = std::chrono::steady_clock::now();
  add_odometry(deps_.replay_odometry.due(frame.timestamp_ns));
  const Status processed = pipeline_.process(frame, record_);
  released = camera_->release(frame);
  // A buffer we cannot give back would starve the camera; a camera that went away meanwhile
  // (kUnavailable) is reopened by the caller, and this frame still counts.
  if (!released.ok() && released.code() != StatusCode::kUnavailable) return released;
  if (processed.code() == StatusCode::kFrameRejected) {
    // A frame the pipeline cannot take (another size, time going back): counted and skipped,
    // the map kept. Nothing is published for it.
    ++summary_.frames_skipped;
    log_message(LogLevel::kWarning, "frame skipped: %s", processed.message().c_str());
    return {};
  }
  ALE_RETURN_IF_ERROR(processed);
  ++summary_.frames;
  apply_body_frame(T_bc_, record_.pose);
  apply_motion(previous_pose_, record_.pose);
  previous_pose_ = record_.pose;
  ale::hal::StatusReport& status = record_.status;  // made by the pipeline; published as it is
  const ale::hal::CameraStats camera_stats = camera_->stats();
  status.add_pool("camera_buffers", camera_stats.buffers_high_water, camera_stats.buffers);
  // The frame waited for the map file work done since the previous frame: its time counts it.
  const std::int64_t frame_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - t0).count() +
      std::max<std::int64_t>(map_file_ns_, 0);
  (map_file_ns_ >= 0 ? summary_.frames_after_map_file : summary_.other_frames).add(frame_ns);
  map_file_ns_ = -1;
  status.frame_time_ms = static_cast<float>(static_cast<double>(frame_ns) / 1e6);
  summary_.frame_time_ms.add(static_cast<double>(status.frame_time_ms));
  if (has_pose(record_.pose.state)) ++summary_.tracked;
  summary_.keyframes = status.keyframes;
  summary_.landmarks = status.map_points;
  summary_.resets = record_.resets;
  summary_.relocalisations = status.relocalisations;
  summary_.loops_closed = status.loops_closed;
  summary_.loops_refused = status.loops_refused;
  summary_.merges = status.merges;
  summary_.merges_refused = status.merges_refused;
  count(deps_.sink.publish(record_.pose));
  publish_status();
  count(log_.append(frame_log_row(record_)));
  count(trajectory_.append(record_));
  show(indicators_.on_frame(status.state, status.brightness, frame.timestamp_ns));
  if (deps_.on_frame) deps_.on_frame(summary_, record_);
  return {};
}

Status FrameLoop::run() {
  const bool final_poses = !config_.daemon.trajectory.empty() && config_.daemon.trajectory_poses == "final";
  pipeline_.record_trajectory(final_poses);
  ALE_RETURN_IF_ERROR(pipeline_.configure(config_, deps_.calibration));
  if (!config_.daemon.frame_log.empty()) ALE_RETURN_IF_ERROR(log_.open(config_.daemon.frame_log));
  if (!config_.daemon.trajectory.empty()) ALE_RETURN_IF_ERROR(trajectory_.open(config_.daemon.trajectory, final_poses));
  ALE_RETURN_IF_ERROR(camera_->start());
  read_extrinsics();
  start_recorder();
  last_frame_ns_ = last_save_ns_ = now_ns();
  int consecutive_errors = 0;
  Status result;
  while (config_.daemon.max_frames == 0 || summary_.frames < static_cast<std::uint64_t>(config_.daemon.max_frames)) {
    const Wake wake = wait_for_frame(config_.camera.acquire_timeout_ms);
    if (wake == Wake::kStop) {
      summary_.stopped_by_signal = true;
      break;
    }
    ale::hal::Frame frame;
    Status got = wake == Wake::kTimeout
                     ? Status(StatusCode::kTimeout, "no frame from " + camera_->describe() + " in " +
                                                        std::to_string(config_.camera.acquire_timeout_ms) + " ms")
                     : camera_->acquire(frame, camera_->poll_fd() >= 0 ? 0 : config_.camera.acquire_timeout_ms);
    if (got.code() == StatusCode::kEndOfStream) {
      summary_.end_of_stream = true;
      break;
    }
    if (!got.ok()) {
      ++summary_.frame_errors;
      log_message(LogLevel::kWarning, "frame error: %s", got.to_string().c_str());
      const bool gone =
          got.code() == StatusCode::kUnavailable || ++consecutive_errors >= config_.camera.max_consecutive_errors;
      if (!gone) {
        if (got.code() == StatusCode::kTimeout) set_camera_state(CameraState::kTimeout);
        continue;
      }
      consecutive_errors = 0;
      result = camera_lost(got);
      if (!result.ok() || summary_.stopped_by_signal) break;
      continue;
    }
    consecutive_errors = 0;
    last_frame_ns_ = now_ns();
    set_camera_state(CameraState::kStreaming);
    if (recorder_) recorder_->submit(frame);  // every frame the camera delivers, processed or not
    Status released;
    if (control_.paused) {
      map_file_ns_ = -1;  // a frame released unprocessed took the delay
      ++summary_.frames_skipped;
      record_.status.timestamp_ns = frame.timestamp_ns;
      released = camera_->release(frame);
      publish_status();
    } else if (!selector_.take(frame.timestamp_ns)) {
      map_file_ns_ = -1;
      ++summary_.frames_skipped;  // counted in the next status; no message of its own
      released = camera_->release(frame);
    } else {
      result = process(frame, released);
      if (!result.ok()) break;
      save_when_due();  // between this frame and the next, which it delays
    }
    if (!released.ok()) {
      result = released.code() == StatusCode::kUnavailable ? camera_lost(released) : released;
      if (!result.ok() || summary_.stopped_by_signal) break;
    }
  }
  if (recorder_) {
    recorder_->finish();  // what is queued is written, so the last status has the final counts
    drain_recorder();
    summary_.recorder = recorder_->stats();
  }
  // The end of the run (SIGTERM, SIGINT, the replay's end, max_frames): the map is saved when
  // map.save names a file; a failure is logged and fails the run, the previous file kept.
  if (!config_.map.save.empty()) {
    Result<MapFileDone> saved = map_file(true, config_.map.save);
    if (!saved.ok() && saved.status().code() != StatusCode::kUnavailable && result.ok()) result = saved.status();
  }
  // SIGTERM / SIGINT: the controller's last word from the daemon. With a recorder, the last
  // status also carries its final counts: its thread may still have been writing when the last
  // frame's status went out.
  if (summary_.stopped_by_signal || recorder_) publish_status();
  show(indicators_.off());
  if (camera_ != nullptr) {
    Status stopped = camera_->stop();
    if (result.ok() && !stopped.ok()) result = stopped;
  }
  for (Status closed : {log_.close(), trajectory_.finish(pipeline_.resolve_trajectory())}) {
    if (result.ok() && !closed.ok()) result = closed;
  }
  return result;  // the caller reports it
}

}  // namespace

void FrameTimeHistogram::add(double ms) {
  int bin;
  if (!(ms >= 0.0)) bin = 0;
  else if (ms < 100.0) bin = static_cast<int>(ms * 100.0);
  else if (ms < 10000.0) bin = kFine + static_cast<int>(ms - 100.0);
  else bin = kFine + kCoarse;
  ++bins_[static_cast<std::size_t>(std::min(bin, kFine + kCoarse))];
  ++count_;
}

double FrameTimeHistogram::quantile(double q) const {
  if (count_ == 0) return 0.0;
  // the rank of the quantile, 1-based, as in "the k-th smallest time"
  const std::uint64_t rank = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(std::ceil(q * static_cast<double>(count_))));
  std::uint64_t seen = 0;
  for (std::size_t b = 0; b < bins_.size(); ++b) {
    seen += bins_[b];
    if (seen < rank) continue;
    const int i = static_cast<int>(b);
    if (i < kFine) return (i + 1) * 0.01;
    if (i < kFine + kCoarse) return 100.0 + (i - kFine + 1);
    return 10000.0;
  }
  return 10000.0;
}

Status run_frame_loop(const DaemonConfig& config, LoopDeps deps, RunSummary& summary) {
  return FrameLoop(config, deps, summary).run();
}

}  // namespace ale::app
