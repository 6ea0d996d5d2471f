#include "app/tools/lib/render/noise_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace ale::render {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The smaller pixel of `small-pixel` and `harsh`: 0.45 of the standard pixel's area (2.0 um
// against 3.0 um), so 0.45 of the photo-electrons for the same light, about half the charge
// (3500 e-), and a noisier read-out (4 e- against 2.5).
void small_pixel(SensorParams& s) {
  s.full_well_e = 3500.0;
  s.sensitivity = 0.45e-3;
  s.read_noise_e = 4.0;
}

// Fixed-pattern noise of a low-cost CMOS sensor: 1.5 % photo-response non-uniformity and 6 e-
// rms of per-pixel offset (datasheets give 1-2 % and a few e- at short exposures).
void fixed_pattern(SensorParams& s) {
  s.fpn_gain = 0.015;
  s.fpn_offset_e = 6.0;
}

// The natural vignetting of a simple wide lens: cos^4 of the angle off axis (0.15 in the corners
// of the 90-degree lens, against the standard model's 0.62).
void cos4(SensorParams& s) {
  s.vignetting = SensorParams::Vignetting::kCosPower;
  s.vignetting_power = 4.0;
}

// Row noise above the pixels' read noise (3 e- against 2.5): plainly visible banding in the
// dark, a stress for a detector rather than a typical sensor's 0.2-0.5 x read noise.
void banding(SensorParams& s) { s.row_noise_e = 3.0; }

// libjpeg's default quality.
void jpeg(SensorParams& s) { s.jpeg_quality = 75; }

// The orthonormal 8-point DCT-II basis: kBasis[u][x].
std::array<std::array<double, 8>, 8> make_basis() {
  std::array<std::array<double, 8>, 8> b{};
  for (int u = 0; u < 8; ++u)
    for (int x = 0; x < 8; ++x)
      b[static_cast<std::size_t>(u)][static_cast<std::size_t>(x)] =
          (u == 0 ? std::sqrt(1.0 / 8.0) : std::sqrt(2.0 / 8.0)) * std::cos((2 * x + 1) * u * kPi / 16.0);
  return b;
}

}  // namespace

const std::vector<std::string>& noise_model_names() {
  static const std::vector<std::string> names = {"standard", "small-pixel", "fpn", "vignetting",
                                                 "banding",  "jpeg",        "harsh"};
  return names;
}

Status apply_noise_model(const std::string& name, SensorParams& s) {
  // Back to the standard model's values (SensorParams' defaults), then the model's changes.
  const SensorParams standard;
  s.full_well_e = standard.full_well_e;
  s.sensitivity = standard.sensitivity;
  s.read_noise_e = standard.read_noise_e;
  s.vignetting = standard.vignetting;
  s.vignetting_corner = standard.vignetting_corner;
  s.vignetting_power = standard.vignetting_power;
  s.fpn_gain = standard.fpn_gain;
  s.fpn_offset_e = standard.fpn_offset_e;
  s.row_noise_e = standard.row_noise_e;
  s.jpeg_quality = standard.jpeg_quality;
  if (name == "standard") return {};
  if (name == "small-pixel") small_pixel(s);
  else if (name == "fpn") fixed_pattern(s);
  else if (name == "vignetting") cos4(s);
  else if (name == "banding") banding(s);
  else if (name == "jpeg") jpeg(s);
  else if (name == "harsh") {
    small_pixel(s);
    fixed_pattern(s);
    cos4(s);
    banding(s);
    jpeg(s);
  } else {
    std::string known;
    for (const std::string& n : noise_model_names()) known += (known.empty() ? "" : ", ") + n;
    return invalid_argument("noise model '" + name + "' is not one of " + known);
  }
  return {};
}

Status validate_noise(const SensorParams& s) {
  auto outside = [](const char* what, double v, double lo, double hi) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s %g outside %g..%g", what, v, lo, hi);
    return invalid_argument(buf);
  };
  if (!(s.full_well_e >= 500.0 && s.full_well_e <= 200000.0)) return outside("full well (e-)", s.full_well_e, 500, 200000);
  if (!(s.read_noise_e >= 0.0 && s.read_noise_e <= 100.0)) return outside("read noise (e-)", s.read_noise_e, 0, 100);
  if (!(s.vignetting_corner > 0.0 && s.vignetting_corner <= 1.0))
    return outside("vignetting in the corners", s.vignetting_corner, 0, 1);
  if (!(s.vignetting_power >= 0.0 && s.vignetting_power <= 8.0))
    return outside("vignetting power", s.vignetting_power, 0, 8);
  if (!(s.fpn_gain >= 0.0 && s.fpn_gain <= 0.5)) return outside("fixed-pattern gain (fraction)", s.fpn_gain, 0, 0.5);
  if (!(s.fpn_offset_e >= 0.0 && s.fpn_offset_e <= 500.0))
    return outside("fixed-pattern offset (e-)", s.fpn_offset_e, 0, 500);
  if (!(s.row_noise_e >= 0.0 && s.row_noise_e <= 500.0)) return outside("row noise (e-)", s.row_noise_e, 0, 500);
  if (s.jpeg_quality < 0 || s.jpeg_quality > 100) return outside("JPEG quality", s.jpeg_quality, 0, 100);
  return {};
}

