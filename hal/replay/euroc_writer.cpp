#include "hal/replay/euroc_writer.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstdio>
#include <cstring>
#include <utility>
#include <filesystem>
#include <system_error>

namespace ale::replay {
namespace {

namespace fs = std::filesystem;

constexpr const char kCsvHeader[] = "#timestamp [ns],filename\n";

std::string number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

const char* model_name(hal::DistortionModel m) {
  switch (m) {
    case hal::DistortionModel::kRadialTangential:
      return "radial-tangential";
    case hal::DistortionModel::kEquidistant:
      return "equidistant";
    case hal::DistortionModel::kNone:
      break;
  }
  return "none";
}

std::string errno_text() { return std::strerror(errno); }

// Writes all of `text` at the end of fd; false (errno set) on a failure or a short write.
bool write_all(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (n == 0) errno = ENOSPC;
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  return true;
}

// A double that reads back (from_chars) to the same value: the shortest such text.
std::string shortest(double v) {
  char text[32];
  const std::to_chars_result r = std::to_chars(text, text + sizeof text, v);
  return std::string(text, r.ptr);
}

// A 4x4 row-major matrix as EuRoC's sensor.yaml has it.
std::string matrix4_yaml(const char* key, const std::array<double, 16>& m) {
  std::string y = std::string(key) + ":\n  cols: 4\n  rows: 4\n  data: [";
  for (std::size_t i = 0; i < m.size(); ++i) y += (i == 0 ? "" : i % 4 == 0 ? ",\n         " : ", ") + number(m[i]);
  return y + "]\n";
}

// Writes `text` as the file at path (replacing it). kIoError naming the file.
Status write_text_file(const std::string& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) return io_error(path + ": cannot create: " + errno_text());
  const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size() && std::fflush(f) == 0;
  const std::string why = written ? std::string() : errno_text();
  if (std::fclose(f) != 0 || !written) return io_error(path + ": cannot write: " + (written ? errno_text() : why));
  return {};
}

constexpr const char kYamlHead[] = "%YAML:1.0\n# Written by ale-slamd's recorder.\n";

}  // namespace

RowFile& RowFile::operator=(RowFile&& other) noexcept {
  if (this != &other) {
    (void)close();
    path_ = std::move(other.path_);
    fd_ = std::exchange(other.fd_, -1);
    bytes_ = other.bytes_;
  }
  return *this;
}

Status RowFile::create(const std::string& path, const std::string& header) {
  (void)close();
  path_ = path;
  bytes_ = 0;
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd_ < 0) return io_error(path + ": cannot create: " + errno_text());
  Status s = append(header);
  if (!s.ok()) {
    // A list without its header is unreadable: no list at all.
    (void)close();
    (void)::unlink(path.c_str());
  }
  return s;
}

Status RowFile::append(const std::string& row) {
  if (fd_ < 0) return io_error(path_ + ": closed");
  if (!write_all(fd_, row)) {
    const std::string why = errno_text();
    // A partial row would make the list unreadable: back to the last whole one.
    if (::ftruncate(fd_, static_cast<off_t>(bytes_)) == 0) (void)::lseek(fd_, static_cast<off_t>(bytes_), SEEK_SET);
    return io_error(path_ + ": cannot write: " + why);
  }
  bytes_ += row.size();
  return {};
}

Status RowFile::close() {
  if (fd_ < 0) return {};
  const int fd = std::exchange(fd_, -1);
  if (::close(fd) != 0) return io_error(path_ + ": cannot close: " + errno_text());
  return {};
}

std::string euroc_sensor_yaml(const hal::CameraCalibration& c) {
  std::string y = std::string(kYamlHead) + "sensor_type: camera\n\n" + matrix4_yaml("T_BS", c.T_BS) + "\n";
  if (c.rate_hz > 0) y += "rate_hz: " + number(c.rate_hz) + "\n";
  y += "resolution: [" + std::to_string(c.width) + ", " + std::to_string(c.height) + "]\n";
  y += "camera_model: pinhole\n";
  y += "intrinsics: [" + number(c.fx) + ", " + number(c.fy) + ", " + number(c.cx) + ", " + number(c.cy) + "]\n";
  y += std::string("distortion_model: ") + model_name(c.distortion_model) + "\n";
  y += "distortion_coefficients: [";
  for (std::size_t i = 0; i < c.distortion.size(); ++i) y += (i == 0 ? "" : ", ") + number(c.distortion[i]);
  y += "]\n";
  return y;
}

