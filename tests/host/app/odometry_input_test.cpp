// Wheel odometry into the daemon: where samples come from (a dataset, LCM), the camera's place on
// the base, the replay's samples in time with its frames, and what the status counts.
#include "app/daemon/odometry_input.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <lcm/lcm-cpp.hpp>

#include "ale_lcm/odometry_t.hpp"
#include "ale_lcm/status_t.hpp"
#include "app/daemon/frame_loop.h"
#include "app/lcm_pose_sink.h"
#include "hal/fake/fake_camera.h"
#include "tests/host/app/loop_fixtures.h"
#include "tests/host/support/test_data.h"

namespace ale::app {
namespace {

using test::frames;
using test::test_lens;

constexpr std::int64_t kMs = 1000000;

// The camera 0.1 m ahead of the base's centre and 0.08 m up, looking forward.
constexpr std::array<double, 16> kMount = {0, 0, 1, 0.1, -1, 0, 0, 0, 0, -1, 0, 0.08, 0, 0, 0, 1};
constexpr const char* kMountText = "0 0 1 0.1, -1 0 0 0, 0 -1 0 0.08, 0 0 0 1";

replay::OdometryTrack track(int rows, std::optional<std::array<double, 16>> T_BC = kMount) {
  replay::OdometryTrack t;
  t.list_file = "/data/mav0/odometry0/data.csv";
  t.sensor_yaml = "/data/mav0/odometry0/sensor.yaml";
  for (int i = 0; i < rows; ++i) {
    replay::OdometryRow r;
    r.timestamp_ns = 20 * kMs * i;
    r.x_m = 0.004 * i;
    t.rows.push_back(r);
  }
  t.T_BC = T_BC;
  return t;
}

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

TEST(OdometryInputTest, ADatasetsSamplesWithItsMounting) {
  DaemonConfig config;
  config.odometry.clock_offset_ms = -2.5;
  OdometryPlan plan;
  ASSERT_TRUE(resolve_odometry(config, track(5), plan).ok());
  ASSERT_EQ(plan.replay.size(), 5u);
  EXPECT_EQ(plan.replay[3].t_ns, 60 * kMs);
  EXPECT_EQ(plan.replay[3].sequence, 3u);
  EXPECT_DOUBLE_EQ(plan.replay[3].x_m, 0.012);
  EXPECT_TRUE(plan.lcm_channel.empty()) << "a dataset's own odometry: LCM is not read";
  EXPECT_EQ(config.slam.odometry.clock_offset_ns, -2500000);
  const geometry::SE3& T = config.slam.odometry.T_bc;
  EXPECT_NEAR(T.translation().x(), 0.1, 1e-12);
  EXPECT_NEAR(T.translation().z(), 0.08, 1e-12);
  // The camera's optical axis (z) is the base's forward (x).
  EXPECT_NEAR((T.so3() * geometry::Vec3(0, 0, 1)).x(), 1.0, 1e-12);
  EXPECT_TRUE(contains(plan.note, "sensor.yaml")) << plan.note;
  // For the recorder: the numbers as given, and the dataset's rate.
  EXPECT_EQ(plan.T_bc, kMount);
  EXPECT_EQ(plan.rate_hz, 0.0);
  replay::OdometryTrack at_50 = track(5);
  at_50.rate_hz = 50;
  ASSERT_TRUE(resolve_odometry(config, at_50, plan).ok());
  EXPECT_EQ(plan.rate_hz, 50.0);

  // odometry.T_bc wins over the dataset's.
  config.odometry.T_bc = "1 0 0 0.5  0 1 0 0  0 0 1 0  0 0 0 1";
  ASSERT_TRUE(resolve_odometry(config, track(5), plan).ok());
  EXPECT_NEAR(config.slam.odometry.T_bc.translation().x(), 0.5, 1e-12);
  EXPECT_TRUE(contains(plan.note, "odometry.T_bc")) << plan.note;
  EXPECT_EQ(plan.T_bc, (std::array<double, 16>{1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}));
}

TEST(OdometryInputTest, ADatasetWithoutMountingOrWithABadOneIsRefusedByName) {
  DaemonConfig config;
  OdometryPlan plan;
  Status s = resolve_odometry(config, track(5, std::nullopt), plan);
  EXPECT_EQ(s.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(contains(s.message(), "/data/mav0/odometry0/sensor.yaml: no T_BC")) << s.message();
  EXPECT_TRUE(contains(s.message(), "odometry.T_bc")) << s.message();
  std::array<double, 16> sheared = kMount;
  sheared[1] = 0.5;
  s = resolve_odometry(config, track(5, sheared), plan);
  EXPECT_TRUE(contains(s.message(), "sensor.yaml: T_BC is not a rigid transform")) << s.message();
  // Off: neither matters.
  config.odometry.enabled = false;
  ASSERT_TRUE(resolve_odometry(config, track(5, std::nullopt), plan).ok());
  EXPECT_TRUE(plan.replay.empty());
  EXPECT_TRUE(plan.lcm_channel.empty());
  EXPECT_FALSE(plan.T_bc.has_value()) << "no source: nothing for the recorder";
}

TEST(OdometryInputTest, LcmNeedsTheMounting) {
  DaemonConfig config;
  OdometryPlan plan;
  ASSERT_TRUE(resolve_odometry(config, std::nullopt, plan).ok());
  EXPECT_TRUE(plan.lcm_channel.empty());
  EXPECT_FALSE(plan.T_bc.has_value());
  EXPECT_TRUE(contains(plan.note, "odometry.T_bc is not set")) << plan.note;
  config.odometry.T_bc = kMountText;
  ASSERT_TRUE(resolve_odometry(config, track(0), plan).ok()) << "an empty data.csv: LCM instead";
  EXPECT_EQ(plan.lcm_channel, "ODOMETRY");
  EXPECT_EQ(plan.T_bc, kMount);
  EXPECT_EQ(plan.rate_hz, 0.0) << "LCM's rate is not known";
  config.odometry.channel = "";
  ASSERT_TRUE(resolve_odometry(config, std::nullopt, plan).ok());
  EXPECT_TRUE(plan.lcm_channel.empty());
  EXPECT_FALSE(plan.T_bc.has_value());
}

TEST(OdometryInputTest, TbcKeyIsCheckedWithTheConfiguration) {
  DaemonConfig config;
  EXPECT_TRUE(parse_config(std::string("[odometry]\nT_bc = ") + kMountText + "\n", "test", config).ok());
  const struct {
    const char* value;
    const char* what;
  } cases[] = {
      {"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0", "expected 16 numbers (4x4 row-major), found 15"},
      {"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 one", "'one' is not a number"},
      {"1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 nan", "'nan' is not a number"},
      {"2 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1", "not a rigid transform"},
      {"1 0 0 0 0 1 0 0 0 0 1 0 0 0 1 1", "not a rigid transform"},
      {"-1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1", "not a rigid transform"},  // a reflection
  };
  for (const auto& c : cases) {
    const Status s = parse_config(std::string("[odometry]\nT_bc = \"") + c.value + "\"\n", "test", config);
    EXPECT_EQ(s.code(), StatusCode::kInvalidArgument) << c.value;
    EXPECT_TRUE(contains(s.message(), std::string("odometry.T_bc: ") + c.what)) << s.message();
  }
  const Status s = parse_config("[slam.odometry]\nmax_speed_mps = 0\n", "test", config);
  EXPECT_TRUE(contains(s.message(), "slam.odometry.max_speed_mps")) << s.message();
  ASSERT_TRUE(parse_config("[slam.odometry]\ncapacity = 64\n", "test", config).ok());
  EXPECT_EQ(config.slam.odometry.capacity, 64);
}

TEST(OdometryInputTest, ReplayHandsOverInOrderUpToTheLookahead) {
  DaemonConfig config;
  OdometryPlan plan;
  ASSERT_TRUE(resolve_odometry(config, track(10), plan).ok());  // every 20 ms from 0
  // MCU time + 5 ms = camera time; 20 ms lookahead.
  ReplayOdometry odometry(plan.replay, 5 * kMs, 20 * kMs);
  EXPECT_TRUE(odometry.due(-30 * kMs).empty());
  std::vector<slam::OdometrySample> d = odometry.due(0);  // camera 5, 25 ms <= 20: only the first
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].sequence, 0u);
  d = odometry.due(45 * kMs);  // up to camera 65 ms: MCU 20, 40, 60
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[0].sequence, 1u);
  EXPECT_EQ(d[2].sequence, 3u);
  EXPECT_TRUE(odometry.due(45 * kMs).empty()) << "each sample once";
  EXPECT_EQ(odometry.due(1000 * kMs).size(), 6u);
  EXPECT_EQ(odometry.handed_over(), 10u);
}

