#include "app/tools/lib/render/renderer.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "app/tools/lib/render/noise_model.h"
#include "app/tools/lib/render/rng.h"

namespace ale::render {

Renderer::Renderer(const Scene& scene, const PinholeCamera& camera, int supersample)
    : scene_(scene), camera_(camera), supersample_(std::clamp(supersample, 1, 4)) {
  const int ss = supersample_;
  const std::size_t n = static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height) *
                        static_cast<std::size_t>(ss * ss);
  rays_c_.reserve(n);
  ray_angle_.reserve(n);
  const double f = std::sqrt(camera.fx * camera.fy);
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x)
      for (int j = 0; j < ss; ++j)
        for (int i = 0; i < ss; ++i) {
          const double u = x + (i + 0.5) / ss - 0.5;
          const double v = y + (j + 0.5) / ss - 0.5;
          const Eigen::Vector3d r = camera.ray(u, v);
          rays_c_.push_back(r.cast<float>());
          // A pixel subtends cos^2/f radially and cos/f tangentially; their geometric mean.
          ray_angle_.push_back(static_cast<float>(std::pow(r.z(), 1.5) / (f * ss)));
        }
}

float Renderer::shade(const Eigen::Vector3f& origin, const Eigen::Vector3f& dir, float angle,
                      const LightState& light) const {
  Hit hit;
  // A zero direction: the lens has no ray there (camera.h), the pixel stays black.
  if (angle <= 0.0f || !cast_ray(scene_, origin, dir, hit)) return 0.0f;
  const Eigen::Vector3f p = origin + hit.t * dir;
  const int axis = hit.face / 2;
  const bool at_max = (hit.face & 1) != 0;
  const bool room = hit.box < 0;
  const Box* box = room ? nullptr : &scene_.boxes[static_cast<std::size_t>(hit.box)];
  // Normal towards the viewer: inward for the room, outward for boxes.
  Eigen::Vector3f n = Eigen::Vector3f::Zero();
  n[axis] = (at_max != room) ? 1.0f : -1.0f;

  const int tex = room ? scene_.room_texture[static_cast<std::size_t>(hit.face)]
                       : box->texture[static_cast<std::size_t>(hit.face)];
  float albedo = 0.0f;
  if (tex >= 0) {
    const Eigen::Vector3f lo = room ? Eigen::Vector3f::Zero() : box->lo;
    const Eigen::Vector3f hi = room ? scene_.size : box->hi;
    const Eigen::Vector2f uv = face_uv(lo, hi, hit.face, room, p);
    const float cos_incidence = std::max(std::fabs(dir[axis]), 0.02f);
    const float footprint = hit.t * angle / std::sqrt(cos_incidence);
    albedo = scene_.textures[static_cast<std::size_t>(tex)].sample(uv.x(), uv.y(), footprint);
  }
  float irradiance;
  float emitted = 0.0f;
  if (light.lamps_on) {
    const float direct = scene_.lamp_normaliser * scene_.lamp_factor(p, n);
    irradiance = light.room_lux * (scene_.ambient_fraction + (1.0f - scene_.ambient_fraction) * direct);
    if (box != nullptr) emitted = box->emission[static_cast<std::size_t>(hit.face)] * light.room_lux;
  } else {
    irradiance = light.off_lux;
  }
  if (room && hit.face == kMinZ && light.sun_lux > 0.0f) irradiance += light.sun_lux * scene_.sun_weight(p.x(), p.y());
  return albedo * irradiance + emitted;
}

void Renderer::render(const Eigen::Matrix3d& R_wc, const Eigen::Vector3d& p_wc, const LightState& light,
                      std::vector<float>& out) const {
  const Eigen::Matrix3f R = R_wc.cast<float>();
  const Eigen::Vector3f o = p_wc.cast<float>();
  const int per_pixel = supersample_ * supersample_;
  const float inv = 1.0f / static_cast<float>(per_pixel);
  const std::size_t pixels = static_cast<std::size_t>(camera_.width) * static_cast<std::size_t>(camera_.height);
  out.resize(pixels);
  std::size_t r = 0;
  for (std::size_t i = 0; i < pixels; ++i) {
    float sum = 0.0f;
    for (int k = 0; k < per_pixel; ++k, ++r) sum += shade(o, R * rays_c_[r], ray_angle_[r], light);
    out[i] = sum * inv;
  }
}

SequenceRenderer::SequenceRenderer(const Scene& scene, const Trajectory& trajectory, const Rig& rig,
                                   const SequenceConfig& config)
    : trajectory_(&trajectory),
      rig_(rig),
      config_(config),
      renderer_(scene, config.camera, config.supersample),
      // The fixed pattern belongs to the sensor: one draw per sequence, from a stream apart from
      // the frames' noise (mix_seed(seed, k) for frame k).
      sensor_(config.sensor, config.camera, mix_seed(config.seed, 0x46697865645061ULL)),
      ae_(config.sensor, config.fps) {}

