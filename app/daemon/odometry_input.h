// Wheel odometry into the SLAM core (core/slam/odometry.h): where the daemon's samples come from
// (a replayed dataset's mav0/odometry0/, or ale_lcm.odometry_t over LCM), decided once at start,
// and the replay's samples handed over in time with its frames.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "app/config.h"
#include "core/slam/odometry.h"
#include "hal/replay/dataset.h"

namespace ale::app {

// A dataset's rows as the core takes them; the sequence is the row's index.
std::vector<ale::slam::OdometrySample> odometry_samples(const ale::replay::OdometryTrack& track);
// The other way: a sample as the recorder writes its row (the MCU's sequence has no column).
ale::replay::OdometryRow odometry_row(const ale::slam::OdometrySample& s);

// Where the samples come from.
struct OdometryPlan {
  std::vector<ale::slam::OdometrySample> replay;  // the dataset's samples; empty: none
  std::string lcm_channel;                        // ale_lcm.odometry_t in; empty: none
  std::string note;                               // what was decided and why, for the log
  // With a source: the T_bc in use as given (16 numbers, row-major) and the dataset's rate_hz
  // (0: not known), for the recorder's odometry0/sensor.yaml.
  std::optional<std::array<double, 16>> T_bc;
  double rate_hz = 0.0;
};

// Sets config.slam.odometry's clock offset (odometry.clock_offset_ms) and T_bc (odometry.T_bc,
// else the dataset's T_BC) and decides the source: none when odometry.enabled is false; the
// dataset's samples when it has some (LCM is not read then: two streams would interleave); else
// odometry.channel over LCM, when T_bc is known. kInvalidArgument naming the sensor.yaml for a
// dataset with samples but no T_BC and no odometry.T_bc, or a T_BC that is not rigid.
Status resolve_odometry(DaemonConfig& config, const std::optional<ale::replay::OdometryTrack>& track,
                        OdometryPlan& plan);

// A replay's samples, handed over in order: before a frame, every one not yet handed over whose
// camera time (MCU time + offset) is at most the frame's time + lookahead.
class ReplayOdometry {
 public:
  ReplayOdometry() = default;
  ReplayOdometry(std::vector<ale::slam::OdometrySample> samples, std::int64_t clock_offset_ns,
                 std::int64_t lookahead_ns)
      : samples_(std::move(samples)), clock_offset_ns_(clock_offset_ns), lookahead_ns_(lookahead_ns) {}

  // The samples due before the frame at frame_t_ns (camera time); empty when none.
  std::vector<ale::slam::OdometrySample> due(std::int64_t frame_t_ns);
  std::size_t handed_over() const { return next_; }

 private:
  std::vector<ale::slam::OdometrySample> samples_;
  std::int64_t clock_offset_ns_ = 0;
  std::int64_t lookahead_ns_ = 0;
  std::size_t next_ = 0;
};

}  // namespace ale::app