// Through the frame loop: before each frame the samples due are handed to the SLAM core; the one
// that is not finite and the one that jumps are refused, and every status counts them so far.
TEST(OdometryInputTest, TheLoopFeedsAReplaysSamplesAndTheStatusCountsThem) {
  hal::FakeCamera::Options o;
  o.period_ns = 50 * kMs;
  hal::FakeCamera cam(frames(4), o);  // frames at 0, 50, 100, 150 ms
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  OdometryPlan plan;
  replay::OdometryTrack t = track(12);  // every 20 ms from 0 to 220 ms
  t.rows[3].theta_rad = std::numeric_limits<double>::quiet_NaN();  // 60 ms
  t.rows[6].x_m = 3.0;                                              // 120 ms: 3 m in 20 ms
  ASSERT_TRUE(resolve_odometry(config, t, plan).ok());
  LoopDeps deps{cam, sink, gpio};
  deps.calibration = test_lens();
  deps.replay_odometry = ReplayOdometry(plan.replay, 0, 20 * kMs);
  RunSummary summary;
  ASSERT_TRUE(run_frame_loop(config, deps, summary).ok());
  ASSERT_EQ(sink.reports.size(), 4u);
  // Due by frame i: MCU time <= 50 i + 20 ms, i.e. 2, 4, 7, 9 samples.
  const std::uint64_t due[] = {2, 4, 7, 9};
  const std::uint64_t refused[] = {0, 1, 2, 2};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(sink.reports[i].odometry_accepted + sink.reports[i].odometry_refused, due[i]) << i;
    EXPECT_EQ(sink.reports[i].odometry_refused, refused[i]) << i;
  }
  EXPECT_EQ(summary.odometry_accepted, 7u);
  EXPECT_EQ(summary.odometry_refused, 2u);
}

