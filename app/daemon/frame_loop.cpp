#include "app/daemon/frame_loop.h"

#include "app/daemon/frame_pipeline.h"
#include "app/daemon/trajectory_file.h"

#include <poll.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace ale::app {
namespace {

enum class Wake { kFrame, kStop, kTimeout };

// Waits on the camera's descriptor, the stop descriptor and the auxiliary one together, so a stop
// request is seen at once even while the camera is silent. A camera without a descriptor (a
// replay) does its own waiting in acquire(), and the other descriptors are only peeked at.
Wake wait_for_frame(const LoopDeps& deps, int timeout_ms) {
  pollfd fds[3];
  nfds_t n = 0;
  const int cam_fd = deps.camera.poll_fd();
  fds[n++] = pollfd{deps.stop_fd, POLLIN, 0};
  fds[n++] = pollfd{deps.aux_fd, POLLIN, 0};
  if (cam_fd >= 0) fds[n++] = pollfd{cam_fd, POLLIN, 0};
  const int ready = ::poll(fds, n, cam_fd >= 0 ? timeout_ms : 0);  // negative fds are ignored
  if (ready > 0 && (fds[0].revents & POLLIN) != 0) return Wake::kStop;
  if (ready > 0 && (fds[1].revents & POLLIN) != 0 && deps.on_aux_ready) deps.on_aux_ready();
  if (cam_fd < 0) return Wake::kFrame;
  // Readable, or an error condition that acquire() will turn into a reason.
  if (ready > 0 && fds[2].revents != 0) return Wake::kFrame;
  return ready == 0 ? Wake::kTimeout : Wake::kFrame;
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
  FramePipeline pipeline;
  ALE_RETURN_IF_ERROR(pipeline.configure(config, deps.calibration));
  FrameLogWriter log;
  if (!config.daemon.frame_log.empty()) ALE_RETURN_IF_ERROR(log.open(config.daemon.frame_log));
  TrajectoryFile trajectory;
  if (!config.daemon.trajectory.empty()) ALE_RETURN_IF_ERROR(trajectory.open(config.daemon.trajectory));
  ALE_RETURN_IF_ERROR(deps.camera.start());
  // The status LED is on while the loop runs.
  if (Status s = deps.gpio.set(ale::hal::GpioLine::kStatusLed, true); !s.ok() && s.code() != StatusCode::kUnsupported)
    std::fprintf(stderr, "ale-slamd: warning: %s\n", s.to_string().c_str());
  int consecutive_errors = 0;
  Status result;
  while (config.daemon.max_frames == 0 || summary.frames < static_cast<std::uint64_t>(config.daemon.max_frames)) {
    const Wake wake = wait_for_frame(deps, config.camera.acquire_timeout_ms);
    if (wake == Wake::kStop) {
      summary.stopped_by_signal = true;
      break;
    }
    ale::hal::Frame frame;
    Status got = wake == Wake::kTimeout
                     ? Status(StatusCode::kTimeout, "no frame from " + deps.camera.describe() + " in " +
                                                        std::to_string(config.camera.acquire_timeout_ms) + " ms")
                     : deps.camera.acquire(frame, deps.camera.poll_fd() >= 0 ? 0 : config.camera.acquire_timeout_ms);
    if (got.code() == StatusCode::kEndOfStream) {
      summary.end_of_stream = true;
      break;
    }
    if (!got.ok()) {
      ++summary.frame_errors;
      std::fprintf(stderr, "ale-slamd: frame error: %s\n", got.to_string().c_str());
      if (got.code() == StatusCode::kUnavailable || ++consecutive_errors >= config.camera.max_consecutive_errors) {
        result = got;
        break;
      }
      continue;
    }
    consecutive_errors = 0;
    const auto t0 = std::chrono::steady_clock::now();
    FrameRecord record;
    const Status processed = pipeline.process(frame, record);
    if (Status s = deps.camera.release(frame); !s.ok()) {
      result = s;  // a buffer we cannot give back would starve the camera
      break;
    }
    if (processed.code() == StatusCode::kInvalidArgument) {
      // A frame the pipeline cannot take (another size, time going back): counted and skipped,
      // the map kept. Nothing is published for it.
      ++summary.frames_skipped;
      std::fprintf(stderr, "ale-slamd: frame skipped: %s\n", processed.message().c_str());
      continue;
    }
    if (!processed.ok()) {
      result = processed;
      break;
    }
    record.status.frame_time_ms =
        std::chrono::duration<float, std::milli>(std::chrono::steady_clock::now() - t0).count();
    record.status.frames_dropped = deps.camera.stats().dropped;
    ++summary.frames;
    summary.frame_time_ms.add(static_cast<double>(record.status.frame_time_ms));
    if (record.pose.state == TrackingState::kTracking) ++summary.tracked;
    summary.keyframes = record.keyframes;
    summary.landmarks = record.landmarks;
    summary.resets = record.resets;
    for (Status s : {deps.sink.publish(record.pose), deps.sink.publish(record.status), log.append(frame_log_row(record)),
                     trajectory.append(record)}) {
      if (!s.ok()) {
        ++summary.publish_errors;
        std::fprintf(stderr, "ale-slamd: publish error: %s\n", s.to_string().c_str());
      }
    }
    if (deps.on_frame) deps.on_frame(summary, record);
  }
  (void)deps.gpio.set(ale::hal::GpioLine::kStatusLed, false);
  Status stopped = deps.camera.stop();
  if (result.ok() && !stopped.ok()) result = stopped;
  for (Status closed : {log.close(), trajectory.close()}) {
    if (result.ok() && !closed.ok()) result = closed;
  }
  return result;
}

}  // namespace ale::app
