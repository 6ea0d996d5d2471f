#include "app/daemon/frame_pipeline.h"

#include <cstdio>

#include <cstring>
#include <vector>

#include "app/daemon/log.h"
#include "core/io/file_bytes.h"
#include "core/place/embedded/embedded_vocabulary.h"

namespace ale::app {

Result<ale::geometry::Camera> camera_of(const ale::hal::CameraCalibration& c, int width, int height) {
  ale::geometry::CameraIntrinsics k;
  k.fx = c.fx;
  k.fy = c.fy;
  k.cx = c.cx;
  k.cy = c.cy;
  k.width = width;
  k.height = height;
  switch (c.distortion_model) {
    case ale::hal::DistortionModel::kNone:
      break;
    case ale::hal::DistortionModel::kRadialTangential:  // k1 k2 p1 p2 (k3 = 0)
      k.distortion = {c.distortion[0], c.distortion[1], c.distortion[2], c.distortion[3], 0.0};
      break;
    case ale::hal::DistortionModel::kEquidistant:
      k.model = ale::geometry::CameraModel::kEquidistant;
      k.distortion = {c.distortion[0], c.distortion[1], c.distortion[2], c.distortion[3], 0.0};
      break;
  }
  return ale::geometry::Camera::create(k);
}

Result<std::shared_ptr<const ale::place::Vocabulary>> load_vocabulary(const std::string& setting) {
  if (setting == "none") return std::shared_ptr<const ale::place::Vocabulary>();
  Result<ale::place::Vocabulary> v = ale::place::Vocabulary{};
  if (setting == "builtin" || setting.empty()) {
    v = ale::place::load_embedded_vocabulary();
  } else {
    std::vector<std::uint8_t> bytes;
    const Status read = ale::io::read_file_bytes(setting, bytes);
    if (!read.ok()) return Status(read.code(), "daemon.vocabulary: " + read.message());
    v = ale::place::Vocabulary::parse(bytes.data(), bytes.size());
  }
  if (!v.ok()) return invalid_argument("daemon.vocabulary " + setting + ": " + v.status().message());
  return std::shared_ptr<const ale::place::Vocabulary>(std::make_shared<ale::place::Vocabulary>(std::move(*v)));
}

Status FramePipeline::configure(const DaemonConfig& config, const ale::hal::CameraCalibration& calibration) {
  if (!(calibration.fx > 0.0) || !(calibration.fy > 0.0))
    return invalid_argument("no camera calibration: set camera.calibration_file or camera.intrinsics.fx/fy/cx/cy");
  // No validation here: the configuration's owner checked it (validate_config), and the core checks
  // what it is given once more where it is built (SlamPipeline::create: FramePath::configure and
  // SlamSystem::create), for every caller.
  features_ = config.features;
  features_.mode = config.enhancement.mode;
  Result<std::shared_ptr<const ale::place::Vocabulary>> vocabulary = load_vocabulary(config.daemon.vocabulary);
  if (!vocabulary.ok()) return vocabulary.status();
  vocabulary_ = std::move(*vocabulary);
  slam_ = config.slam;
  calibration_ = calibration;
  map_load_ = config.map.load;
  path_.reset();
  if (calibration.width > 0 && calibration.height > 0) return start(calibration.width, calibration.height);
  return {};
}

Status FramePipeline::start(int width, int height) {
  Result<ale::geometry::Camera> camera = camera_of(calibration_, width, height);
  if (!camera.ok()) return camera.status();
  Result<std::unique_ptr<ale::slam::SlamPipeline>> path = ale::slam::SlamPipeline::create(features_, slam_, *camera, vocabulary_);
  if (!path.ok()) return path.status();
  path_ = std::move(*path);
  path_->record_trajectory(record_trajectory_);
  std::vector<ale::slam::OdometrySample> waiting;
  waiting.swap(odometry_waiting_);
  for (const ale::slam::OdometrySample& sample : waiting) add_odometry(sample);
  if (!map_load_.empty()) load_at_start(map_load_);
  return {};
}

namespace {

void log_loaded(const std::string& path, const ale::io::MapFileSummary& m) {
  log_message(LogLevel::kInfo,
              "map file %s loaded: %d map(s), %d keyframes, %d landmarks, %llu bytes; relocalising in map %u", path.c_str(),
              m.maps, m.keyframes, m.landmarks, static_cast<unsigned long long>(m.bytes), static_cast<unsigned>(m.current_map));
}

}  // namespace

void FramePipeline::load_at_start(const std::string& path) {
  Result<ale::io::MapFileSummary> loaded = path_->load_map(path);
  if (loaded.ok()) {
    log_loaded(path, *loaded);
    return;
  }
  if (loaded.status().code() == StatusCode::kNotFound) {
    log_message(LogLevel::kInfo, "no map file at %s: starting an empty map", path.c_str());
    return;
  }
  // keep the refused file for inspection, out of the way of the next save
  const std::string refused = path + ".refused";
  const bool moved = std::rename(path.c_str(), refused.c_str()) == 0;
  log_message(LogLevel::kError, "map file %s refused: %s; %s", path.c_str(), loaded.status().to_string().c_str(),
              moved ? ("moved to " + refused).c_str() : "left in place (it could not be moved aside)");
  const std::string backup = ale::io::map_file_backup_path(path);
  Result<ale::io::MapFileSummary> from_backup = path_->load_map(backup);
  if (from_backup.ok()) {
    log_message(LogLevel::kWarning, "loading the backup %s instead", backup.c_str());
    log_loaded(backup, *from_backup);
  } else if (from_backup.status().code() == StatusCode::kNotFound) {
    log_message(LogLevel::kError, "no backup %s: starting an empty map", backup.c_str());
  } else {
    log_message(LogLevel::kError, "the backup %s is refused too (%s): starting an empty map", backup.c_str(),
                from_backup.status().to_string().c_str());
  }
}

Result<MapFileDone> FramePipeline::save_map(const std::string& path) {
  if (!path_) return unavailable("no map to save yet: the SLAM core starts with the first frame");
  const std::int64_t start = ale::steady_clock_ns();
  Result<ale::io::MapFileSummary> saved = path_->save_map(path);
  const double ms = static_cast<double>(ale::steady_clock_ns() - start) * 1e-6;
  if (!saved.ok()) {
    log_message(LogLevel::kError, "map not saved to %s: %s", path.c_str(), saved.status().to_string().c_str());
    return saved.status();
  }
  log_message(LogLevel::kInfo, "map saved to %s in %.1f ms: %d map(s), %d keyframes, %d landmarks, %llu bytes",
              path.c_str(), ms, saved->maps, saved->keyframes, saved->landmarks,
              static_cast<unsigned long long>(saved->bytes));
  return MapFileDone{*saved, ms, false};
}

Result<MapFileDone> FramePipeline::load_map(const std::string& path) {
  if (!path_) {
    map_load_ = path;
    log_message(LogLevel::kInfo, "map file %s will be loaded when the SLAM core starts (the first frame)", path.c_str());
    return MapFileDone{{}, 0.0, true};
  }
  const std::int64_t start = ale::steady_clock_ns();
  Result<ale::io::MapFileSummary> loaded = path_->load_map(path);
  const double ms = static_cast<double>(ale::steady_clock_ns() - start) * 1e-6;
  if (!loaded.ok()) {
    log_message(LogLevel::kError, "map file %s not loaded: %s; the map is as it was", path.c_str(),
                loaded.status().to_string().c_str());
    return loaded.status();
  }
  log_loaded(path, *loaded);
  return MapFileDone{*loaded, ms, false};
}

void FramePipeline::add_odometry(const ale::slam::OdometrySample& sample) {
  if (!path_) {
    if (odometry_waiting_.size() >= static_cast<std::size_t>(slam_.odometry.capacity))
      odometry_waiting_.erase(odometry_waiting_.begin());
    odometry_waiting_.push_back(sample);
    return;
  }
  const ale::slam::OdometryCounters before = path_->system().odometry().counters();
  const Status added = path_->add_odometry(sample);
  if (added.ok()) return;
  const ale::slam::OdometryCounters& after = path_->system().odometry().counters();
  const int kind = after.not_finite > before.not_finite         ? 0
                   : after.not_increasing > before.not_increasing ? 1
                   : after.jumps > before.jumps                   ? 2
                                                                  : -1;
  if (kind >= 0 && odometry_logged_[kind]) return;
  if (kind >= 0) odometry_logged_[kind] = true;
  log_message(LogLevel::kWarning, "odometry refused: %s (further ones like it are counted in status, not logged)",
              added.message().c_str());
}

ale::slam::OdometryCounters FramePipeline::odometry_counters() const {
  return path_ ? path_->system().odometry().counters() : ale::slam::OdometryCounters{};
}

Status FramePipeline::set_enhance(const ale::enhance::EnhanceParams& params) {
  if (Status s = ale::enhance::validate(params); !s.ok()) return invalid_argument("features.enhance." + s.message());
  if (path_) ALE_RETURN_IF_ERROR(path_->set_enhance(params));
  features_.enhance = params;  // a path built later (the first frame's size) starts with them
  return {};
}

void FramePipeline::reset_map() {
  if (path_) path_->reset();
}

const std::vector<ale::features::Keypoint>& FramePipeline::keypoints() const {
  static const std::vector<ale::features::Keypoint> kNone;
  return path_ ? path_->keypoints() : kNone;
}

Status FramePipeline::process(const ale::hal::Frame& frame, FrameRecord& record) {
  if (Status s = check_view(frame.image, "frame"); !s.ok()) return frame_rejected(s.message());
  if (!path_) ALE_RETURN_IF_ERROR(start(frame.image.width, frame.image.height));
  ALE_RETURN_IF_ERROR(path_->process({frame.timestamp_ns, frame.sequence}, frame.image));
  const ale::features::ExtractionStats& stats = path_->stats();
  const ale::slam::SlamReport& slam = path_->report();
  if (slam.loop.closed) {
    log_message(LogLevel::kInfo,
                "loop closed at %.2f s: the place of %.2f s seen again (%d inliers); the keyframe moves %.3f map units, "
                "scale %.4f",
                slam.loop.time_s, slam.loop.loop_time_s, slam.loop.inliers, slam.loop.correction, slam.loop.scale);
  } else if (slam.loop.refused) {
    log_message(LogLevel::kInfo, "loop refused at %.2f s: %s", slam.loop.time_s, slam.loop.message.c_str());
  }
  // Map merging reports its counts only: a line for each rise.
  const double frame_s = static_cast<double>(frame.timestamp_ns) * 1e-9;
  if (slam.merges > merges_logged_) {
    log_message(LogLevel::kInfo, "map merged at %.2f s: the current map moved into map %u, an older one (merges %d)",
                frame_s, static_cast<unsigned>(slam.map_id), slam.merges);
  }
  if (slam.merges_refused > merges_refused_logged_) {
    log_message(LogLevel::kInfo, "map merge refused at %.2f s (merges_refused %d)", frame_s, slam.merges_refused);
  }
  merges_logged_ = slam.merges;
  merges_refused_logged_ = slam.merges_refused;
  record.enhance = {};
  record.enhance.brightness = stats.brightness;
  record.enhance.mean = stats.mean;
  record.enhance.sigma = stats.sigma;
  record.enhance.gamma = stats.gamma;
  record.enhance.clip = stats.level[0].clahe_clip;
  record.enhance.negative = stats.negative;
  record.map_reset = slam.map_reset;
  record.resets = slam.resets;
  record.matches = slam.matches;

  record.pose = {};
  record.pose.timestamp_ns = frame.timestamp_ns;
  record.pose.frame_sequence = frame.sequence;
  record.pose.map_id = static_cast<int>(slam.map_id);
  // A pose is published as tracking only when the core found one, and only a finite one.
  record.pose.state = slam.state;
  // the camera's pose from T_cw, when finite
  const auto put_pose = [&record](const ale::geometry::SE3& T_cw) {
    const ale::geometry::SE3 T_wc = T_cw.inverse();
    const Eigen::Vector3d p = T_wc.translation();
    const Eigen::Quaterniond& q = T_wc.so3().quaternion();
    if (!p.allFinite() || !q.coeffs().allFinite()) return false;
    record.pose.p_wc = {p.x(), p.y(), p.z()};
    record.pose.q_wc = {q.w(), q.x(), q.y(), q.z()};
    return true;
  };
  bool posed = false;
  if (slam.has_pose) {
    posed = put_pose(slam.T_cw);
    if (!posed) record.pose.state = TrackingState::kLost;
  } else if (has_pose(slam.state)) {
    record.pose.state = TrackingState::kLost;
  } else {
    posed = slam.odometry_pose && put_pose(slam.T_cw);
  }
  // The wheel odometry's pose, flagged: tracking carried through a frame the camera could not
  // track (state tracking), or a lost frame dead-reckoned (never published as tracking).
  if (posed && slam.odometry_pose) {
    record.pose.odometry_only = true;
    record.pose.position_sigma_m = slam.pose_sigma_m;
  }
  // pose_t's flag for a jump: set on the relocalised frame's pose (a kept one) only.
  record.pose.relocalized = record.pose.state == TrackingState::kRelocalized;
  record.status = {};
  record.status.timestamp_ns = frame.timestamp_ns;
  record.status.state = record.pose.state;
  record.status.brightness = record.enhance.brightness;
  record.status.mean_intensity = static_cast<float>(record.enhance.mean);
  record.status.features = static_cast<int>(path_->keypoints().size());
  record.status.inliers = slam.inliers;
  record.status.message = slam.message;
  record.status.map_id = record.pose.map_id;
  record.status.relocalisations = slam.relocalisations;
  record.status.map_scale = slam.map_scale;
  record.status.odometry_disagreements = static_cast<std::uint64_t>(slam.odometry_disagreements);
  record.status.place_ms = static_cast<float>(static_cast<double>(slam.place_ns) * 1e-6);
  record.status.loops_closed = slam.loops_closed;
  record.status.loops_refused = slam.loops_refused;
  record.status.loop_ms = static_cast<float>(static_cast<double>(slam.loop_ns) * 1e-6);
  record.status.merges = slam.merges;
  record.status.merges_refused = slam.merges_refused;
  record.status.keyframes = static_cast<int>(slam.keyframes);
  record.status.map_points = static_cast<int>(slam.landmarks);
  record.status.timings = path_->timings();
  record.pose.inliers = slam.inliers;
  // The map store's fixed arenas: how full they ever got (the status' pools).
  record.status.add_pool("map_keyframes", slam.keyframes_high_water, slam.keyframe_capacity);
  record.status.add_pool("map_landmarks", slam.landmarks_high_water, slam.landmark_capacity);
  return {};
}

FrameLogRow frame_log_row(const FrameRecord& r) {
  FrameLogRow row;
  row.timestamp_ns = static_cast<std::uint64_t>(r.status.timestamp_ns);  // camera clocks start at >= 0
  row.sequence = r.pose.frame_sequence;
  row.state = r.status.state;
  row.brightness = r.status.brightness;
  row.mean = r.enhance.mean;
  row.sigma = r.enhance.sigma;
  row.gamma = r.enhance.gamma;
  row.clip = r.enhance.clip;
  row.negative = r.enhance.negative;
  row.features = r.status.features;
  row.inliers = r.status.inliers;
  row.frame_time_ms = static_cast<double>(r.status.frame_time_ms);
  row.map_id = static_cast<std::uint64_t>(r.status.map_id);
  row.keyframes = r.status.keyframes;
  row.landmarks = r.status.map_points;
  row.place_ms = static_cast<double>(r.status.place_ms);
  row.loops = r.status.loops_closed;
  row.loop_ms = static_cast<double>(r.status.loop_ms);
  row.merges = r.status.merges;
  row.merges_refused = r.status.merges_refused;
  // The stages by name: the front end's, then the SLAM core's.
  for (std::size_t i = 0; i < r.status.timings.count; ++i) {
    const StageTime& st = r.status.timings.stage[i];
    const double ms = static_cast<double>(st.ns) * 1e-6;
    if (std::strcmp(st.name, ale::slam::SlamPipeline::kTrackStage) == 0) row.tracking_ms += ms;
    else if (std::strcmp(st.name, ale::slam::SlamPipeline::kMapStage) == 0 ||
             std::strcmp(st.name, ale::slam::SlamPipeline::kAdjustStage) == 0)
      row.mapping_ms += ms;
    else row.frontend_ms += ms;
  }
  return row;
}

}  // namespace ale::app
