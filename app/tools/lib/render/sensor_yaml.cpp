#include "app/tools/lib/render/sensor_yaml.h"

#include <cstdio>
#include <fstream>
#include <sstream>

namespace ale::render {

namespace {

std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.12g", v == 0.0 ? 0.0 : v);  // no "-0"
  return buf;
}

}  // namespace

std::string sensor_yaml_text(const PinholeCamera& c, double rate_hz, const Rig& rig, const std::string& comment,
                             const std::string& notes) {
  std::ostringstream y;
  y << "%YAML:1.0\n# General sensor definitions.\nsensor_type: camera\ncomment: " << comment << "\n";
  if (!notes.empty()) {
    std::istringstream lines(notes);
    for (std::string line; std::getline(lines, line);) y << "# " << line << "\n";
  }
  y << "\n# Sensor extrinsics wrt. the body-frame.\nT_BS:\n  cols: 4\n  rows: 4\n  data: [";
  for (int r = 0; r < 4; ++r) {
    for (int k = 0; k < 4; ++k) {
      const double v = r == 3 ? (k == 3 ? 1.0 : 0.0) : (k < 3 ? rig.R_bc(r, k) : rig.t_bc(r));
      y << num(v) << (k < 3 ? ", " : "");
    }
    if (r < 3) y << ",\n         ";
  }
  y << "]\n\n# Camera specific definitions.\n";
  if (rate_hz > 0.0) y << "rate_hz: " << num(rate_hz) << "\n";
  y << "resolution: [" << c.width << ", " << c.height << "]\ncamera_model: pinhole\n";
  y << "intrinsics: [" << num(c.fx) << ", " << num(c.fy) << ", " << num(c.cx) << ", " << num(c.cy)
    << "] #fu, fv, cu, cv\n";
  const bool fisheye = c.distortion == PinholeCamera::Distortion::kEquidistant;
  y << "distortion_model: " << (fisheye ? "equidistant" : "radial-tangential") << "\ndistortion_coefficients: [";
  for (std::size_t i = 0; i < c.coeffs.size(); ++i) {
    const double v = c.distortion == PinholeCamera::Distortion::kNone ? 0.0 : c.coeffs[i];
    y << num(v) << (i + 1 < c.coeffs.size() ? ", " : "");
  }
  y << (fisheye ? "] #k1, k2, k3, k4\n" : "] #k1, k2, p1, p2\n");
  return y.str();
}

Status write_text_file(const std::string& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  if (!f) return io_error(path + ": cannot open for writing");
  f << text;
  f.close();
  if (!f) return io_error(path + ": write failed");
  return {};
}

}  // namespace ale::render
