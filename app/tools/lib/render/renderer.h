// Ray casting the room into a radiance image, and whole sequences: trajectory, light profile,
// auto-exposure and sensor noise, frame after frame.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <vector>

#include "core/base/image.h"
#include "core/base/status.h"
#include "app/tools/lib/render/camera.h"
#include "app/tools/lib/render/lighting.h"
#include "app/tools/lib/render/scene.h"
#include "app/tools/lib/render/trajectory.h"

namespace ale::render {

// Casts one ray per sub-pixel (supersample x supersample per pixel, on a regular grid) with
// per-pixel ray directions computed once. Textures are filtered for each ray's footprint.
class Renderer {
 public:
  Renderer(const Scene& scene, const PinholeCamera& camera, int supersample);

  // Scene radiance (albedo x lux, plus glowing lamps) averaged over each pixel, for a camera at
  // R_wc, p_wc; `out` is resized to width*height.
  void render(const Eigen::Matrix3d& R_wc, const Eigen::Vector3d& p_wc, const LightState& light,
              std::vector<float>& out) const;

  const PinholeCamera& camera() const { return camera_; }

 private:
  float shade(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float angle, const LightState& light) const;

  const Scene& scene_;
  PinholeCamera camera_;
  int supersample_;
  std::vector<Eigen::Vector3f> rays_c_;  // unit directions in the camera frame, pixel-major
  std::vector<float> ray_angle_;         // angular size of each ray's share of a pixel, rad
};

// All light off from start_s for duration_s (seconds on the frames' clock: from the first
// frame's timestamp, gaps included): lamps, the light left when they are off and the sun; the
// sensor sees only its own noise.
struct Blackout {
  double start_s = 0.0;
  double duration_s = 0.0;
};

// When the trajectory's time reaches at_s, the camera jumps to the trajectory's pose at to_s
// (a place already seen: to_s < at_s) and drives on from there; the frames' timestamps go on
// after gap_s seconds without frames.
struct Kidnap {
  double at_s = 0.0;
  double to_s = 0.0;
  double gap_s = 0.0;
};

struct SequenceConfig {
  PinholeCamera camera = PinholeCamera::wide(640, 480);
  SensorParams sensor;
  LightProfile light = LightProfile::kNormal;
  double fps = 30.0;
  int frames = 300;
  std::uint64_t seed = 1;
  int supersample = 2;
  double start_s = 0.0;  // where on the trajectory frame 0 is taken
  std::vector<Blackout> blackouts;
  std::vector<Kidnap> kidnaps;  // in the order they happen
};

// One rendered frame's facts.
struct FrameRecord {
  int index = 0;
  double t_s = 0.0;  // on the trajectory (start_s for frame 0)
  // Time without frames before this frame (the kidnaps' gaps so far): its timestamp is
  // index / fps + gap_ns after frame 0's.
  std::int64_t gap_ns = 0;
  bool blackout = false;  // the light was off (a Blackout)
  Pose body;         // world pose of the body at t_s
  Pose camera;       // world pose of the camera at t_s (the body's through the rig): q_wc, p_wc
  LightState light;
  ExposureState exposure;  // used for this frame
  double mean_grey = 0.0;
};

// Renders a sequence frame by frame, in order (the auto-exposure carries from one frame to the
// next). The same inputs and seed give the same frames, bit for bit.
class SequenceRenderer {
 public:
  // The trajectory must last at least start_s + (frames - 1) / fps.
  static Result<SequenceRenderer> create(const Scene& scene, const Trajectory& trajectory, const Rig& rig,
                                         const SequenceConfig& config);

  int frames() const { return config_.frames; }
  int next_index() const { return next_; }
  // Renders the next frame into `out` (camera size); kEndOfStream after the last.
  Status render_next(MutableGrayView out, FrameRecord& record);
  // The camera pose (R_wc, p_wc) at time t_s.
  void camera_pose(double t_s, Eigen::Matrix3d& R_wc, Eigen::Vector3d& p_wc) const;

 private:
  SequenceRenderer(const Scene& scene, const Trajectory& trajectory, const Rig& rig, const SequenceConfig& config);

  const Trajectory* trajectory_;
  Rig rig_;
  SequenceConfig config_;
  Renderer renderer_;
  SensorModel sensor_;
  AutoExposure ae_;
  std::vector<float> radiance_;
  int next_ = 0;
  std::size_t next_kidnap_ = 0;
  double jumped_s_ = 0.0;  // added to the trajectory's time by the kidnaps so far
  std::int64_t gap_ns_ = 0;
};

}  // namespace ale::render
