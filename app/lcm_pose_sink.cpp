#include "app/lcm_pose_sink.h"

#include <lcm/lcm-cpp.hpp>

#include <cstdint>

#include "app/daemon/log.h"

#include "ale_lcm/command_reply_t.hpp"
#include "ale_lcm/command_t.hpp"
#include "ale_lcm/odometry_t.hpp"
#include "ale_lcm/pose_t.hpp"
#include "ale_lcm/status_t.hpp"

namespace ale::app {
namespace {

template <std::size_t N>
void copy_to(const std::array<double, N>& from, double (&to)[N]) {
  for (std::size_t i = 0; i < N; ++i) to[i] = from[i];
}

}  // namespace

Result<std::unique_ptr<LcmPoseSink>> LcmPoseSink::open(const std::string& url, LcmChannels channels) {
  auto l = std::make_unique<lcm::LCM>(url);
  if (!l->good()) return unavailable("LCM cannot be set up on '" + url + "'");
  std::unique_ptr<LcmPoseSink> sink(new LcmPoseSink(std::move(l), LcmChannels{}));
  sink->channels_.command.clear();
  ALE_RETURN_IF_ERROR(sink->set_channels(std::move(channels)));
  return sink;
}

Status LcmPoseSink::set_channels(LcmChannels channels) {
  if (channels.command != channels_.command) {
    lcm::Subscription* subscription = nullptr;
    if (!channels.command.empty()) {
      subscription = lcm_->subscribeFunction(channels.command, &LcmPoseSink::on_command_of, this);
      if (subscription == nullptr) return unavailable("LCM cannot subscribe to '" + channels.command + "'");
    }
    if (command_subscription_ != nullptr) (void)lcm_->unsubscribe(command_subscription_);
    command_subscription_ = subscription;
  }
  channels_ = std::move(channels);
  return {};
}

LcmPoseSink::LcmPoseSink(std::unique_ptr<lcm::LCM> l, LcmChannels channels)
    : lcm_(std::move(l)), channels_(std::move(channels)) {}

LcmPoseSink::~LcmPoseSink() = default;

Status LcmPoseSink::publish(const ale::hal::PoseEstimate& pose) {
  ale_lcm::pose_t msg;
  msg.timestamp_ns = pose.timestamp_ns;
  msg.frame_sequence = static_cast<int64_t>(pose.frame_sequence);
  msg.state = static_cast<int8_t>(pose.state);
  copy_to(pose.p_wc, msg.position);
  copy_to(pose.q_wc, msg.orientation);
  msg.body_valid = pose.body_valid;
  copy_to(pose.p_bc, msg.T_bc_position);
  copy_to(pose.q_bc, msg.T_bc_orientation);
  copy_to(pose.p_wb, msg.body_position);
  copy_to(pose.q_wb, msg.body_orientation);
  copy_to(pose.velocity_w_mps, msg.velocity_mps);
  copy_to(pose.angular_velocity_w_radps, msg.angular_velocity_radps);
  msg.inliers = pose.inliers;
  msg.map_id = pose.map_id;
  msg.relocalized = pose.relocalized;
  msg.odometry_only = pose.odometry_only;
  msg.position_sigma_m = static_cast<float>(pose.position_sigma_m);
  if (lcm_->publish(channels_.pose, &msg) != 0) return io_error("LCM publish on " + channels_.pose + " failed");
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
  msg.keyframes = report.keyframes;
  msg.map_points = report.map_points;
  msg.map_id = report.map_id;
  msg.relocalisations = report.relocalisations;
  msg.place_ms = report.place_ms;
  msg.loops_closed = report.loops_closed;
  msg.loops_refused = report.loops_refused;
  msg.loop_ms = report.loop_ms;
  msg.merges = report.merges;
  msg.merges_refused = report.merges_refused;
  msg.pool_count = static_cast<int32_t>(report.pool_count);
  for (std::size_t i = 0; i < report.pool_count; ++i) {
    msg.pool_names.emplace_back(report.pools[i].name);
    msg.pool_high_water.push_back(static_cast<int64_t>(report.pools[i].high_water));
    msg.pool_capacity.push_back(static_cast<int64_t>(report.pools[i].capacity));
  }
  msg.camera_state = static_cast<int8_t>(report.camera_state);
  msg.camera_reconnects = static_cast<int64_t>(report.camera_reconnects);
  msg.frames_dropped = static_cast<int64_t>(report.frames_dropped);
  msg.frames_skipped = static_cast<int64_t>(report.frames_skipped);
  msg.frame_errors = static_cast<int64_t>(report.frame_errors);
  msg.stage_count = static_cast<int32_t>(report.timings.count);
  for (std::size_t i = 0; i < report.timings.count; ++i) {
    msg.stage_names.emplace_back(report.timings.stage[i].name);
    msg.stage_ms.push_back(static_cast<float>(static_cast<double>(report.timings.stage[i].ns) / 1e6));
  }
  msg.config_generation = report.config_generation;
  msg.paused = report.paused;
  msg.publish_errors = static_cast<int64_t>(report.publish_errors);
  msg.commands_received = static_cast<int64_t>(report.commands_received);
  msg.commands_rejected = static_cast<int64_t>(report.commands_rejected);
  msg.recorder_state = static_cast<int8_t>(report.recorder_state);
  msg.frames_recorded = static_cast<int64_t>(report.frames_recorded);
  msg.frames_not_recorded = static_cast<int64_t>(report.frames_not_recorded);
  msg.odometry_accepted = static_cast<int64_t>(report.odometry_accepted);
  msg.odometry_refused = static_cast<int64_t>(report.odometry_refused);
  msg.map_scale = static_cast<float>(report.map_scale);
  msg.odometry_disagreements = static_cast<int64_t>(report.odometry_disagreements);
  msg.map_saves = static_cast<int64_t>(report.map_saves);
  msg.map_save_failures = static_cast<int64_t>(report.map_save_failures);
  msg.last_save_ms = report.last_save_ms;
  msg.last_error = report.last_error;
  msg.message = report.message;
  if (lcm_->publish(channels_.status, &msg) != 0) return io_error("LCM publish on " + channels_.status + " failed");
  return {};
}

Status LcmPoseSink::subscribe_odometry(const std::string& channel) {
  if (odometry_subscription_ != nullptr) (void)lcm_->unsubscribe(odometry_subscription_);
  odometry_subscription_ = nullptr;
  if (channel.empty()) return {};
  odometry_subscription_ = lcm_->subscribeFunction(channel, &LcmPoseSink::on_odometry_of, this);
  if (odometry_subscription_ == nullptr) return unavailable("LCM cannot subscribe to '" + channel + "'");
  return {};
}

void LcmPoseSink::on_odometry(const lcm::ReceiveBuffer* buffer, const std::string& channel) {
  ale_lcm::odometry_t msg;
  if (msg.decode(buffer->data, 0, static_cast<int>(buffer->data_size)) < 0) {
    ++odometry_malformed_;
    if (!odometry_malformed_logged_)
      log_message(LogLevel::kWarning, "%u bytes on %s are not an ale_lcm.odometry_t (further ones are counted in status)",
                  static_cast<unsigned>(buffer->data_size), channel.c_str());
    odometry_malformed_logged_ = true;
    return;
  }
  ale::slam::OdometrySample s;
  s.t_ns = msg.timestamp_ns;
  s.sequence = static_cast<std::uint32_t>(static_cast<std::uint64_t>(msg.sequence));
  s.x_m = msg.x;
  s.y_m = msg.y;
  s.theta_rad = msg.theta;
  s.has_gyro = (msg.flags & ale_lcm::odometry_t::HAS_GYRO) != 0;
  s.gyro_z_rps = msg.gyro_z;
  s.has_wheels = (msg.flags & ale_lcm::odometry_t::HAS_WHEELS) != 0;
  s.v_left_mps = msg.v_left;
  s.v_right_mps = msg.v_right;
  odometry_.push_back(s);
}

std::uint64_t LcmPoseSink::take_odometry(std::vector<ale::slam::OdometrySample>& out) {
  out.insert(out.end(), odometry_.begin(), odometry_.end());
  odometry_.clear();
  const std::uint64_t malformed = odometry_malformed_;
  odometry_malformed_ = 0;
  return malformed;
}

int LcmPoseSink::poll_fd() const { return lcm_->getFileno(); }

namespace {

// lcm-gen 1.3.1's decode() of a string takes its int32 length field on trust unless it exceeds
// the buffer: 0 or a negative length makes std::string::assign ask for length - 1 characters
// (SIZE_MAX or near: std::length_error), and INT32_MIN overflows to INT32_MAX characters read from
// a buffer of a few bytes. So command_t's one string is checked first: its length field (big-
// endian, after the 8-byte fingerprint, the 8-byte command_id and the 1-byte command) must count
// its '\0' and fit in the bytes received (tests/fuzz/corpus/command/regression_*).
bool command_string_length_fits(const void* data, std::size_t size) {
  constexpr std::size_t kLengthAt = 8 + 8 + 1;
  if (size < kLengthAt + 4) return false;
  const auto* p = static_cast<const std::uint8_t*>(data) + kLengthAt;
  const std::uint32_t length = (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) |
                               (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]};
  return length >= 1 && length <= size - (kLengthAt + 4);
}

}  // namespace

