#include "app/tools/lib/render/odometry.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "app/tools/lib/render/rng.h"

namespace ale::render {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegToRad = kPi / 180.0;

// Independent random streams of one seed.
enum Stream : std::uint64_t { kFigures = 1, kGyroNoise = 2, kSlip = 3 };

double uniform(SplitMix64& g, double lo, double hi) { return lo + (hi - lo) * g.uniform_double(); }

// Angle in (-pi, pi].
double wrap(double a) {
  const double r = std::remainder(a, 2.0 * kPi);
  return r <= -kPi ? r + 2.0 * kPi : r;
}

// Arc length / chord length of a circular arc turning by 2 * half.
double arc_over_chord(double half) {
  return std::abs(half) < 1e-6 ? 1.0 + half * half / 6.0 : half / std::sin(half);
}

// One wheel's slip, re-drawn every 2..5 s when it varies.
class SlipSchedule {
 public:
  SlipSchedule(const OdometryErrors& e, std::uint64_t seed) : e_(e), rng_(seed) {}
  double at(double t_s) {
    if (!e_.slip_varies) return e_.slip;
    while (t_s >= next_s_) {
      slip_ = uniform(rng_, 0.0, e_.slip_max);
      next_s_ += uniform(rng_, 2.0, 5.0);
    }
    return slip_;
  }

 private:
  const OdometryErrors& e_;
  SplitMix64 rng_;
  double slip_ = 0.0;
  double next_s_ = 0.0;
};

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.12g", v == 0.0 ? 0.0 : v);  // no "-0"
  return buf;
}

}  // namespace

const char* to_string(OdometryNoise noise) {
  switch (noise) {
    case OdometryNoise::kNone: return "none";
    case OdometryNoise::kNormal: return "normal";
    case OdometryNoise::kHarsh: return "harsh";
  }
  return "?";
}

Result<OdometryNoise> parse_odometry_noise(const std::string& name) {
  for (OdometryNoise n : {OdometryNoise::kNone, OdometryNoise::kNormal, OdometryNoise::kHarsh})
    if (name == to_string(n)) return n;
  return invalid_argument("odometry noise '" + name + "' is not none, normal or harsh");
}

OdometryErrors odometry_errors(const OdometrySettings& settings, double duration_s) {
  OdometryErrors e;
  SplitMix64 g(mix_seed(settings.seed, kFigures));
  switch (settings.noise) {
    case OdometryNoise::kNone:
      break;
    case OdometryNoise::kNormal:
      e.radius_error_left = 0.005;
      e.radius_error_right = -0.003;
      e.slip = 0.01;
      e.gyro_bias_dps = 0.05;
      e.gyro_noise_dps_rthz = 0.01;
      e.gyro_scale_error = 0.002;
      break;
    case OdometryNoise::kHarsh:
      e.radius_error_left = uniform(g, -0.01, 0.01);
      e.radius_error_right = uniform(g, -0.01, 0.01);
      e.slip_varies = true;
      e.slip_max = 0.03;
      e.slip = 0.5 * e.slip_max;
      e.gyro_bias_dps = g.below(2) == 0 ? 0.2 : -0.2;
      e.gyro_noise_dps_rthz = 0.03;
      e.gyro_scale_error = 0.002;
      e.wheel_spin = true;
      e.wheel_spin_left = g.below(2) == 0;
      e.wheel_spin_s = 1.0;
      e.wheel_spin_start_s = uniform(g, 0.0, std::max(0.0, duration_s - e.wheel_spin_s));
      e.wheel_spin_mps = 0.2;
      break;
  }
  return e;
}