// With recorder.dir the loop records every sample it hands over, as received: the refused ones
// too, in order, in the sequence of its frames, with the T_bc and rate it was given.
TEST(OdometryInputTest, TheLoopRecordsTheSamplesItHandsOver) {
  hal::FakeCamera::Options o;
  o.period_ns = 50 * kMs;
  hal::FakeCamera cam(frames(4), o);
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  DaemonConfig config;
  config.recorder.dir = test::make_temp_dir("loop-odometry-recorder");
  OdometryPlan plan;
  replay::OdometryTrack t = track(12);
  t.rows[3].theta_rad = std::numeric_limits<double>::quiet_NaN();
  t.rows[6].x_m = 3.0;
  t.rate_hz = 50;
  ASSERT_TRUE(resolve_odometry(config, t, plan).ok());
  LoopDeps deps{cam, sink, gpio};
  deps.calibration = test_lens();
  deps.replay_odometry = ReplayOdometry(plan.replay, 0, 20 * kMs);
  deps.odometry_sensor = OdometrySensor{*plan.T_bc, plan.rate_hz};
  RunSummary summary;
  ASSERT_TRUE(run_frame_loop(config, deps, summary).ok());
  EXPECT_EQ(summary.odometry_refused, 2u);
  EXPECT_EQ(summary.recorder.frames_recorded, 4u);
  EXPECT_EQ(summary.recorder.odometry_recorded, 9u) << "the samples due by the last frame";
  EXPECT_EQ(summary.recorder.odometry_not_recorded, 0u);
  Result<replay::Dataset> ds = replay::open_dataset(summary.recorder.sequence);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  ASSERT_TRUE(ds->odometry.has_value());
  ASSERT_EQ(ds->odometry->rows.size(), 9u);
  for (std::size_t i = 0; i < 9; ++i) {
    EXPECT_EQ(ds->odometry->rows[i].timestamp_ns, t.rows[i].timestamp_ns) << i;
    EXPECT_EQ(ds->odometry->rows[i].x_m, t.rows[i].x_m) << i;
  }
  EXPECT_TRUE(std::isnan(ds->odometry->rows[3].theta_rad));
  EXPECT_EQ(ds->odometry->T_BC, kMount);
  EXPECT_EQ(ds->odometry->rate_hz, 50.0);
}

struct StatusReceiver {
  std::vector<ale_lcm::status_t> statuses;
  static void on_status(const lcm::ReceiveBuffer*, const std::string&, const ale_lcm::status_t* m,
                        StatusReceiver* self) {
    self->statuses.push_back(*m);
  }
};

ale_lcm::odometry_t message(std::int64_t t_ns, std::int64_t sequence, double x) {
  ale_lcm::odometry_t m{};
  m.timestamp_ns = t_ns;
  m.sequence = sequence;
  m.x = x;
  m.y = -0.5;
  m.theta = 0.25;
  m.gyro_z = 0.125;
  m.v_left = 0.2;
  m.v_right = 0.3;
  m.flags = ale_lcm::odometry_t::HAS_GYRO;
  return m;
}