ale::hal::Command decode_command(const void* data, std::size_t size, const std::string& channel) {
  ale_lcm::command_t msg;
  ale::hal::Command c;
  // decode() checks the type's fingerprint and the other lengths: a foreign type or truncated
  // bytes fail.
  if (size > static_cast<std::size_t>(INT32_MAX) || !command_string_length_fits(data, size) ||
      msg.decode(data, 0, static_cast<int>(size)) < 0) {
    c.malformed = true;
    c.error = std::to_string(size) + " bytes on " + channel + " are not an ale_lcm.command_t";
  } else {
    c.id = msg.command_id;
    c.kind = msg.command;
    c.argument = msg.argument;
  }
  return c;
}

void LcmPoseSink::on_command(const lcm::ReceiveBuffer* buffer, const std::string& channel) {
  received_.push_back(decode_command(buffer->data, buffer->data_size, channel));
}

Status LcmPoseSink::receive(std::vector<ale::hal::Command>& out) {
  // handleTimeout(0) dispatches at most one message: drain what is waiting.
  for (int handled = 1; handled > 0;) {
    handled = lcm_->handleTimeout(0);
    if (handled < 0) return io_error("LCM receive failed");
  }
  for (auto& c : received_) out.push_back(std::move(c));
  received_.clear();
  return {};
}

Status LcmPoseSink::reply(const ale::hal::CommandReply& r) {
  ale_lcm::command_reply_t msg;
  msg.timestamp_ns = r.timestamp_ns;
  msg.command_id = r.id;
  msg.command = r.kind;
  msg.result = static_cast<int8_t>(r.result);
  msg.message = r.message;
  if (lcm_->publish(channels_.reply, &msg) != 0) return io_error("LCM publish on " + channels_.reply + " failed");
  return {};
}

}  // namespace ale::app
