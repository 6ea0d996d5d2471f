#include "app/tools/ale_render/euroc_writer.h"

#include <algorithm>
#include <cmath>
#include <cinttypes>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "app/tools/lib/render/sensor_yaml.h"
#include "core/io/image_io.h"

namespace ale::render {

namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadToDeg = 180.0 / kPi;

std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
std::string format(const char* fmt, ...) {
  char buf[512];
  va_list args;
  va_start(args, fmt);
  const int n = std::vsnprintf(buf, sizeof buf, fmt, args);
  va_end(args);
  return n < 0 ? std::string() : std::string(buf, std::min<std::size_t>(static_cast<std::size_t>(n), sizeof buf - 1));
}

}  // namespace

std::string ns_to_seconds_text(std::int64_t ns) {
  const bool negative = ns < 0;
  const std::uint64_t a = negative ? static_cast<std::uint64_t>(-(ns + 1)) + 1u : static_cast<std::uint64_t>(ns);
  return format("%s%" PRIu64 ".%09" PRIu64, negative ? "-" : "", a / 1000000000u, a % 1000000000u);
}

Result<EurocWriter> EurocWriter::create(const std::string& out_dir, bool overwrite) {
  if (out_dir.empty()) return invalid_argument("output folder is empty");
  std::error_code ec;
  const fs::path out(out_dir);
  const fs::path mav0 = out / "mav0";
  if (fs::exists(mav0, ec)) {
    if (!overwrite) return invalid_argument(mav0.string() + " already exists (pass --overwrite to replace it)");
    fs::remove_all(mav0, ec);
    if (ec) return io_error(mav0.string() + ": cannot remove: " + ec.message());
  }
  for (const fs::path& p : {mav0 / "cam0" / "data", mav0 / "state_groundtruth_estimate0"}) {
    fs::create_directories(p, ec);
    if (ec) return io_error(p.string() + ": cannot create: " + ec.message());
  }
  EurocWriter w(out.string());
  w.frames_csv_ = "#timestamp [ns],filename\n";
  w.state_csv_ =
      "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z [], "
      "v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], "
      "b_w_RS_S_z [rad s^-1], b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]\n";
  w.tum_ = "# timestamp tx ty tz qx qy qz qw\n";
  w.lighting_csv_ = "#timestamp [ns],profile,room_lux,lamps_on,sun_lux,exposure_us,gain,mean_grey\n";
  return w;
}

Status EurocWriter::write_sensor_yaml(const PinholeCamera& c, double fps, const Rig& rig, const std::string& comment,
                                      const std::string& notes) {
  return write_text_file((fs::path(out_) / "mav0" / "cam0" / "sensor.yaml").string(),
                         sensor_yaml_text(c, fps, rig, comment, notes));
}

Status EurocWriter::add_frame(std::int64_t ts, GrayView image, const FrameRecord& rec, const Eigen::Vector3d& v,
                              const char* profile) {
  const std::string name = format("%" PRId64 ".png", ts);
  ALE_RETURN_IF_ERROR(io::write_png((fs::path(out_) / "mav0" / "cam0" / "data" / name).string(), image));
  frames_csv_ += format("%" PRId64 ",%s\n", ts, name.c_str());
  const Eigen::Vector3d& p = rec.body.p_wb;
  const Eigen::Quaterniond q = rec.body.q_wb.normalized();
  state_csv_ += format("%" PRId64 ",%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,0,0,0,0,0,0\n", ts, p.x(), p.y(),
                       p.z(), q.w(), q.x(), q.y(), q.z(), v.x(), v.y(), v.z());
  const Eigen::Vector3d& pc = rec.camera.p_wb;
  const Eigen::Quaterniond qc = rec.camera.q_wb.normalized();
  tum_ += ns_to_seconds_text(ts) +
          format(" %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", pc.x(), pc.y(), pc.z(), qc.x(), qc.y(), qc.z(), qc.w());
  lighting_csv_ += format("%" PRId64 ",%s,%.4g,%d,%.6g,%.1f,%.4f,%.3f\n", ts, profile, rec.light.room_lux,
                          rec.light.lamps_on ? 1 : 0, rec.light.sun_lux, rec.exposure.exposure_us, rec.exposure.gain,
                          rec.mean_grey);
  return {};
}

Status EurocWriter::finish() {
  const fs::path out(out_);
  ALE_RETURN_IF_ERROR(write_text_file((out / "mav0" / "cam0" / "data.csv").string(), frames_csv_));
  ALE_RETURN_IF_ERROR(write_text_file((out / "mav0" / "state_groundtruth_estimate0" / "data.csv").string(), state_csv_));
  ALE_RETURN_IF_ERROR(write_text_file((out / "groundtruth.txt").string(), tum_));
  return write_text_file((out / "lighting.csv").string(), lighting_csv_);
}

Status EurocWriter::write_odometry(const std::string& csv, const std::string& yaml) {
  const fs::path dir = fs::path(out_) / "mav0" / "odometry0";
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return io_error(dir.string() + ": cannot create: " + ec.message());
  ALE_RETURN_IF_ERROR(write_text_file((dir / "data.csv").string(), csv));
  return write_text_file((dir / "sensor.yaml").string(), yaml);
}

Result<std::string> write_sweeper_odometry(EurocWriter& writer, const Trajectory& trajectory, const Rig& rig,
                                           const Eigen::Isometry3d& T_BC, const std::vector<FrameTime>& frames,
                                           const OdometrySettings& settings, const std::string& route) {
  if (frames.size() < 2) return std::string("odometry0 not written: it needs at least 2 frames\n");
  Result<std::vector<BaseTruth>> truth = sample_base_truth(trajectory, rig, T_BC, frames, settings.rate_hz);
  if (!truth.ok()) return truth.status();
  if (truth->size() < 2) return std::string("odometry0 not written: the frames span less than one odometry step\n");
  const double duration_s = 1e-9 * static_cast<double>(truth->back().t_ns - truth->front().t_ns);
  const OdometryErrors errors = odometry_errors(settings, duration_s);
  Result<std::vector<OdometrySample>> odo = simulate_odometry(*truth, settings, errors);
  if (!odo.ok()) return odo.status();
  char comment[200];
  std::snprintf(comment, sizeof comment, "ale-render wheel odometry of the %s route, noise %s, seed %llu",
                route.c_str(), to_string(settings.noise), static_cast<unsigned long long>(settings.seed));
  ALE_RETURN_IF_ERROR(writer.write_odometry(odometry_csv_text(*odo), odometry_yaml_text(settings, errors, T_BC, comment)));
  const BaseTruth end = in_frame_of(truth->front(), truth->back());
  const OdometrySample& o = odo->back();
  double path_m = 0.0;
  for (std::size_t i = 1; i < truth->size(); ++i)
    path_m += std::hypot((*truth)[i].x_m - (*truth)[i - 1].x_m, (*truth)[i].y_m - (*truth)[i - 1].y_m);
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "odometry: %zu samples at %g Hz, noise %s, seed %llu; base path %.2f m, heading turned %.1f deg net; "
                "at the end off by %.4f m and %.3f deg\n",
                odo->size(), settings.rate_hz, to_string(settings.noise),
                static_cast<unsigned long long>(settings.seed), path_m, end.yaw_rad * kRadToDeg,
                std::hypot(o.x_m - end.x_m, o.y_m - end.y_m), std::remainder(o.theta_rad - end.yaw_rad, 2.0 * kPi) * kRadToDeg);
  return std::string(buf);
}

}  // namespace ale::render
