// ale-slamd: the vision daemon of the sweeper. Reads frames from the camera (V4L2 on the robot,
// a recorded dataset in a replay), runs the per-frame pipeline, publishes poses and status
// over LCM, drives the status LED.
#include <signal.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "app/config.h"
#include "app/daemon/board.h"
#include "app/daemon/frame_loop.h"
#include "app/daemon/log.h"
#include "app/daemon/odometry_input.h"
#include "app/lcm_pose_sink.h"
#include "app/version.h"
#include "core/base/frame_record.h"

namespace {

void print_help() {
  std::printf(
      "usage: ale-slamd [--config FILE] [--replay DATASET] [--trajectory OUT.tum] [--set KEY=VALUE]...\n"
      "                 [--lcm-url URL] [--max-frames N] [--frame-log FILE.csv] [--verbose]\n"
      "                 [--no-odometry] [--load-map FILE] [--save-map FILE] [--print-config]\n"
      "       ale-slamd --version | --help\n"
      "\n"
      "  --config FILE      configuration file (see docs/configuration.md); defaults otherwise\n"
      "  --replay DATASET   replay a recorded dataset (EuRoC ASL or TUM layout) instead of the camera,\n"
      "                     as fast as the pipeline goes\n"
      "  --trajectory FILE  write one TUM line per frame with a pose (camera in the map frame)\n"
      "  --set KEY=VALUE    set any configuration key (after --config), e.g. --set enhancement.mode=off\n"
      "  --lcm-url URL      LCM provider (default udpm://239.255.76.67:7667?ttl=0; memq:// for tests)\n"
      "  --max-frames N     stop after N frames\n"
      "  --frame-log FILE   write one CSV line per frame (tracking, enhancement, map, stage times)\n"
      "  --verbose          one line per frame on stderr: state, matches, inliers, map, why no pose\n"
      "  --no-odometry      hand no wheel odometry to the SLAM (odometry.enabled = false)\n"
      "  --load-map FILE    start from a saved map: relocalise in it (map.load)\n"
      "  --save-map FILE    save the map at the end of the run (map.save)\n"
      "  --print-config     print the configuration in effect (every key) and exit\n"
      "  --print-config-reference  print the key reference of docs/configuration.md and exit\n"
      "\n"
      "Publishes ale_lcm.pose_t on ALE_POSE and ale_lcm.status_t on ALE_STATUS, takes ale_lcm.command_t\n"
      "on ALE_COMMAND and answers each with ale_lcm.command_reply_t on ALE_COMMAND_REPLY ([lcm] keys).\n"
      "Exit status: 0 on a clean stop (signal or end of replay), 1 on a runtime error, 2 on bad usage.\n");
}

}  // namespace