// memq:// keeps everything in the process (nothing on the network).
TEST(OdometryInputTest, LcmSamplesAreDecodedInArrivalOrder) {
  auto sink = LcmPoseSink::open("memq://", LcmChannels{});
  ASSERT_TRUE(sink.ok()) << sink.status().to_string();
  ASSERT_TRUE((*sink)->subscribe_odometry("ODOMETRY").ok());
  for (int i : {0, 1}) {
    const ale_lcm::odometry_t m = message(1000 + i, 7 + i, 0.5 * i);
    ASSERT_EQ((*sink)->lcm().publish("ODOMETRY", &m), 0);
  }
  const char junk[] = "not odometry";
  ASSERT_EQ((*sink)->lcm().publish("ODOMETRY", junk, sizeof junk), 0);
  std::vector<hal::Command> commands;
  ASSERT_TRUE((*sink)->receive(commands).ok());
  EXPECT_TRUE(commands.empty());
  std::vector<slam::OdometrySample> got;
  EXPECT_EQ((*sink)->take_odometry(got), 1u) << "one message did not decode";
  ASSERT_EQ(got.size(), 2u);
  EXPECT_EQ(got[0].t_ns, 1000);
  EXPECT_EQ(got[1].sequence, 8u);
  EXPECT_EQ(got[1].x_m, 0.5);
  EXPECT_EQ(got[1].y_m, -0.5);
  EXPECT_EQ(got[1].theta_rad, 0.25);
  EXPECT_TRUE(got[1].has_gyro);
  EXPECT_EQ(got[1].gyro_z_rps, 0.125);
  EXPECT_FALSE(got[1].has_wheels);
  got.clear();
  EXPECT_EQ((*sink)->take_odometry(got), 0u);
  EXPECT_TRUE(got.empty());
  // Off again: nothing more is collected.
  ASSERT_TRUE((*sink)->subscribe_odometry("").ok());
  const ale_lcm::odometry_t late = message(2000, 9, 1.0);
  ASSERT_EQ((*sink)->lcm().publish("ODOMETRY", &late), 0);
  ASSERT_TRUE((*sink)->receive(commands).ok());
  (*sink)->take_odometry(got);
  EXPECT_TRUE(got.empty());
}

// The whole way over memq://: odometry_t published on the channel reaches the SLAM core through
// the frame loop, and status_t carries the counts.
TEST(OdometryInputTest, LcmSamplesAreCountedInTheStatus) {
  auto opened = LcmPoseSink::open("memq://", LcmChannels{});
  ASSERT_TRUE(opened.ok()) << opened.status().to_string();
  LcmPoseSink& lcm_sink = **opened;
  ASSERT_TRUE(lcm_sink.subscribe_odometry("ODOMETRY").ok());
  StatusReceiver rx;
  lcm_sink.lcm().subscribeFunction("ALE_STATUS", &StatusReceiver::on_status, &rx);
  for (int i = 0; i < 5; ++i) {
    ale_lcm::odometry_t m = message(20 * kMs * i, i, 0.004 * i);
    if (i == 2) m.x = std::numeric_limits<double>::infinity();
    ASSERT_EQ(lcm_sink.lcm().publish("ODOMETRY", &m), 0);
  }
  const char junk[] = "not odometry";
  ASSERT_EQ(lcm_sink.lcm().publish("ODOMETRY", junk, sizeof junk), 0);

  hal::FakeCamera::Options o;
  o.period_ns = 50 * kMs;
  hal::FakeCamera cam(frames(3), o);
  hal::NullGpio gpio;
  DaemonConfig config;
  config.odometry.T_bc = kMountText;
  OdometryPlan plan;
  ASSERT_TRUE(resolve_odometry(config, std::nullopt, plan).ok());
  ASSERT_EQ(plan.lcm_channel, "ODOMETRY");
  LoopDeps deps{cam, lcm_sink, gpio, -1, &lcm_sink};
  deps.calibration = test_lens();
  deps.take_odometry = [&lcm_sink](std::vector<slam::OdometrySample>& out) { return lcm_sink.take_odometry(out); };
  RunSummary summary;
  ASSERT_TRUE(run_frame_loop(config, deps, summary).ok());
  while (lcm_sink.lcm().handleTimeout(0) > 0) {
  }
  EXPECT_EQ(summary.odometry_accepted, 4u);
  EXPECT_EQ(summary.odometry_refused, 2u) << "the infinite x and the bytes that are not an odometry_t";
  ASSERT_FALSE(rx.statuses.empty());
  EXPECT_EQ(rx.statuses.back().odometry_accepted, 4);
  EXPECT_EQ(rx.statuses.back().odometry_refused, 2);
}

}  // namespace
}  // namespace ale::app
