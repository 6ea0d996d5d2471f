#include "app/tools/lib/render/camera.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "app/tools/lib/render/noise_model.h"
#include "app/tools/lib/render/rng.h"

namespace ale::render {

namespace {
constexpr int kLutSize = 16384;
constexpr double kPi = 3.14159265358979323846;
}  // namespace

PinholeCamera PinholeCamera::wide(int width, int height) {
  PinholeCamera c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = 0.5 * width;
  c.cx = 0.5 * (width - 1);
  c.cy = 0.5 * (height - 1);
  return c;
}

Result<PinholeCamera> PinholeCamera::named(const std::string& lens, int width, int height) {
  PinholeCamera c = wide(width, height);
  if (lens == "ideal") return c;
  c.cx += 0.01 * width;
  c.cy -= 0.008 * height;
  if (lens == "radtan") {
    c.fx = 0.52 * width;
    c.fy = 0.521 * width;
    c.distortion = Distortion::kRadTan;
    c.coeffs = {-0.28, 0.07, 0.0008, -0.0005};
    return c;
  }
  if (lens == "fisheye") {
    c.fx = 0.47 * width;
    c.fy = 0.47 * width;
    c.distortion = Distortion::kEquidistant;
    c.coeffs = {0.02, -0.01, 0.004, -0.001};
    return c;
  }
  return invalid_argument("lens '" + lens + "' is not ideal, radtan or fisheye");
}

Result<geometry::Camera> PinholeCamera::lens() const {
  geometry::CameraIntrinsics k;
  k.model = distortion == Distortion::kEquidistant ? geometry::CameraModel::kEquidistant
                                                   : geometry::CameraModel::kPinholeRadTan;
  k.fx = fx;
  k.fy = fy;
  k.cx = cx;
  k.cy = cy;
  if (distortion != Distortion::kNone) std::copy(coeffs.begin(), coeffs.end(), k.distortion.begin());
  k.width = width;
  k.height = height;
  return geometry::Camera::create(k);
}

Eigen::Vector2d PinholeCamera::project(const Eigen::Vector3d& p_c) const {
  if (distortion == Distortion::kNone) return {fx * p_c.x() / p_c.z() + cx, fy * p_c.y() / p_c.z() + cy};
  const Result<geometry::Camera> cam = lens();
  Eigen::Vector2d uv = Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  if (cam.ok() && !cam->project(p_c, &uv)) uv.setConstant(std::numeric_limits<double>::quiet_NaN());
  return uv;
}

Eigen::Vector3d PinholeCamera::ray(double u, double v) const {
  if (distortion == Distortion::kNone) return Eigen::Vector3d((u - cx) / fx, (v - cy) / fy, 1.0).normalized();
  const Result<geometry::Camera> cam = lens();
  Eigen::Vector3d r;
  if (!cam.ok() || !cam->unproject({u, v}, &r)) return Eigen::Vector3d::Zero();
  return r.normalized();
}

Eigen::Matrix3d sweeper_R_bc(double tilt_up_deg) {
  const double t = tilt_up_deg * kPi / 180.0;
  Eigen::Matrix3d R;
  // Columns: the camera's x (right), y (down) and z (forward, tilted up) axes in the body frame.
  R.col(0) = Eigen::Vector3d(0.0, -1.0, 0.0);
  R.col(1) = Eigen::Vector3d(std::sin(t), 0.0, -std::cos(t));
  R.col(2) = Eigen::Vector3d(std::cos(t), 0.0, std::sin(t));
  return R;
}

double SensorModel::response(double linear) {
  const double x = std::clamp(linear, 0.0, 1.0);
  return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
}

double SensorModel::inverse_response(double encoded) {
  const double y = std::clamp(encoded, 0.0, 1.0);
  return y <= 0.04045 ? y / 12.92 : std::pow((y + 0.055) / 1.055, 2.4);
}

SensorModel::SensorModel(const SensorParams& params, const PinholeCamera& camera, std::uint64_t fixed_pattern_seed)
    : params_(params), width_(camera.width), height_(camera.height) {
  const int width = width_;
  const int height = height_;
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  vignetting_.resize(pixels);
  const double cx = 0.5 * (width - 1);
  const double cy = 0.5 * (height - 1);
  const double r2_corner = cx * cx + cy * cy;
  const bool cos_power = params.vignetting == SensorParams::Vignetting::kCosPower;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      double illumination;
      if (cos_power) {
        // cos^2 of the angle off axis of the pinhole ray through the pixel.
        const double tx = (x - camera.cx) / camera.fx;
        const double ty = (y - camera.cy) / camera.fy;
        illumination = std::pow(1.0 / (1.0 + tx * tx + ty * ty), 0.5 * params.vignetting_power);
      } else {
        // Falls off with the square of the distance from the centre, to `vignetting_corner` in
        // the corners.
        const double r2 = ((x - cx) * (x - cx) + (y - cy) * (y - cy)) / std::max(r2_corner, 1.0);
        illumination = 1.0 - (1.0 - params.vignetting_corner) * r2;
      }
      vignetting_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)] =
          static_cast<float>(illumination);
    }
  if (params.fpn_gain > 0.0 || params.fpn_offset_e > 0.0) {
    SplitMix64 rng(fixed_pattern_seed);
    pixel_gain_.resize(pixels);
    pixel_offset_e_.resize(pixels);
    for (std::size_t i = 0; i < pixels; ++i) {
      pixel_gain_[i] = std::max(0.0f, 1.0f + static_cast<float>(params.fpn_gain) * rng.gaussian());
      pixel_offset_e_[i] = static_cast<float>(params.fpn_offset_e) * rng.gaussian();
    }
  }
  response_lut_.resize(kLutSize + 1);
  for (int i = 0; i <= kLutSize; ++i)
    response_lut_[static_cast<std::size_t>(i)] =
        static_cast<std::uint8_t>(std::lround(255.0 * response(static_cast<double>(i) / kLutSize)));
}

