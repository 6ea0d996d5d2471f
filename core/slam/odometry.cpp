#include "core/slam/odometry.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace ale::slam {
namespace {

constexpr double kPi = 3.14159265358979323846;

bool finite(const OdometrySample& s) {
  bool ok = std::isfinite(s.x_m) && std::isfinite(s.y_m) && std::isfinite(s.theta_rad);
  if (s.has_gyro) ok = ok && std::isfinite(s.gyro_z_rps);
  if (s.has_wheels) ok = ok && std::isfinite(s.v_left_mps) && std::isfinite(s.v_right_mps);
  return ok;
}

BasePose2 blend(const OdometrySample& a, const OdometrySample& b, double u) {
  return {a.x_m + u * (b.x_m - a.x_m), a.y_m + u * (b.y_m - a.y_m),
          a.theta_rad + u * angle_difference(b.theta_rad, a.theta_rad)};
}

}  // namespace

Status validate(const OdometryParams& p) {
  if (p.capacity < 2 || p.capacity > 100000) return invalid_argument("odometry capacity must be 2..100000 samples");
  if (!(p.max_gap_s > 0.0 && p.max_gap_s <= 10.0)) return invalid_argument("odometry max_gap_s must be in (0, 10]");
  if (!(p.max_extrapolation_s >= 0.0 && p.max_extrapolation_s <= 1.0))
    return invalid_argument("odometry max_extrapolation_s must be in [0, 1]");
  if (!(p.max_speed_mps > 0.0 && p.max_speed_mps <= 100.0))
    return invalid_argument("odometry max_speed_mps must be in (0, 100]");
  if (!(p.max_turn_rate_rps > 0.0 && p.max_turn_rate_rps <= 100.0))
    return invalid_argument("odometry max_turn_rate_rps must be in (0, 100]");
  if (p.jump_restart < 1 || p.jump_restart > 1000) return invalid_argument("odometry jump_restart must be 1..1000");
  if (!(p.min_init_baseline_m > 0.0 && p.min_init_baseline_m <= 10.0))
    return invalid_argument("odometry min_init_baseline_m must be in (0, 10]");
  if (!(p.prior_sigma_m > 0.0 && p.prior_sigma_m <= 10.0)) return invalid_argument("odometry prior_sigma_m must be in (0, 10]");
  if (!(p.prior_sigma_fraction >= 0.0 && p.prior_sigma_fraction <= 10.0))
    return invalid_argument("odometry prior_sigma_fraction must be in [0, 10]");
  if (!(p.keyframe_prior_max_span_s >= 0.0 && p.keyframe_prior_max_span_s <= 3600.0))
    return invalid_argument("odometry keyframe_prior_max_span_s must be in [0, 3600]");
  if (!(p.coast_s >= 0.0 && p.coast_s <= 60.0)) return invalid_argument("odometry coast_s must be in [0, 60]");
  if (!(p.rotation_prior_sigma_deg >= 0.0 && p.rotation_prior_sigma_deg <= 180.0))
    return invalid_argument("odometry rotation_prior_sigma_deg must be in [0, 180]");
  if (!(p.rotation_prior_sigma_fraction >= 0.0 && p.rotation_prior_sigma_fraction <= 10.0))
    return invalid_argument("odometry rotation_prior_sigma_fraction must be in [0, 10]");
  if (!(p.gyro_bias_window_s >= 1.0 && p.gyro_bias_window_s <= 3600.0))
    return invalid_argument("odometry gyro_bias_window_s must be in [1, 3600]");
  if (!(p.gyro_bias_z >= 0.0 && p.gyro_bias_z <= 100.0)) return invalid_argument("odometry gyro_bias_z must be in [0, 100]");
  if (!p.T_bc.translation().allFinite() || !p.T_bc.rotation().allFinite())
    return invalid_argument("odometry T_bc must be finite");
  return Status::ok_status();
}