Result<std::vector<OdometrySample>> simulate_odometry(const std::vector<BaseTruth>& truth,
                                                      const OdometrySettings& settings, const OdometryErrors& e) {
  if (truth.size() < 2) return invalid_argument("odometry: fewer than 2 truth samples");
  if (!(settings.wheel_base_m > 0.0)) return invalid_argument("odometry: the wheel base must be > 0 m");
  for (std::size_t i = 1; i < truth.size(); ++i)
    if (truth[i].t_ns <= truth[i - 1].t_ns)
      return invalid_argument("odometry: truth times do not increase at sample " + std::to_string(i));
  const std::int64_t offset_ns = std::llround(settings.clock_offset_ms * 1e6);
  SplitMix64 gyro_rng(mix_seed(settings.seed, kGyroNoise));
  SlipSchedule slip_left(e, mix_seed(settings.seed, kSlip));
  SlipSchedule slip_right(e, mix_seed(settings.seed, kSlip + 1));
  const double half_base = 0.5 * settings.wheel_base_m;

  std::vector<OdometrySample> out;
  out.reserve(truth.size());
  OdometrySample first;
  first.t_ns = truth.front().t_ns + offset_ns;
  out.push_back(first);
  double x = 0.0, y = 0.0, theta = 0.0;  // theta unwrapped
  for (std::size_t i = 1; i < truth.size(); ++i) {
    const BaseTruth& a = truth[i - 1];
    const BaseTruth& b = truth[i];
    const double dt = 1e-9 * static_cast<double>(b.t_ns - a.t_ns);
    const double mid_s = 1e-9 * static_cast<double>(a.t_ns - truth.front().t_ns) + 0.5 * dt;
    // The true step in the base frame of its start; nothing of a carried step reaches the sensors.
    double dx = 0.0, dy = 0.0, dth = 0.0;
    if (!b.carried) {
      const BaseTruth step = in_frame_of(a, b);
      dx = step.x_m;
      dy = step.y_m;
      dth = step.yaw_rad;
    }
    // As a circular arc: the chord points half the turn ahead. What is left across the chord (a
    // step that changes from driving to turning, ~1e-5 m) is no wheel's travel and passes as is.
    const double half = 0.5 * dth;
    const double along = dx * std::cos(half) + dy * std::sin(half);
    const double across = -dx * std::sin(half) + dy * std::cos(half);
    const double arc = along * arc_over_chord(half);
    double left = (arc - dth * half_base) * (1.0 + e.radius_error_left) * (1.0 - slip_left.at(mid_s));
    double right = (arc + dth * half_base) * (1.0 + e.radius_error_right) * (1.0 - slip_right.at(mid_s));
    if (e.wheel_spin && mid_s >= e.wheel_spin_start_s && mid_s < e.wheel_spin_start_s + e.wheel_spin_s)
      (e.wheel_spin_left ? left : right) += e.wheel_spin_mps * dt;
    const double noise_rps = e.gyro_noise_dps_rthz * kDegToRad / std::sqrt(dt);
    const double gyro = (dth / dt) * (1.0 + e.gyro_scale_error) + e.gyro_bias_dps * kDegToRad +
                        (noise_rps > 0.0 ? noise_rps * static_cast<double>(gyro_rng.gaussian()) : 0.0);
    // The MCU: heading from the gyro, the wheels' mean travel along it.
    const double turn = gyro * dt;
    const double chord = 0.5 * (left + right) / arc_over_chord(0.5 * turn);
    const double dir = theta + 0.5 * turn;
    x += chord * std::cos(dir) - across * std::sin(dir);
    y += chord * std::sin(dir) + across * std::cos(dir);
    theta += turn;
    OdometrySample o;
    o.t_ns = b.t_ns + offset_ns;
    o.x_m = x;
    o.y_m = y;
    o.theta_rad = wrap(theta);
    o.gyro_z_rps = gyro;
    o.v_left_mps = left / dt;
    o.v_right_mps = right / dt;
    out.push_back(o);
  }
  return out;
}

Eigen::Isometry3d sweeper_T_BC(const Rig& rig, const DriveOptions& drive) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rig.R_bc;
  T.translation() = Eigen::Vector3d(drive.camera_ahead_m, 0.0, drive.camera_height_m) + rig.t_bc;
  return T;
}

BaseTruth base_under_camera(const Eigen::Isometry3d& T_wc, const Eigen::Isometry3d& T_BC) {
  const Eigen::Isometry3d T_w_base = T_wc * T_BC.inverse();
  BaseTruth b;
  b.x_m = T_w_base.translation().x();
  b.y_m = T_w_base.translation().y();
  b.yaw_rad = std::atan2(T_w_base.linear()(1, 0), T_w_base.linear()(0, 0));
  return b;
}

