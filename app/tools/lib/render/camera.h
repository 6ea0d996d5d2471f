// The rendered camera: pinhole geometry, its mounting on the sweeper, and the sensor model that
// turns scene radiance into an 8-bit frame (auto-exposure, gain, shot and read noise,
// vignetting, fixed-pattern and row noise, response curve, quantisation, block compression).
// Named sets of the sensor's noise parameters: noise_model.h.
#pragma once

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/base/image.h"
#include "core/base/status.h"
#include "core/geometry/camera.h"

namespace ale::render {

// Pixel (u, v) has its centre at integer coordinates; u right, v down; the camera frame has x
// right, y down, z forward (the EuRoC / OpenCV convention). With distortion the lens is the
// daemon's own camera model (core/geometry/camera.h): radial-tangential (k1 k2 p1 p2) or
// equidistant fisheye (k1..k4); without it, the ideal pinhole.
struct PinholeCamera {
  enum class Distortion { kNone, kRadTan, kEquidistant };

  int width = 640;
  int height = 480;
  double fx = 320.0, fy = 320.0;
  double cx = 319.5, cy = 239.5;
  Distortion distortion = Distortion::kNone;
  std::array<double, 4> coeffs{};  // radtan: k1 k2 p1 p2; equidistant: k1 k2 k3 k4

  // The sweeper's wide lens: focal length half the width (90 degrees across), centred.
  static PinholeCamera wide(int width, int height);
  // A lens by name, scaled to the image size: "ideal" (wide()), "radtan" (a 0.3 MP sweeper
  // module: 88 degrees across, barrel distortion k1 -0.28, principal point off centre) or
  // "fisheye" (equidistant, about 120 degrees across, 150 on the diagonal). kInvalidArgument
  // for another name.
  static Result<PinholeCamera> named(const std::string& lens, int width, int height);

  // The same lens as the daemon's camera model; kInvalidArgument for values it rejects.
  Result<geometry::Camera> lens() const;

  // Image position of camera-frame point p (p.z() > 0); NaN where the lens has none.
  Eigen::Vector2d project(const Eigen::Vector3d& p_c) const;
  // Unit direction, in the camera frame, of the ray through image position (u, v); the zero
  // vector where the lens has no ray (beyond a strong distortion's fold or 90 degrees off axis).
  Eigen::Vector3d ray(double u, double v) const;
};

// Camera orientation in the sweeper's body frame (x forward, y left, z up; origin at the camera's
// optical centre): looking forward, tilted up by `tilt_up_deg`.
Eigen::Matrix3d sweeper_R_bc(double tilt_up_deg);

struct SensorParams {
  double full_well_e = 8000.0;   // electrons at saturation (gain 1)
  double read_noise_e = 2.5;     // rms, referred to the input
  // Electrons per microsecond per unit of scene radiance (albedo x lux).
  double sensitivity = 1.0e-3;
  int min_exposure_us = 10000;   // anti-banding: one half-period of 50 Hz mains light
  int max_exposure_us = 33000;   // also capped at the frame period
  double max_gain = 8.0;         // analogue gain (1 .. max_gain)
  double target_grey = 110.0;    // what the auto-exposure aims the frame's mean grey at
  double ae_time_constant_s = 0.35;  // first-order lag of the auto-exposure
  // Relative illumination over the image: kQuadratic falls with the squared distance from the
  // image centre to `vignetting_corner` in the corners; kCosPower is cos^vignetting_power of the
  // angle between the optical axis and the undistorted pinhole ray through the pixel.
  enum class Vignetting { kQuadratic, kCosPower };
  Vignetting vignetting = Vignetting::kQuadratic;
  double vignetting_corner = 0.62;
  double vignetting_power = 4.0;
  // Fixed-pattern noise, drawn once per sequence (constant over its frames): each pixel's gain
  // is 1 + fpn_gain x N(0,1) (photo-response non-uniformity, a fraction) and it adds an offset of
  // fpn_offset_e x N(0,1) electrons (dark-signal non-uniformity, referred to the input).
  double fpn_gain = 0.0;
  double fpn_offset_e = 0.0;
  // Row noise: every row of a frame gets its own offset, row_noise_e x N(0,1) electrons,
  // redrawn every frame (horizontal banding).
  double row_noise_e = 0.0;
  // JPEG-like compression of the 8-bit frame: 8x8 block DCT quantised at this quality, 1..100
  // (noise_model.h, compress_blocks()); 0 for none.
  int jpeg_quality = 0;
};

struct ExposureState {
  double exposure_us = 20000.0;
  double gain = 1.0;
  double product() const { return exposure_us * gain; }
};

// Radiance image -> 8-bit frame. Holds the tables that depend on the camera and, with
// fixed-pattern noise, the pattern drawn from `fixed_pattern_seed`.
class SensorModel {
 public:
  SensorModel(const SensorParams& params, const PinholeCamera& camera, std::uint64_t fixed_pattern_seed);

  // Exposes `radiance` (width*height values, albedo x lux, row-major) into `out` with noise drawn
  // from `noise_seed` (and compresses it, with jpeg_quality); returns the frame's mean grey.
  double expose(const std::vector<float>& radiance, const ExposureState& exposure, std::uint64_t noise_seed,
                MutableGrayView out) const;
  // Mean grey without noise over every `step`-th pixel (for the exposure search).
  double mean_grey(const std::vector<float>& radiance, const ExposureState& exposure, int step) const;

  // The response curve (sRGB-like: linear toe, then a 1/2.4 power) and its inverse, on [0, 1].
  static double response(double linear);
  static double inverse_response(double encoded);

  const SensorParams& params() const { return params_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  std::uint8_t encode(float linear) const;
  // Photo-electrons of pixel i before noise: vignetting, fixed-pattern gain, the full well.
  float electrons(const std::vector<float>& radiance, std::size_t i, float e_per_radiance) const;

  SensorParams params_;
  int width_;
  int height_;
  std::vector<float> vignetting_;        // per pixel
  std::vector<float> pixel_gain_;        // per pixel, empty without fixed-pattern noise
  std::vector<float> pixel_offset_e_;    // per pixel, empty without fixed-pattern noise
  std::vector<std::uint8_t> response_lut_;  // linear [0, 1] in kLutSize steps -> grey
};

// Auto-exposure with a first-order lag on log(exposure x gain), exposure used before gain.
class AutoExposure {
 public:
  AutoExposure(const SensorParams& params, double fps);

  const ExposureState& state() const { return state_; }
  // The range of exposure x gain the camera can reach, in microseconds.
  double min_product() const { return min_exposure_us_; }
  double max_product() const { return max_exposure_us_ * max_gain_; }

  // Settles on `radiance` as if the camera had been running on that view for a while.
  void settle(const SensorModel& sensor, const std::vector<float>& radiance);
  // One frame later: moves towards the exposure that would bring `mean_grey` to the target.
  void update(double mean_grey);

 private:
  void set_product(double product);

  ExposureState state_;
  double min_exposure_us_;
  double max_exposure_us_;
  double max_gain_;
  double target_linear_;
  double alpha_;  // per-frame step of the lag
};

}  // namespace ale::render