Result<SequenceRenderer> SequenceRenderer::create(const Scene& scene, const Trajectory& trajectory, const Rig& rig,
                                                  const SequenceConfig& config) {
  const PinholeCamera& c = config.camera;
  if (c.width < 8 || c.height < 8 || c.width > 8192 || c.height > 8192)
    return invalid_argument("render: image size " + std::to_string(c.width) + "x" + std::to_string(c.height) +
                            " outside 8..8192");
  if (!(c.fx > 0.0) || !(c.fy > 0.0)) return invalid_argument("render: focal lengths must be positive");
  if (!(config.fps > 0.0 && config.fps <= 1000.0))
    return invalid_argument("render: fps " + std::to_string(config.fps) + " outside (0, 1000]");
  if (config.frames < 1) return invalid_argument("render: frames must be at least 1");
  if (config.supersample < 1 || config.supersample > 4) return invalid_argument("render: supersample must be 1..4");
  const SensorParams& s = config.sensor;
  if (!(s.full_well_e > 0) || !(s.sensitivity > 0) || s.min_exposure_us <= 0 || s.max_exposure_us < s.min_exposure_us ||
      !(s.max_gain >= 1.0) || !(s.target_grey > 0 && s.target_grey < 255))
    return invalid_argument("render: sensor parameters out of range");
  if (const Status noise = validate_noise(s); !noise.ok()) return invalid_argument("render: " + noise.message());
  if (trajectory.empty()) return invalid_argument("render: empty trajectory");
  for (const Blackout& b : config.blackouts)
    if (!(b.start_s >= 0.0) || !(b.duration_s > 0.0) || !std::isfinite(b.start_s + b.duration_s))
      return invalid_argument("render: a blackout needs a start >= 0 s and a duration > 0 s");
  double earliest_s = config.start_s;
  for (const Kidnap& k : config.kidnaps) {
    if (!(k.to_s >= 0.0) || !(k.at_s > k.to_s) || !(k.gap_s >= 0.0) || !std::isfinite(k.at_s + k.gap_s))
      return invalid_argument("render: a kidnap needs 0 <= to < at and a gap >= 0 s (at " + std::to_string(k.at_s) +
                              ", to " + std::to_string(k.to_s) + ", gap " + std::to_string(k.gap_s) + ")");
    // Each kidnap must come after the place the previous one left the camera.
    if (!(k.at_s > earliest_s))
      return invalid_argument("render: a kidnap at " + std::to_string(k.at_s) + " s comes before " +
                              std::to_string(earliest_s) + " s on the trajectory (the start or the previous kidnap's place)");
    earliest_s = k.to_s;
  }
  if (!(config.start_s >= 0.0)) return invalid_argument("render: start time must be >= 0");
  const double needed = config.start_s + (config.frames - 1) / config.fps;
  if (trajectory.duration_s() + 1e-9 < needed)
    return invalid_argument("render: trajectory lasts " + std::to_string(trajectory.duration_s()) + " s but " +
                            std::to_string(config.frames) + " frames at " + std::to_string(config.fps) +
                            " fps need " + std::to_string(needed) + " s");
  return SequenceRenderer(scene, trajectory, rig, config);
}

void SequenceRenderer::camera_pose(double t_s, Eigen::Matrix3d& R_wc, Eigen::Vector3d& p_wc) const {
  const Pose body = trajectory_->at(t_s);
  const Eigen::Matrix3d R_wb = body.q_wb.toRotationMatrix();
  R_wc = R_wb * rig_.R_bc;
  p_wc = body.p_wb + R_wb * rig_.t_bc;
}

Status SequenceRenderer::render_next(MutableGrayView out, FrameRecord& record) {
  if (next_ >= config_.frames) return end_of_stream("render: all " + std::to_string(config_.frames) + " frames done");
  if (out.data == nullptr || out.width != config_.camera.width || out.height != config_.camera.height)
    return invalid_argument("render: output view is " + std::to_string(out.width) + "x" + std::to_string(out.height) +
                            ", the camera " + std::to_string(config_.camera.width) + "x" +
                            std::to_string(config_.camera.height));
  const double drive_s = config_.start_s + next_ / config_.fps;
  while (next_kidnap_ < config_.kidnaps.size() && drive_s + jumped_s_ >= config_.kidnaps[next_kidnap_].at_s) {
    const Kidnap& k = config_.kidnaps[next_kidnap_++];
    jumped_s_ += k.to_s - k.at_s;
    gap_ns_ += std::llround(k.gap_s * 1e9);
  }
  const double t = drive_s + jumped_s_;
  const double fraction = config_.frames > 1 ? static_cast<double>(next_) / (config_.frames - 1) : 0.0;
  Eigen::Matrix3d R_wc;
  Eigen::Vector3d p_wc;
  camera_pose(t, R_wc, p_wc);
  LightState light = light_at(config_.light, fraction);
  const double clock_s = next_ / config_.fps + 1e-9 * static_cast<double>(gap_ns_);
  const bool blackout = std::any_of(config_.blackouts.begin(), config_.blackouts.end(), [&](const Blackout& b) {
    return clock_s >= b.start_s && clock_s < b.start_s + b.duration_s;
  });
  if (blackout) {
    light.lamps_on = false;
    light.off_lux = 0.0f;
    light.sun_lux = 0.0f;
  }
  renderer_.render(R_wc, p_wc, light, radiance_);
  // The camera was running before the first frame: start settled on that view.
  if (next_ == 0) ae_.settle(sensor_, radiance_);
  record.index = next_;
  record.t_s = t;
  record.gap_ns = gap_ns_;
  record.blackout = blackout;
  record.body = trajectory_->at(t);
  record.camera.q_wb = Eigen::Quaterniond(R_wc).normalized();
  record.camera.p_wb = p_wc;
  record.light = light;
  record.exposure = ae_.state();
  record.mean_grey = sensor_.expose(radiance_, record.exposure,
                                    mix_seed(config_.seed, static_cast<std::uint64_t>(next_)), out);
  ae_.update(record.mean_grey);
  ++next_;
  return {};
}

}  // namespace ale::render