namespace {
constexpr ConfigField kOdometryFields[] = {
    number<&OdometryParams::capacity>("capacity", 2, 100000, "odometry samples kept (a fixed ring)"),
    number<&OdometryParams::max_gap_s>("max_gap_s", 0.001, 10,
                                       "no interpolation between samples further apart than this, s"),
    number<&OdometryParams::max_extrapolation_s>("max_extrapolation_s", 0, 1,
                                                 "a frame this much newer than the last sample is extrapolated, s"),
    number<&OdometryParams::max_speed_mps>("max_speed_mps", 0.01, 100,
                                           "a sample implying a faster move is a jump: refused, m/s"),
    number<&OdometryParams::max_turn_rate_rps>("max_turn_rate_rps", 0.01, 100,
                                               "a sample implying a faster turn is a jump: refused, rad/s"),
    number<&OdometryParams::jump_restart>("jump_restart", 1, 1000,
                                          "after this many jumps in a row the stream restarts from its new value"),
    number<&OdometryParams::min_init_baseline_m>("min_init_baseline_m", 0.001, 10,
                                                 "the map is put in metres when the odometry moved this far between its first keyframes, m"),
    number<&OdometryParams::prior_sigma_m>("prior_sigma_m", 0.0001, 10,
                                           "camera-centre prior from the odometry: sigma's constant part, m"),
    number<&OdometryParams::prior_sigma_fraction>("prior_sigma_fraction", 0, 10,
                                                  "... plus this share of the odometry's step"),
    number<&OdometryParams::keyframe_prior_max_span_s>("keyframe_prior_max_span_s", 0, 3600,
                                                       "local BA: odometry priors between keyframes at most this far apart, s"),
    number<&OdometryParams::gyro_bias_window_s>("gyro_bias_window_s", 1, 3600,
                                                "the gyro's bias against the camera's heading: averaged over about this long, s"),
    number<&OdometryParams::gyro_bias_z>("gyro_bias_z", 0, 100,
                                         "... taken off the heading prior once this many standard errors from 0 (0: never)"),
    number<&OdometryParams::coast_s>("coast_s", 0, 60,
                                     "a frame the camera cannot track is posed by the odometry, for this long at most, s (0: off)"),
    number<&OdometryParams::rotation_prior_sigma_deg>("rotation_prior_sigma_deg", 0, 180,
                                                      "local BA: keyframe rotation prior from the odometry's turn, sigma's constant part, deg (0: none)"),
    number<&OdometryParams::rotation_prior_sigma_fraction>("rotation_prior_sigma_fraction", 0, 10,
                                                           "... plus this share of the turn"),
};
}  // namespace
extern constexpr ConfigTable kOdometryConfig = table_of<OdometryParams>(kOdometryFields);

geometry::SE3 base_pose_se3(const BasePose2& pose) {
  return geometry::SE3(geometry::SO3::exp(geometry::Vec3(0.0, 0.0, pose.theta_rad)),
                       geometry::Vec3(pose.x_m, pose.y_m, 0.0));
}

OdometryBuffer::OdometryBuffer(const OdometryParams& params)
    : params_(params), ring_(static_cast<std::size_t>(std::max(2, params.capacity))) {}

void OdometryBuffer::clear() {
  head_ = 0;
  size_ = 0;
  jumps_in_row_ = 0;
}

const OdometrySample& OdometryBuffer::sample(std::size_t i) const { return ring_[(head_ + i) % ring_.size()]; }

bool OdometryBuffer::is_jump(const OdometrySample& last, const OdometrySample& next) const {
  const double dt = static_cast<double>(next.t_ns - last.t_ns) * 1e-9;
  // Within a gap the robot may have moved further; a gap is judged by its own counter instead.
  const double span = std::min(dt, params_.max_gap_s);
  const double distance = std::hypot(next.x_m - last.x_m, next.y_m - last.y_m);
  const double turn = std::abs(angle_difference(next.theta_rad, last.theta_rad));
  // A few centimetres and degrees of slack: a slow stream's single step is not judged at rest.
  return distance > params_.max_speed_mps * span + 0.02 || turn > params_.max_turn_rate_rps * span + 0.05;
}

Status OdometryBuffer::add(const OdometrySample& s) {
  if (!finite(s)) {
    ++counters_.not_finite;
    return frame_rejected("odometry sample " + std::to_string(s.sequence) + " has a value that is not finite");
  }
  if (size_ > 0) {
    const OdometrySample& last = sample(size_ - 1);
    if (s.t_ns <= last.t_ns) {
      ++counters_.not_increasing;
      return frame_rejected("odometry sample " + std::to_string(s.sequence) + " at " + std::to_string(s.t_ns) +
                            " ns does not come after the last one at " + std::to_string(last.t_ns) + " ns");
    }
    if (is_jump(last, s)) {
      ++counters_.jumps;
      if (++jumps_in_row_ < params_.jump_restart) {
        return frame_rejected("odometry sample " + std::to_string(s.sequence) +
                              " jumps further than the robot can move since the last one");
      }
      // The stream stays at its new place: it restarted (an MCU reset, a new odometry frame).
      ++counters_.restarts;
      clear();
    } else {
      if (s.sequence != last.sequence + 1 && s.sequence > last.sequence)
        counters_.lost_reports += s.sequence - last.sequence - 1;
      if (static_cast<double>(s.t_ns - last.t_ns) * 1e-9 > params_.max_gap_s) ++counters_.gaps;
    }
  }
  jumps_in_row_ = 0;
  if (size_ == ring_.size()) {
    head_ = (head_ + 1) % ring_.size();
    --size_;
  }
  ring_[(head_ + size_) % ring_.size()] = s;
  ++size_;
  ++counters_.accepted;
  return Status::ok_status();
}