std::string describe_noise(const std::string& name, const SensorParams& s) {
  char buf[768];
  char vignetting[96];
  if (s.vignetting == SensorParams::Vignetting::kCosPower)
    std::snprintf(vignetting, sizeof vignetting, "cos^%g of the angle off axis", s.vignetting_power);
  else
    std::snprintf(vignetting, sizeof vignetting, "quadratic, %g in the corners", s.vignetting_corner);
  std::snprintf(buf, sizeof buf,
                "noise model: %s\n"
                "full well: %g e-\n"
                "sensitivity: %g e- per us per albedo-lux\n"
                "read noise: %g e- rms\n"
                "vignetting: %s\n"
                "fixed-pattern gain: %g %% rms\n"
                "fixed-pattern offset: %g e- rms\n"
                "row noise: %g e- rms per row and frame\n"
                "jpeg quality: %d%s\n",
                name.c_str(), s.full_well_e, s.sensitivity, s.read_noise_e, vignetting, 100.0 * s.fpn_gain,
                s.fpn_offset_e, s.row_noise_e, s.jpeg_quality, s.jpeg_quality == 0 ? " (none)" : "");
  return buf;
}

int block_step(int u, int v, int quality) {
  const int q = std::clamp(quality, 1, 100);
  const double scale = q < 50 ? 50.0 / q : 2.0 - q / 50.0;
  return std::max(1, static_cast<int>(std::lround(scale * (12.0 + 7.0 * (u + v)))));
}

void compress_blocks(MutableGrayView image, int quality) {
  static const std::array<std::array<double, 8>, 8> basis = make_basis();
  std::array<std::array<int, 8>, 8> step{};
  for (int u = 0; u < 8; ++u)
    for (int v = 0; v < 8; ++v) step[static_cast<std::size_t>(u)][static_cast<std::size_t>(v)] = block_step(u, v, quality);
  double block[8][8];
  double tmp[8][8];
  for (int by = 0; by < image.height; by += 8)
    for (int bx = 0; bx < image.width; bx += 8) {
      for (int y = 0; y < 8; ++y) {
        const std::uint8_t* src = image.row(std::min(by + y, image.height - 1));
        for (int x = 0; x < 8; ++x) block[y][x] = src[std::min(bx + x, image.width - 1)] - 128.0;
      }
      // Forward: coefficients F[v][u] = sum_y sum_x basis[v][y] basis[u][x] f[y][x].
      for (int y = 0; y < 8; ++y)
        for (int u = 0; u < 8; ++u) {
          double acc = 0.0;
          for (int x = 0; x < 8; ++x) acc += basis[static_cast<std::size_t>(u)][static_cast<std::size_t>(x)] * block[y][x];
          tmp[y][u] = acc;
        }
      for (int v = 0; v < 8; ++v)
        for (int u = 0; u < 8; ++u) {
          double acc = 0.0;
          for (int y = 0; y < 8; ++y) acc += basis[static_cast<std::size_t>(v)][static_cast<std::size_t>(y)] * tmp[y][u];
          const double q = step[static_cast<std::size_t>(u)][static_cast<std::size_t>(v)];
          block[v][u] = std::nearbyint(acc / q) * q;
        }
      // Inverse: f[y][x] = sum_v sum_u basis[v][y] basis[u][x] F[v][u].
      for (int v = 0; v < 8; ++v)
        for (int x = 0; x < 8; ++x) {
          double acc = 0.0;
          for (int u = 0; u < 8; ++u) acc += basis[static_cast<std::size_t>(u)][static_cast<std::size_t>(x)] * block[v][u];
          tmp[v][x] = acc;
        }
      for (int y = 0; y < 8 && by + y < image.height; ++y) {
        std::uint8_t* dst = image.row(by + y);
        for (int x = 0; x < 8 && bx + x < image.width; ++x) {
          double acc = 0.0;
          for (int v = 0; v < 8; ++v) acc += basis[static_cast<std::size_t>(v)][static_cast<std::size_t>(y)] * tmp[v][x];
          dst[bx + x] = static_cast<std::uint8_t>(std::clamp(std::lround(acc + 128.0), 0L, 255L));
        }
      }
    }
}

}  // namespace ale::render
