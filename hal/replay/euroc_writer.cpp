#include "hal/replay/euroc_writer.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
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

}  // namespace

std::string euroc_sensor_yaml(const hal::CameraCalibration& c) {
  std::string y = "%YAML:1.0\n# Written by ale-slamd's recorder.\nsensor_type: camera\n\nT_BS:\n  cols: 4\n  rows: 4\n  data: [";
  for (std::size_t i = 0; i < c.T_BS.size(); ++i) y += (i == 0 ? "" : i % 4 == 0 ? ",\n         " : ", ") + number(c.T_BS[i]);
  y += "]\n\n";
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

EurocWriter::EurocWriter(EurocWriter&& other) noexcept { *this = std::move(other); }

EurocWriter& EurocWriter::operator=(EurocWriter&& other) noexcept {
  if (this != &other) {
    (void)close();
    root_ = std::move(other.root_);
    cam0_ = std::move(other.cam0_);
    csv_fd_ = std::exchange(other.csv_fd_, -1);
    csv_bytes_ = other.csv_bytes_;
    last_t_ns_ = other.last_t_ns_;
    text_bytes_ = other.text_bytes_;
    yaml_bytes_ = other.yaml_bytes_;
  }
  return *this;
}

EurocWriter::~EurocWriter() { (void)close(); }

Result<EurocWriter> EurocWriter::create(const std::string& root) {
  EurocWriter w;
  w.root_ = root;
  w.cam0_ = root + "/mav0/cam0";
  std::error_code ec;
  fs::create_directories(w.cam0_ + "/data", ec);
  if (ec) return io_error(w.cam0_ + "/data: cannot create: " + ec.message());
  const std::string csv = w.cam0_ + "/data.csv";
  // O_EXCL: never append to another recording's list.
  w.csv_fd_ = ::open(csv.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (w.csv_fd_ < 0) return io_error(csv + ": cannot create: " + errno_text());
  if (!write_all(w.csv_fd_, kCsvHeader)) return io_error(csv + ": cannot write: " + errno_text());
  w.csv_bytes_ = sizeof kCsvHeader - 1;
  w.text_bytes_ = w.csv_bytes_;
  return w;
}

std::string EurocWriter::frame_path(std::int64_t t_ns) const {
  return cam0_ + "/data/" + std::to_string(t_ns) + ".png";
}

Status EurocWriter::write_calibration(const hal::CameraCalibration& c) {
  const std::string path = cam0_ + "/sensor.yaml";
  const std::string text = euroc_sensor_yaml(c);
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) return io_error(path + ": cannot create: " + errno_text());
  const bool written = std::fwrite(text.data(), 1, text.size(), f) == text.size() && std::fflush(f) == 0;
  const std::string why = written ? std::string() : errno_text();
  if (std::fclose(f) != 0 || !written) return io_error(path + ": cannot write: " + (written ? errno_text() : why));
  text_bytes_ += text.size() - yaml_bytes_;
  yaml_bytes_ = text.size();
  return {};
}

Status EurocWriter::append(std::int64_t t_ns) {
  const std::string csv = cam0_ + "/data.csv";
  if (csv_fd_ < 0) return io_error(csv + ": closed");
  if (last_t_ns_ && t_ns <= *last_t_ns_)
    return invalid_argument(csv + ": timestamp " + std::to_string(t_ns) + " does not follow " +
                            std::to_string(*last_t_ns_));
  const std::string t = std::to_string(t_ns);
  const std::string row = t + "," + t + ".png\n";
  if (!write_all(csv_fd_, row)) {
    const std::string why = errno_text();
    // A partial row would make the list unreadable: back to the last whole one.
    if (::ftruncate(csv_fd_, static_cast<off_t>(csv_bytes_)) == 0)
      (void)::lseek(csv_fd_, static_cast<off_t>(csv_bytes_), SEEK_SET);
    return io_error(csv + ": cannot write: " + why);
  }
  csv_bytes_ += row.size();
  last_t_ns_ = t_ns;
  text_bytes_ += row.size();
  return {};
}

Status EurocWriter::close() {
  if (csv_fd_ < 0) return {};
  const int fd = std::exchange(csv_fd_, -1);
  if (::close(fd) != 0) return io_error(cam0_ + "/data.csv: cannot close: " + errno_text());
  return {};
}

}  // namespace ale::replay