std::optional<BasePose2> OdometryBuffer::at(std::int64_t camera_t_ns) const {
  if (size_ == 0) return std::nullopt;
  const std::int64_t t = camera_t_ns - params_.clock_offset_ns;
  const std::int64_t max_gap_ns = static_cast<std::int64_t>(params_.max_gap_s * 1e9);
  const OdometrySample& newest = sample(size_ - 1);
  if (t >= newest.t_ns) {
    if (t == newest.t_ns) return blend(newest, newest, 0.0);
    if (size_ < 2 || static_cast<double>(t - newest.t_ns) * 1e-9 > params_.max_extrapolation_s) return std::nullopt;
    const OdometrySample& before = sample(size_ - 2);
    if (newest.t_ns - before.t_ns > max_gap_ns) return std::nullopt;
    const double u = static_cast<double>(t - before.t_ns) / static_cast<double>(newest.t_ns - before.t_ns);
    return blend(before, newest, u);
  }
  if (t < sample(0).t_ns) return std::nullopt;
  // The first kept sample after t, by bisection over the ring.
  std::size_t lo = 0, hi = size_ - 1;  // sample(lo).t <= t < sample(hi).t
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    if (sample(mid).t_ns <= t) lo = mid; else hi = mid;
  }
  const OdometrySample& a = sample(lo);
  const OdometrySample& b = sample(hi);
  if (b.t_ns - a.t_ns > max_gap_ns) return std::nullopt;
  return blend(a, b, static_cast<double>(t - a.t_ns) / static_cast<double>(b.t_ns - a.t_ns));
}

geometry::SE3 base_between(const BasePose2& a, const BasePose2& b) {
  const double c = std::cos(a.theta_rad), s = std::sin(a.theta_rad);
  const double dx = b.x_m - a.x_m, dy = b.y_m - a.y_m;
  return base_pose_se3({c * dx + s * dy, -s * dx + c * dy, angle_difference(b.theta_rad, a.theta_rad)});
}

geometry::SE3 camera_between(const geometry::SE3& T_bc, const BasePose2& a, const BasePose2& b) {
  return T_bc.inverse() * base_between(a, b) * T_bc;
}

double angle_difference(double a, double b) {
  double d = std::remainder(a - b, 2.0 * kPi);
  if (d <= -kPi) d += 2.0 * kPi;
  return d;
}

BasePose2 keyframe_odometry(const map::Keyframe& k) { return {k.odometry_x_m, k.odometry_y_m, k.odometry_theta_rad}; }

void GyroBias::add(double odometry_turn_rad, double camera_turn_rad, double dt_s, int inliers) {
  if (!(params_.gyro_bias_z > 0.0) || !(dt_s > 0.0) || inliers < kMinInliers) return;
  if (!(std::abs(odometry_turn_rad) <= kStraightRps * dt_s) || !std::isfinite(camera_turn_rad)) return;
  const double keep = std::exp(-dt_s / params_.gyro_bias_window_s);
  const double d = odometry_turn_rad - camera_turn_rad;
  sum_ = keep * sum_ + d;
  sum_sq_ = keep * sum_sq_ + d * d;
  frames_ = keep * frames_ + 1.0;
  time_s_ = keep * time_s_ + dt_s;
  if (frames_ < kMinFrames) return;
  const double mean = sum_ / frames_;
  const double standard_error = std::sqrt(std::max(0.0, sum_sq_ / frames_ - mean * mean) / frames_);
  rate_rps_ = std::abs(mean) > params_.gyro_bias_z * standard_error ? sum_ / time_s_ : 0.0;
}

double OdometryParams::prior_sigma(double step_m) const { return prior_sigma_m + prior_sigma_fraction * step_m; }
double OdometryParams::rotation_prior_sigma(const BasePose2& a, const BasePose2& b) const {
  return rotation_prior_sigma_deg * (kPi / 180.0) + rotation_prior_sigma_fraction * std::abs(angle_difference(b.theta_rad, a.theta_rad));
}

std::optional<geometry::SE3> OdometryBuffer::base_motion(std::int64_t t1_ns, std::int64_t t2_ns) const {
  const std::optional<BasePose2> b1 = at(t1_ns);
  const std::optional<BasePose2> b2 = at(t2_ns);
  if (!b1 || !b2) return std::nullopt;
  return base_between(*b1, *b2);
}

std::optional<geometry::SE3> OdometryBuffer::camera_motion(std::int64_t t1_ns, std::int64_t t2_ns) const {
  const std::optional<geometry::SE3> T_b1b2 = base_motion(t1_ns, t2_ns);
  if (!T_b1b2) return std::nullopt;
  return (params_.T_bc.inverse() * *T_b1b2 * params_.T_bc).inverse();
}

}  // namespace ale::slam