Result<std::vector<BaseTruth>> sample_base_truth(const Trajectory& trajectory, const Rig& rig,
                                                 const Eigen::Isometry3d& T_BC, const std::vector<FrameTime>& frames,
                                                 double rate_hz) {
  if (frames.size() < 2) return invalid_argument("odometry: fewer than 2 frames");
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) return invalid_argument("odometry: the rate must be > 0 Hz");
  for (std::size_t k = 1; k < frames.size(); ++k)
    if (frames[k].clock_ns <= frames[k - 1].clock_ns)
      return invalid_argument("odometry: frame times do not increase at frame " + std::to_string(k));
  Eigen::Isometry3d T_bc = Eigen::Isometry3d::Identity();
  T_bc.linear() = rig.R_bc;
  T_bc.translation() = rig.t_bc;
  // A kidnap shows as trajectory time that does not advance with the clock between two frames.
  std::vector<int> drive(frames.size(), 0);
  for (std::size_t k = 1; k < frames.size(); ++k) {
    const double clock_s = 1e-9 * static_cast<double>(frames[k].clock_ns - frames[k - 1].clock_ns);
    drive[k] = drive[k - 1] + (std::abs(frames[k].t_s - frames[k - 1].t_s - clock_s) > 1e-6 ? 1 : 0);
  }
  const std::int64_t first = frames.front().clock_ns;
  const double span_s = 1e-9 * static_cast<double>(frames.back().clock_ns - first);
  const auto n = static_cast<std::int64_t>(std::floor(span_s * rate_hz + 1e-9)) + 1;
  std::vector<BaseTruth> out;
  out.reserve(static_cast<std::size_t>(n));
  std::size_t k = 0;
  for (std::int64_t i = 0; i < n; ++i) {
    const std::int64_t t_ns = first + std::llround(static_cast<double>(i) * 1e9 / rate_hz);
    const std::size_t before = k;
    while (k + 1 < frames.size() && frames[k + 1].clock_ns <= t_ns) ++k;
    const FrameTime& f = frames[k];
    const bool same_drive = k + 1 < frames.size() && drive[k + 1] == drive[k];
    const double t_s = same_drive ? f.t_s + 1e-9 * static_cast<double>(t_ns - f.clock_ns) : f.t_s;
    const Pose body = trajectory.at(t_s);
    Eigen::Isometry3d T_wb = Eigen::Isometry3d::Identity();
    T_wb.linear() = body.q_wb.normalized().toRotationMatrix();
    T_wb.translation() = body.p_wb;
    BaseTruth b = base_under_camera(T_wb * T_bc, T_BC);
    b.t_ns = t_ns;
    b.carried = drive[k] != drive[before];
    out.push_back(b);
  }
  return out;
}

BaseTruth in_frame_of(const BaseTruth& origin, const BaseTruth& b) {
  const double c = std::cos(origin.yaw_rad), s = std::sin(origin.yaw_rad);
  BaseTruth r = b;
  r.x_m = c * (b.x_m - origin.x_m) + s * (b.y_m - origin.y_m);
  r.y_m = -s * (b.x_m - origin.x_m) + c * (b.y_m - origin.y_m);
  r.yaw_rad = wrap(b.yaw_rad - origin.yaw_rad);
  return r;
}

std::string odometry_csv_text(const std::vector<OdometrySample>& samples) {
  std::string csv = "#timestamp [ns],x [m],y [m],theta [rad],gyro_z [rad/s],v_left [m/s],v_right [m/s]\n";
  char row[256];
  for (const OdometrySample& s : samples) {
    std::snprintf(row, sizeof row, "%" PRId64 ",%.12g,%.12g,%.12g,%.12g,%.12g,%.12g\n", s.t_ns, s.x_m, s.y_m,
                  s.theta_rad, s.gyro_z_rps, s.v_left_mps, s.v_right_mps);
    csv += row;
  }
  return csv;
}

std::string odometry_yaml_text(const OdometrySettings& settings, const OdometryErrors& e,
                               const Eigen::Isometry3d& T_BC, const std::string& comment) {
  std::ostringstream y;
  y << "sensor_type: odometry\ncomment: " << comment << "\nrate_hz: " << num(settings.rate_hz) << "\n";
  y << "T_BC:\n  cols: 4\n  rows: 4\n  data: [";
  const Eigen::Matrix4d m = T_BC.matrix();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      const double v = r == 3 ? (c == 3 ? 1.0 : 0.0) : m(r, c);
      y << num(v) << (r == 3 && c == 3 ? "" : ", ");
    }
  y << "]\n";
  y << "noise: " << to_string(settings.noise) << "\n";
  y << "seed: " << settings.seed << "\n";
  y << "clock_offset_ms: " << num(settings.clock_offset_ms) << "\n";
  y << "wheel_base_m: " << num(settings.wheel_base_m) << "\n";
  y << "wheel_radius_error_left: " << num(e.radius_error_left) << "\n";
  y << "wheel_radius_error_right: " << num(e.radius_error_right) << "\n";
  if (e.slip_varies) y << "slip: varies per wheel every 2..5 s in 0.." << num(e.slip_max) << "\n";
  else y << "slip: " << num(e.slip) << "\n";
  y << "gyro_bias_dps: " << num(e.gyro_bias_dps) << "\n";
  y << "gyro_noise_dps_rthz: " << num(e.gyro_noise_dps_rthz) << "\n";
  y << "gyro_scale_error: " << num(e.gyro_scale_error) << "\n";
  if (e.wheel_spin)
    y << "wheel_spin: " << (e.wheel_spin_left ? "left" : "right") << " wheel " << num(e.wheel_spin_mps) << " m/s for "
      << num(e.wheel_spin_s) << " s from " << num(e.wheel_spin_start_s) << " s\n";
  else y << "wheel_spin: none\n";
  return y.str();
}

}  // namespace ale::render
