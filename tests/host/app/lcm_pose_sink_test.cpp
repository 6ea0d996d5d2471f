#include "app/lcm_pose_sink.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "ale_lcm/command_reply_t.hpp"
#include "ale_lcm/command_t.hpp"
#include "ale_lcm/pose_t.hpp"
#include "ale_lcm/status_t.hpp"

namespace ale::app {
namespace {

// Subscribed with subscribeFunction (a plain function and a context pointer), not with a member
// function: LCM's member-function subscription calls `(subs->handler->*subs->handlerMethod)(...)`,
// and GCC 12 miscompiles exactly that form (the object of a pointer-to-member call read through a
// polymorphic object) under -fsanitize=vptr: one branch of the virtual/non-virtual dispatch uses a
// register it never loaded, so the handler gets a garbage `this` (the host-asan crash in LCM's
// dispatch). A 15-line program without LCM reproduces it; the plain build is unaffected.
struct Receiver {
  std::vector<ale_lcm::pose_t> poses;
  std::vector<ale_lcm::status_t> statuses;
  std::vector<ale_lcm::command_reply_t> replies;
  static void on_reply(const lcm::ReceiveBuffer*, const std::string&, const ale_lcm::command_reply_t* m, Receiver* self) {
    self->replies.push_back(*m);
  }
  static void on_pose(const lcm::ReceiveBuffer*, const std::string&, const ale_lcm::pose_t* m, Receiver* self) {
    self->poses.push_back(*m);
  }
  static void on_status(const lcm::ReceiveBuffer*, const std::string&, const ale_lcm::status_t* m, Receiver* self) {
    self->statuses.push_back(*m);
  }
};

// memq:// keeps everything inside the process: nothing goes on the network.
TEST(LcmPoseSinkTest, RoundTripsPoseAndStatusInProcess) {
  auto sink = LcmPoseSink::open("memq://", LcmChannels{});
  ASSERT_TRUE(sink.ok()) << sink.status().to_string();
  Receiver rx;
  (*sink)->lcm().subscribeFunction("ALE_POSE", &Receiver::on_pose, &rx);
  (*sink)->lcm().subscribeFunction("ALE_STATUS", &Receiver::on_status, &rx);

  hal::PoseEstimate p;
  p.timestamp_ns = 1403715273262142976LL;
  p.frame_sequence = 7;
  p.state = TrackingState::kTracking;
  p.p_wc = {1.5, -2.0, 0.25};
  p.q_wc = {0.5, 0.5, -0.5, 0.5};
  p.body_valid = true;
  p.p_bc = {0.1, 0.2, 0.3};
  p.q_bc = {0, 1, 0, 0};
  p.p_wb = {4, 5, 6};
  p.q_wb = {0, 0, 1, 0};
  p.velocity_w_mps = {0.25, 0, -0.125};
  p.angular_velocity_w_radps = {0, 0.5, 0};
  p.inliers = 142;
  p.map_id = 3;
  p.relocalized = true;
  p.odometry_only = true;
  p.position_sigma_m = 0.0625;
  ASSERT_TRUE((*sink)->publish(p).ok());
  hal::StatusReport r;
  r.timestamp_ns = p.timestamp_ns;
  r.brightness = BrightnessClass::kDark;
  r.features = 987;
  r.keyframes = 12;
  r.map_points = 3400;
  r.map_id = 3;
  r.relocalisations = 2;
  r.odometry_accepted = 1234;
  r.odometry_refused = 5;
  r.map_scale = 1.015625;
  r.odometry_disagreements = 9;
  r.map_saves = 11;
  r.map_save_failures = 2;
  r.last_save_ms = 7.25f;
  r.place_ms = 1.75f;
  r.loops_closed = 4;
  r.loops_refused = 1;
  r.loop_ms = 38.5f;
  r.merges = 3;
  r.merges_refused = 2;
  r.add_pool("frames", 3, 4);
  r.add_pool("keyframes", 12, 256);
  r.camera_state = hal::CameraState::kReconnecting;
  r.camera_reconnects = 2;
  r.frames_dropped = 5;
  r.frames_skipped = 6;
  r.frame_errors = 7;
  r.timings.add("grade", 1500000);
  r.timings.add("pyramid", 250000);
  r.config_generation = 4;
  r.paused = true;
  r.publish_errors = 8;
  r.commands_received = 9;
  r.commands_rejected = 1;
  r.recorder_state = hal::RecorderState::kStopped;
  r.frames_recorded = 41;
  r.frames_not_recorded = 3;
  r.last_error = "camera lost";
  r.message = "ok";
  ASSERT_TRUE((*sink)->publish(r).ok());
  while ((*sink)->lcm().handleTimeout(0) > 0) {
  }
  ASSERT_EQ(rx.poses.size(), 1u);
  EXPECT_EQ(rx.poses[0].timestamp_ns, p.timestamp_ns);
  EXPECT_EQ(rx.poses[0].frame_sequence, 7);
  EXPECT_EQ(rx.poses[0].state, static_cast<int8_t>(TrackingState::kTracking));
  EXPECT_DOUBLE_EQ(rx.poses[0].position[1], -2.0);
  EXPECT_DOUBLE_EQ(rx.poses[0].orientation[2], -0.5);
  ASSERT_EQ(rx.statuses.size(), 1u);
  EXPECT_EQ(rx.statuses[0].brightness_class, static_cast<int8_t>(BrightnessClass::kDark));
  EXPECT_EQ(rx.statuses[0].features, 987);
  EXPECT_EQ(rx.statuses[0].message, "ok");

  const ale_lcm::pose_t& m = rx.poses[0];
  EXPECT_TRUE(m.body_valid);
  EXPECT_DOUBLE_EQ(m.T_bc_position[2], 0.3);
  EXPECT_DOUBLE_EQ(m.T_bc_orientation[1], 1.0);
  EXPECT_DOUBLE_EQ(m.body_position[0], 4.0);
  EXPECT_DOUBLE_EQ(m.body_orientation[2], 1.0);
  EXPECT_DOUBLE_EQ(m.velocity_mps[2], -0.125);
  EXPECT_DOUBLE_EQ(m.angular_velocity_radps[1], 0.5);
  EXPECT_EQ(m.inliers, 142);
  EXPECT_EQ(m.map_id, 3);
  EXPECT_TRUE(m.relocalized);
  EXPECT_TRUE(m.odometry_only);
  EXPECT_FLOAT_EQ(m.position_sigma_m, 0.0625f);
  const ale_lcm::status_t& st = rx.statuses[0];
  EXPECT_EQ(st.keyframes, 12);
  EXPECT_EQ(st.map_points, 3400);
  EXPECT_EQ(st.map_id, 3);
  EXPECT_EQ(st.relocalisations, 2);
  EXPECT_EQ(st.odometry_accepted, 1234);
  EXPECT_EQ(st.odometry_refused, 5);
  EXPECT_FLOAT_EQ(st.map_scale, 1.015625f);
  EXPECT_EQ(st.odometry_disagreements, 9);
  EXPECT_EQ(st.map_saves, 11);
  EXPECT_EQ(st.map_save_failures, 2);
  EXPECT_FLOAT_EQ(st.last_save_ms, 7.25f);
  EXPECT_FLOAT_EQ(st.place_ms, 1.75f);
  EXPECT_EQ(st.loops_closed, 4);
  EXPECT_EQ(st.loops_refused, 1);
  EXPECT_FLOAT_EQ(st.loop_ms, 38.5f);
  EXPECT_EQ(st.merges, 3);
  EXPECT_EQ(st.merges_refused, 2);
  ASSERT_EQ(st.pool_count, 2);
  EXPECT_EQ(st.pool_names[1], "keyframes");
  EXPECT_EQ(st.pool_high_water[1], 12);
  EXPECT_EQ(st.pool_capacity[0], 4);
  EXPECT_EQ(st.camera_state, int{ale_lcm::status_t::CAMERA_RECONNECTING});
  EXPECT_EQ(st.camera_reconnects, 2);
  EXPECT_EQ(st.frames_dropped, 5);
  EXPECT_EQ(st.frames_skipped, 6);
  EXPECT_EQ(st.frame_errors, 7);
  ASSERT_EQ(st.stage_count, 2);
  EXPECT_EQ(st.stage_names[0], "grade");
  EXPECT_FLOAT_EQ(st.stage_ms[0], 1.5f);
  EXPECT_FLOAT_EQ(st.stage_ms[1], 0.25f);
  EXPECT_EQ(st.config_generation, 4);
  EXPECT_TRUE(st.paused);
  EXPECT_EQ(st.publish_errors, 8);
  EXPECT_EQ(st.commands_received, 9);
  EXPECT_EQ(st.commands_rejected, 1);
  EXPECT_EQ(st.recorder_state, int{ale_lcm::status_t::RECORDER_STOPPED});
  EXPECT_EQ(st.frames_recorded, 41);
  EXPECT_EQ(st.frames_not_recorded, 3);
  EXPECT_EQ(st.last_error, "camera lost");
}

// The enums of the HAL and the constants of the messages are one set of wire values.
TEST(LcmPoseSinkTest, WireValuesMatchTheMessageConstants) {
  EXPECT_EQ(static_cast<int>(TrackingState::kTracking), int{ale_lcm::pose_t::TRACKING});
  EXPECT_EQ(static_cast<int>(TrackingState::kRelocalized), int{ale_lcm::pose_t::RELOCALIZED});
  EXPECT_EQ(static_cast<int>(hal::CameraState::kGone), int{ale_lcm::status_t::CAMERA_GONE});
  EXPECT_EQ(static_cast<int>(hal::RecorderState::kOff), int{ale_lcm::status_t::RECORDER_OFF});
  EXPECT_EQ(static_cast<int>(hal::RecorderState::kRecording), int{ale_lcm::status_t::RECORDER_RECORDING});
  EXPECT_EQ(static_cast<int>(hal::RecorderState::kStopped), int{ale_lcm::status_t::RECORDER_STOPPED});
  EXPECT_EQ(static_cast<int>(hal::CommandKind::kSetLogLevel), int{ale_lcm::command_t::SET_LOG_LEVEL});
  EXPECT_EQ(static_cast<int>(hal::CommandKind::kPause), int{ale_lcm::command_t::PAUSE});
  EXPECT_EQ(static_cast<int>(hal::CommandKind::kSaveMap), int{ale_lcm::command_t::SAVE_MAP});
  EXPECT_EQ(static_cast<int>(hal::CommandKind::kLoadMap), int{ale_lcm::command_t::LOAD_MAP});
  EXPECT_EQ(static_cast<int>(hal::CommandResult::kNotSupported), int{ale_lcm::command_reply_t::NOT_SUPPORTED});
  EXPECT_EQ(static_cast<int>(hal::CommandResult::kMalformed), int{ale_lcm::command_reply_t::MALFORMED});
}

// lcm-gen's decoder takes a string's length field (big-endian int32 after the 8-byte fingerprint,
// the 8-byte id and the 1-byte kind) on trust when it is 0 or negative: it throws, or (INT32_MIN)
// reads 2 GB past the bytes. Such bytes are a malformed command, not the end of the daemon (found
// by tests/fuzz/command_fuzz.cpp).
TEST(LcmPoseSinkTest, AStringLengthOutOfRangeIsAMalformedCommand) {
  ale_lcm::command_t c;
  c.command_id = 7;
  c.command = ale_lcm::command_t::SET_LOG_LEVEL;
  c.argument = "debug";
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(c.getEncodedSize()));
  ASSERT_EQ(c.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  const hal::Command good = decode_command(bytes.data(), bytes.size(), "ALE_COMMAND");
  ASSERT_FALSE(good.malformed) << good.error;
  EXPECT_EQ(good.argument, "debug");
  constexpr std::size_t kLengthAt = 8 + 8 + 1;
  // 0, -1, INT32_MIN, and 7 (one more than the 6 bytes of "debug\0" there are)
  const std::uint32_t lengths[] = {0u, 0xffffffffu, 0x80000000u, 7u};
  for (const std::uint32_t length : lengths) {
    std::vector<std::uint8_t> bad = bytes;
    for (std::size_t i = 0; i < 4; ++i) bad[kLengthAt + i] = static_cast<std::uint8_t>(length >> (24 - 8 * i));
    const hal::Command got = decode_command(bad.data(), bad.size(), "ALE_COMMAND");
    EXPECT_TRUE(got.malformed) << "length " << length;
    EXPECT_NE(got.error.find("ALE_COMMAND"), std::string::npos) << got.error;
  }
}

TEST(LcmPoseSinkTest, ReceivesCommandsFlagsUndecodableBytesAndReplies) {
  auto sink = LcmPoseSink::open("memq://", LcmChannels{});
  ASSERT_TRUE(sink.ok()) << sink.status().to_string();
  Receiver rx;
  (*sink)->lcm().subscribeFunction("ALE_COMMAND_REPLY", &Receiver::on_reply, &rx);
  ale_lcm::command_t c;
  c.command_id = 41;
  c.command = ale_lcm::command_t::SET_LOG_LEVEL;
  c.argument = "debug";
  ASSERT_EQ((*sink)->lcm().publish("ALE_COMMAND", &c), 0);
  const char junk[] = "not a command";
  ASSERT_EQ((*sink)->lcm().publish("ALE_COMMAND", junk, sizeof junk), 0);
  ale_lcm::pose_t wrong_type{};  // another type's fingerprint
  ASSERT_EQ((*sink)->lcm().publish("ALE_COMMAND", &wrong_type), 0);

  std::vector<hal::Command> got;
  ASSERT_TRUE((*sink)->receive(got).ok());
  ASSERT_EQ(got.size(), 3u);
  EXPECT_FALSE(got[0].malformed);
  EXPECT_EQ(got[0].id, 41);
  EXPECT_EQ(got[0].kind, int{ale_lcm::command_t::SET_LOG_LEVEL});
  EXPECT_EQ(got[0].argument, "debug");
  EXPECT_TRUE(got[1].malformed);
  EXPECT_NE(got[1].error.find("ALE_COMMAND"), std::string::npos) << got[1].error;
  EXPECT_TRUE(got[2].malformed);

  hal::CommandReply r;
  r.id = 41;
  r.kind = c.command;
  r.result = hal::CommandResult::kBadArgument;
  r.message = "why";
  ASSERT_TRUE((*sink)->reply(r).ok());
  while ((*sink)->lcm().handleTimeout(0) > 0) {
  }
  ASSERT_EQ(rx.replies.size(), 1u);
  EXPECT_EQ(rx.replies[0].command_id, 41);
  EXPECT_EQ(rx.replies[0].result, int{ale_lcm::command_reply_t::BAD_ARGUMENT});
  EXPECT_EQ(rx.replies[0].message, "why");
}

TEST(LcmPoseSinkTest, BadUrlIsAClearError) {
  auto sink = LcmPoseSink::open("nosuchprovider://x", LcmChannels{});
  ASSERT_FALSE(sink.ok());
  EXPECT_EQ(sink.status().code(), StatusCode::kUnavailable);
  EXPECT_NE(sink.status().message().find("nosuchprovider://x"), std::string::npos);
}

}  // namespace
}  // namespace ale::app