Result<EurocWriter> EurocWriter::create(const std::string& root) {
  EurocWriter w;
  w.root_ = root;
  w.cam0_ = root + "/mav0/cam0";
  std::error_code ec;
  fs::create_directories(w.cam0_ + "/data", ec);
  if (ec) return io_error(w.cam0_ + "/data: cannot create: " + ec.message());
  ALE_RETURN_IF_ERROR(w.csv_.create(w.cam0_ + "/data.csv", kCsvHeader));
  return w;
}

std::string EurocWriter::frame_path(std::int64_t t_ns) const {
  return cam0_ + "/data/" + std::to_string(t_ns) + ".png";
}

Status EurocWriter::write_calibration(const hal::CameraCalibration& c) {
  const std::string text = euroc_sensor_yaml(c);
  ALE_RETURN_IF_ERROR(write_text_file(cam0_ + "/sensor.yaml", text));
  yaml_bytes_ = text.size();
  return {};
}

Status EurocWriter::append(std::int64_t t_ns) {
  if (last_t_ns_ && t_ns <= *last_t_ns_)
    return invalid_argument(cam0_ + "/data.csv: timestamp " + std::to_string(t_ns) + " does not follow " +
                            std::to_string(*last_t_ns_));
  const std::string t = std::to_string(t_ns);
  ALE_RETURN_IF_ERROR(csv_.append(t + "," + t + ".png\n"));
  last_t_ns_ = t_ns;
  return {};
}

Result<OdometryWriter> OdometryWriter::create(const std::string& root, const std::array<double, 16>& T_BC,
                                              double rate_hz) {
  OdometryWriter w;
  w.folder_ = root + "/mav0/odometry0";
  std::error_code ec;
  fs::create_directories(w.folder_, ec);
  if (ec) return io_error(w.folder_ + ": cannot create: " + ec.message());
  std::string yaml = std::string(kYamlHead) + "sensor_type: odometry\n";
  if (rate_hz > 0) yaml += "rate_hz: " + number(rate_hz) + "\n";
  yaml += matrix4_yaml("T_BC", T_BC);
  ALE_RETURN_IF_ERROR(write_text_file(w.folder_ + "/sensor.yaml", yaml));
  w.yaml_bytes_ = yaml.size();
  return w;
}

Status OdometryWriter::append(const OdometryRow& row) {
  const std::string csv = folder_ + "/data.csv";
  if (!csv_.is_open()) {
    std::string header = "#timestamp [ns],x [m],y [m],theta [rad]";
    if (row.has_gyro) header += ",gyro_z [rad/s]";
    if (row.has_wheels) header += ",v_left [m/s],v_right [m/s]";
    ALE_RETURN_IF_ERROR(csv_.create(csv, header + "\n"));
    gyro_ = row.has_gyro;
    wheels_ = row.has_wheels;
  }
  if (last_t_ns_ && row.timestamp_ns <= *last_t_ns_)
    return invalid_argument(csv + ": timestamp " + std::to_string(row.timestamp_ns) + " does not follow " +
                            std::to_string(*last_t_ns_));
  if (row.has_gyro != gyro_ || row.has_wheels != wheels_) {
    const bool gyro = row.has_gyro != gyro_;
    const bool has = gyro ? row.has_gyro : row.has_wheels;
    return invalid_argument(csv + ": the sample at " + std::to_string(row.timestamp_ns) + (has ? " has " : " has no ") +
                            (gyro ? "gyro_z" : "wheel speeds") + ", unlike the file's columns");
  }
  std::string text = std::to_string(row.timestamp_ns) + "," + shortest(row.x_m) + "," + shortest(row.y_m) + "," +
                     shortest(row.theta_rad);
  if (row.has_gyro) text += "," + shortest(row.gyro_z_rps);
  if (row.has_wheels) text += "," + shortest(row.v_left_mps) + "," + shortest(row.v_right_mps);
  ALE_RETURN_IF_ERROR(csv_.append(text + "\n"));
  last_t_ns_ = row.timestamp_ns;
  return {};
}

}  // namespace ale::replay