std::uint8_t SensorModel::encode(float linear) const {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  return response_lut_[static_cast<std::size_t>(c * static_cast<float>(kLutSize) + 0.5f)];
}

float SensorModel::electrons(const std::vector<float>& radiance, std::size_t i, float e_per_radiance) const {
  float e = radiance[i] * vignetting_[i] * e_per_radiance;
  if (!pixel_gain_.empty()) e *= pixel_gain_[i];
  return std::min(e, static_cast<float>(params_.full_well_e));
}

double SensorModel::expose(const std::vector<float>& radiance, const ExposureState& exposure,
                           std::uint64_t noise_seed, MutableGrayView out) const {
  SplitMix64 rng(noise_seed);
  // Row offsets from a stream of their own: the pixels' noise is the same with and without.
  SplitMix64 row_rng(mix_seed(noise_seed, 0x526F774E6F697365ULL));
  const auto read_var = static_cast<float>(params_.read_noise_e * params_.read_noise_e);
  const auto row_sigma = static_cast<float>(params_.row_noise_e);
  const auto e_per_radiance = static_cast<float>(params_.sensitivity * exposure.exposure_us);
  const auto to_linear = static_cast<float>(exposure.gain / params_.full_well_e);
  const bool fixed_pattern = !pixel_offset_e_.empty();
  std::uint64_t sum = 0;
  for (int y = 0; y < height_; ++y) {
    const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(width_);
    const float row_offset = row_sigma > 0.0f ? row_sigma * row_rng.gaussian() : 0.0f;
    std::uint8_t* dst = out.row(y);
    for (int x = 0; x < width_; ++x) {
      const std::size_t i = row + static_cast<std::size_t>(x);
      // Photo-electrons (saturating at the full well), then shot and read noise as one Gaussian.
      const float e = electrons(radiance, i, e_per_radiance);
      float noisy = e + std::sqrt(e + read_var) * rng.gaussian();
      if (fixed_pattern) noisy += pixel_offset_e_[i];
      if (row_sigma > 0.0f) noisy += row_offset;
      const std::uint8_t g = encode(noisy * to_linear);
      dst[x] = g;
      sum += g;
    }
  }
  if (params_.jpeg_quality > 0) {
    compress_blocks(out, params_.jpeg_quality);
    sum = 0;
    for (int y = 0; y < height_; ++y)
      for (int x = 0; x < width_; ++x) sum += out.row(y)[x];
  }
  return static_cast<double>(sum) / (static_cast<double>(width_) * static_cast<double>(height_));
}

double SensorModel::mean_grey(const std::vector<float>& radiance, const ExposureState& exposure, int step) const {
  const auto e_per_radiance = static_cast<float>(params_.sensitivity * exposure.exposure_us);
  const auto to_linear = static_cast<float>(exposure.gain / params_.full_well_e);
  std::uint64_t sum = 0;
  std::uint64_t n = 0;
  for (std::size_t i = 0; i < radiance.size(); i += static_cast<std::size_t>(step)) {
    float e = electrons(radiance, i, e_per_radiance);
    if (!pixel_offset_e_.empty()) e += pixel_offset_e_[i];
    sum += encode(e * to_linear);
    ++n;
  }
  return n == 0 ? 0.0 : static_cast<double>(sum) / static_cast<double>(n);
}

AutoExposure::AutoExposure(const SensorParams& params, double fps)
    : min_exposure_us_(params.min_exposure_us),
      max_exposure_us_(std::max<double>(params.min_exposure_us, std::min<double>(params.max_exposure_us, 1e6 / fps))),
      max_gain_(std::max(1.0, params.max_gain)),
      target_linear_(SensorModel::inverse_response(params.target_grey / 255.0)),
      alpha_(1.0 - std::exp(-1.0 / (fps * std::max(1e-3, params.ae_time_constant_s)))) {
  set_product(20000.0);
}

void AutoExposure::set_product(double product) {
  const double p = std::clamp(product, min_product(), max_product());
  state_.exposure_us = std::clamp(p, min_exposure_us_, max_exposure_us_);
  state_.gain = std::clamp(p / state_.exposure_us, 1.0, max_gain_);
}

void AutoExposure::update(double mean_grey) {
  const double measured = std::max(SensorModel::inverse_response(mean_grey / 255.0), 1e-4);
  const double wanted = std::log(state_.product() * target_linear_ / measured);
  const double now = std::log(state_.product());
  set_product(std::exp(now + alpha_ * (wanted - now)));
}

void AutoExposure::settle(const SensorModel& sensor, const std::vector<float>& radiance) {
  // Without lag: a few full steps reach the fixed point (or a limit) from any start.
  for (int i = 0; i < 40; ++i) {
    const double before = state_.product();
    const double mean = sensor.mean_grey(radiance, state_, 7);
    const double measured = std::max(SensorModel::inverse_response(mean / 255.0), 1e-4);
    set_product(before * target_linear_ / measured);
    if (std::fabs(state_.product() / before - 1.0) < 1e-4) break;
  }
}

}  // namespace ale::render