int main(int argc, char** argv) {
  using namespace ale::app;
  const std::int64_t start_ns = ale::steady_clock_ns();
  DaemonConfig config;
  std::string config_path, replay, lcm_url, max_frames, frame_log, trajectory, load_map, save_map;
  std::string sets;  // --set KEY=VALUE lines, in the config file's syntax
  bool print = false;
  bool verbose = false;
  bool no_odometry = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](std::string& out) {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "ale-slamd: %s needs a value\n", a.c_str());
        return false;
      }
      out = argv[++i];
      return true;
    };
    if (a == "--help" || a == "-h") {
      print_help();
      return 0;
    } else if (a == "--version") {
      std::printf("ale-slamd %s (%s)\n", ALE_VERSION, ALE_TARGET_PROCESSOR);
      return 0;
    } else if (a == "--config") {
      if (!value(config_path)) return 2;
    } else if (a == "--replay") {
      if (!value(replay)) return 2;
    } else if (a == "--lcm-url") {
      if (!value(lcm_url)) return 2;
    } else if (a == "--max-frames") {
      if (!value(max_frames)) return 2;
    } else if (a == "--frame-log") {
      if (!value(frame_log)) return 2;
    } else if (a == "--trajectory") {
      if (!value(trajectory)) return 2;
    } else if (a == "--load-map") {
      if (!value(load_map)) return 2;
    } else if (a == "--save-map") {
      if (!value(save_map)) return 2;
    } else if (a == "--set") {
      std::string kv;
      if (!value(kv)) return 2;
      const std::size_t eq = kv.find('=');
      if (eq == std::string::npos || eq == 0 || kv.find_first_of("\n#[") != std::string::npos) {
        std::fprintf(stderr, "ale-slamd: --set wants KEY=VALUE, got '%s'\n", kv.c_str());
        return 2;
      }
      sets += kv.substr(0, eq) + " = " + kv.substr(eq + 1) + "\n";
    } else if (a == "--print-config") {
      print = true;
    } else if (a == "--verbose") {
      verbose = true;
    } else if (a == "--no-odometry") {
      no_odometry = true;
    } else if (a == "--print-config-reference") {
      std::fputs(config_reference_markdown().c_str(), stdout);
      return 0;
    } else {
      std::fprintf(stderr, "ale-slamd: unknown argument '%s' (try --help)\n", a.c_str());
      return 2;
    }
  }
  if (!config_path.empty()) {
    if (ale::Status s = load_config(config_path, config); !s.ok()) {
      std::fprintf(stderr, "ale-slamd: %s\n", s.to_string().c_str());
      return 2;
    }
  }
  // Command-line options override the file; they go through the same validation.
  std::string overrides = sets;  // before any [section] header: full keys
  if (!replay.empty()) overrides += "[camera]\nsource = replay\nreplay_path = " + replay + "\n";
  if (!lcm_url.empty()) overrides += "[lcm]\nurl = " + lcm_url + "\n";
  if (!max_frames.empty()) overrides += "[daemon]\nmax_frames = " + max_frames + "\n";
  if (!frame_log.empty()) overrides += "[daemon]\nframe_log = " + frame_log + "\n";
  if (!trajectory.empty()) overrides += "[daemon]\ntrajectory = " + trajectory + "\n";
  if (no_odometry) overrides += "[odometry]\nenabled = false\n";
  if (!load_map.empty()) overrides += "[map]\nload = " + load_map + "\n";
  if (!save_map.empty()) overrides += "[map]\nsave = " + save_map + "\n";
  if (ale::Status s = parse_config(overrides, "command line", config); !s.ok()) {
    std::fprintf(stderr, "ale-slamd: %s\n", s.to_string().c_str());
    return 2;
  }
  if (print) {
    std::fputs(print_config(config).c_str(), stdout);
    return 0;
  }

  // Signals arrive on a descriptor the loop polls; no work in a handler.
  sigset_t mask;
  sigemptyset(&mask);
  sigaddset(&mask, SIGINT);
  sigaddset(&mask, SIGTERM);
  sigprocmask(SIG_BLOCK, &mask, nullptr);
  const int stop_fd = signalfd(-1, &mask, SFD_CLOEXEC | SFD_NONBLOCK);
  sigset_t hup;
  sigemptyset(&hup);
  sigaddset(&hup, SIGHUP);
  sigprocmask(SIG_BLOCK, &hup, nullptr);
  const int reload_fd = signalfd(-1, &hup, SFD_CLOEXEC | SFD_NONBLOCK);

  if (ale::Status s = configure_log(config.log.level, config.log.target); !s.ok()) {
    std::fprintf(stderr, "ale-slamd: %s\n", s.to_string().c_str());
    return 2;
  }
  Board board;
  if (ale::Status s = build_board(config, board); !s.ok()) {
    std::fprintf(stderr, "ale-slamd: %s\n", s.to_string().c_str());
    return 1;
  }
  auto sink = LcmPoseSink::open(config.lcm.url, LcmChannels{config.lcm.pose_channel, config.lcm.status_channel,
                                                            config.lcm.command_channel, config.lcm.reply_channel});
  if (!sink.ok()) {
    std::fprintf(stderr, "ale-slamd: %s\n", sink.status().to_string().c_str());
    return 1;
  }
  // Where wheel odometry comes from, and the camera's place on the base (config.slam.odometry).
  OdometryPlan odometry;
  if (ale::Status s = resolve_odometry(config, board.odometry, odometry); !s.ok()) {
    std::fprintf(stderr, "ale-slamd: %s\n", s.to_string().c_str());
    return 1;
  }
  if (ale::Status s = (*sink)->subscribe_odometry(odometry.lcm_channel); !s.ok()) {
    std::fprintf(stderr, "ale-slamd: %s\n", s.to_string().c_str());
    return 1;
  }
  std::fprintf(stderr, "ale-slamd %s: camera %s, gpio %s, lcm %s; %s\n", ALE_VERSION, board.camera->describe().c_str(),
               board.gpio->describe().c_str(), config.lcm.url.c_str(), odometry.note.c_str());
  RunSummary summary;
  LcmPoseSink& lcm_sink = **sink;
  LoopDeps deps{*board.camera, lcm_sink, *board.gpio, stop_fd, &lcm_sink};
  deps.calibration = board.calibration;
  deps.replay_odometry = ReplayOdometry(std::move(odometry.replay), config.slam.odometry.clock_offset_ns,
                                        std::llround(config.odometry.lookahead_ms * 1e6));
  if (odometry.T_bc) deps.odometry_sensor = OdometrySensor{*odometry.T_bc, odometry.rate_hz};
  if (!odometry.lcm_channel.empty())
    deps.take_odometry = [&lcm_sink](std::vector<ale::slam::OdometrySample>& out) { return lcm_sink.take_odometry(out); };
  deps.reopen_camera = [&]() -> ale::Result<ale::hal::Camera*> {
    ALE_RETURN_IF_ERROR(reopen_camera(config, board));
    return board.camera.get();
  };
  // SIGHUP: the file again, then the command line over it, as at start.
  deps.reload_fd = reload_fd;
  deps.load_config = [&](DaemonConfig& loaded) -> ale::Status {
    if (!config_path.empty()) ALE_RETURN_IF_ERROR(load_config(config_path, loaded));
    return parse_config(overrides, "command line", loaded);
  };
  deps.apply_config = [&lcm_sink](const DaemonConfig& c) {
    return lcm_sink.set_channels(
        LcmChannels{c.lcm.pose_channel, c.lcm.status_channel, c.lcm.command_channel, c.lcm.reply_channel});
  };
  deps.start_ns = start_ns;
  // On a terminal, a progress line every few seconds; with --verbose a line per frame.
  const bool terminal = ::isatty(STDERR_FILENO) == 1;
  auto last_progress = std::chrono::steady_clock::now();
  if (terminal || verbose) {
    deps.on_frame = [&last_progress, terminal, verbose](const RunSummary& s, const FrameRecord& r) {
      if (verbose) {
        std::fprintf(stderr, "ale-slamd: frame %llu %s features %d matches %d inliers %d keyframes %d points %d%s%s\n",
                     static_cast<unsigned long long>(r.pose.frame_sequence), ale::to_string(r.pose.state),
                     r.status.features, r.matches, r.status.inliers, r.status.keyframes, r.status.map_points,
                     r.status.message.empty() ? "" : ": ", r.status.message.c_str());
      }
      const auto now = std::chrono::steady_clock::now();
      if (!terminal || now - last_progress < std::chrono::seconds(3)) return;
      last_progress = now;
      std::fprintf(stderr, "ale-slamd: %llu frames, %llu tracked, %d keyframes, %d points, %d resets\n",
                   static_cast<unsigned long long>(s.frames), static_cast<unsigned long long>(s.tracked), s.keyframes,
                   s.landmarks, s.resets);
    };
  }
  const ale::Status run = run_frame_loop(config, deps, summary);
  std::fprintf(stderr,
               "ale-slamd: frames %llu tracked %llu keyframes %d points %d resets %d relocalisations %d loops_closed %d loops_refused %d merges %d merges_refused %d frame_ms_median %.2f "
               "frame_ms_p95 %.2f commands %llu rejected %llu camera_reconnects %llu odometry %llu refused %llu; %llu frame "
               "errors, %llu skipped, %llu publish errors%s\n",
               static_cast<unsigned long long>(summary.frames), static_cast<unsigned long long>(summary.tracked),
               summary.keyframes, summary.landmarks, summary.resets, summary.relocalisations,
               summary.loops_closed, summary.loops_refused, summary.merges, summary.merges_refused,
               summary.frame_time_ms.quantile(0.5),
               summary.frame_time_ms.quantile(0.95), static_cast<unsigned long long>(summary.commands),
               static_cast<unsigned long long>(summary.commands_rejected),
               static_cast<unsigned long long>(summary.camera_reconnects),
               static_cast<unsigned long long>(summary.odometry_accepted),
               static_cast<unsigned long long>(summary.odometry_refused),
               static_cast<unsigned long long>(summary.frame_errors),
               static_cast<unsigned long long>(summary.frames_skipped),
               static_cast<unsigned long long>(summary.publish_errors),
               summary.stopped_by_signal ? ", stopped by signal" : (summary.end_of_stream ? ", end of stream" : ""));
  if (summary.map_saves + summary.map_save_failures > 0) {
    // The frames that waited for a map save or load against the others: what a save costs the loop.
    const CostFigure& after = summary.frames_after_map_file;
    const CostFigure& others = summary.other_frames;
    std::fprintf(stderr,
                 "ale-slamd: map saves %llu failed %llu, %.1f ms mean %.1f ms max; frame time of the %llu frames after "
                 "a map file %.1f ms mean %.1f ms max, of the %llu others %.1f ms mean %.1f ms max\n",
                 static_cast<unsigned long long>(summary.map_saves),
                 static_cast<unsigned long long>(summary.map_save_failures), summary.save.mean_ms(),
                 summary.save.max_ms(), static_cast<unsigned long long>(after.count), after.mean_ms(), after.max_ms(),
                 static_cast<unsigned long long>(others.count), others.mean_ms(), others.max_ms());
  }
  if (summary.recorder.state != ale::hal::RecorderState::kOff) {
    const RecorderStats& r = summary.recorder;
    std::fprintf(stderr,
                 "ale-slamd: recorder %s: %llu frames recorded, %llu not recorded, %llu odometry samples recorded, "
                 "%llu not recorded, %.1f MiB in %s, %llu sequences dropped; on the frame loop %.3f ms mean %.3f ms "
                 "max per frame (%llu waits for the writer, %.1f ms mean), writer %.2f ms mean %.2f ms max\n",
                 ale::hal::to_string(r.state), static_cast<unsigned long long>(r.frames_recorded),
                 static_cast<unsigned long long>(r.frames_not_recorded),
                 static_cast<unsigned long long>(r.odometry_recorded),
                 static_cast<unsigned long long>(r.odometry_not_recorded), static_cast<double>(r.bytes) / (1024.0 * 1024.0),
                 config.recorder.dir.c_str(), static_cast<unsigned long long>(r.sequences_dropped), r.submit.mean_ms(),
                 r.submit.max_ms(), static_cast<unsigned long long>(r.waited.count), r.waited.mean_ms(), r.write.mean_ms(),
                 r.write.max_ms());
  }
  if (stop_fd >= 0) ::close(stop_fd);
  if (reload_fd >= 0) ::close(reload_fd);
  if (!run.ok()) {
    std::fprintf(stderr, "ale-slamd: %s\n", run.to_string().c_str());
    return 1;
  }
  return 0;
}
