#include "tests/host/core/geometry/euroc_keyframes.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "core/base/image.h"
#include "core/features/undistort.h"
#include "hal/replay/dataset.h"
#include "core/io/image_io.h"

namespace ale::test {

using geometry::Mat3;
using geometry::Vec2;
using geometry::Vec3;

namespace {

constexpr std::int64_t kMaxGtGapNs = 1000000;  // 1 ms

// "1403715273262142976_0.jpg" -> 1403715273262142976.
bool timestamp_from_name(const std::string& stem, std::int64_t* t_ns) {
  const std::string digits = stem.substr(0, stem.find('_'));
  const std::optional<std::int64_t> v = replay::parse_integer_ns(digits);
  if (!v) return false;
  *t_ns = *v;
  return true;
}

}  // namespace

Status load_euroc_keyframes(const std::string& keyframes_dir, const std::string& sensor_yaml, EurocKeyframes* out) {
  namespace fs = std::filesystem;
  *out = EurocKeyframes{};
  const Result<hal::CameraCalibration> calib = replay::read_euroc_sensor_yaml(sensor_yaml);
  if (!calib.ok()) return calib.status();
  if (calib->distortion_model != hal::DistortionModel::kRadialTangential)
    return invalid_argument(sensor_yaml + ": expected radial-tangential distortion");
  geometry::CameraIntrinsics& cam = out->camera;
  cam.model = geometry::CameraModel::kPinholeRadTan;
  cam.fx = calib->fx;
  cam.fy = calib->fy;
  cam.cx = calib->cx;
  cam.cy = calib->cy;
  cam.distortion = {calib->distortion[0], calib->distortion[1], calib->distortion[2], calib->distortion[3], 0.0};
  cam.width = calib->width;
  cam.height = calib->height;
  out->pinhole = cam;
  out->pinhole.distortion = {};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) out->T_bc.R(r, c) = calib->T_BS[static_cast<std::size_t>(4 * r + c)];
    out->T_bc.t(r) = calib->T_BS[static_cast<std::size_t>(4 * r + 3)];
  }

  const Result<std::vector<replay::GroundTruthState>> gt =
      replay::read_euroc_groundtruth(keyframes_dir + "/gt_openvins_v101_at_keyframes.csv");
  if (!gt.ok()) return gt.status();
  if (gt->empty()) return corrupt_data(keyframes_dir + ": empty ground truth");

  const std::string cam_dir = keyframes_dir + "/cam0";
  std::error_code ec;
  std::vector<fs::path> images;
  for (fs::directory_iterator it(cam_dir, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string ext = it->path().extension().string();
    if (ext == ".jpg" || ext == ".png") images.push_back(it->path());
  }
  if (ec || images.empty()) return not_found(cam_dir + ": no images");
  std::sort(images.begin(), images.end());

  for (const fs::path& p : images) {
    EurocKeyframe f;
    f.image_path = p.string();
    if (!timestamp_from_name(p.stem().string(), &f.timestamp_ns))
      return corrupt_data(f.image_path + ": file name is not a nanosecond timestamp");
    // Nearest ground-truth row (the CSV is sorted by time).
    const auto later = std::lower_bound(gt->begin(), gt->end(), f.timestamp_ns,
                                        [](const replay::GroundTruthState& s, std::int64_t t) { return s.timestamp_ns < t; });
    std::int64_t best_gap = std::numeric_limits<std::int64_t>::max();
    const replay::GroundTruthState* best = nullptr;
    for (auto it = later == gt->begin() ? later : later - 1; it != gt->end() && it <= later; ++it) {
      const std::int64_t gap = std::llabs(it->timestamp_ns - f.timestamp_ns);
      if (gap < best_gap) {
        best_gap = gap;
        best = &*it;
      }
    }
    if (best == nullptr || best_gap > kMaxGtGapNs)
      return corrupt_data(f.image_path + ": no ground-truth row within 1 ms");
    const Eigen::Quaterniond q(best->q_wb_wxyz[0], best->q_wb_wxyz[1], best->q_wb_wxyz[2], best->q_wb_wxyz[3]);
    f.T_wb.R = q.normalized().toRotationMatrix();
    f.T_wb.t = Vec3(best->p_wb[0], best->p_wb[1], best->p_wb[2]);
    f.T_wc = f.T_wb * out->T_bc;
    out->frames.push_back(std::move(f));
  }
  return Status::ok_status();
}

RigidPose relative_pose(const EurocKeyframes& kf, int i, int j) {
  return kf.frames[static_cast<std::size_t>(j)].T_wc.inverse() * kf.frames[static_cast<std::size_t>(i)].T_wc;
}

features::ExtractorConfig default_keyframe_extractor() { return features::ExtractorConfig{}; }

Status extract_keyframe(const EurocKeyframes& kf, int index, frontend::FramePath& extractor, FrameFeatures* out) {
  if (index < 0 || index >= static_cast<int>(kf.frames.size()))
    return invalid_argument("extract_keyframe: index " + std::to_string(index) + " out of range");
  const EurocKeyframe& f = kf.frames[static_cast<std::size_t>(index)];
  GrayImage image;
  ALE_RETURN_IF_ERROR(io::read_gray(f.image_path, image));
  ALE_RETURN_IF_ERROR(extractor.extract(image.view(), out->keypoints, out->descriptors));
  const Result<geometry::Camera> camera = geometry::Camera::create(kf.camera);
  if (!camera.ok()) return camera.status();
  features::undistort_keypoints(*camera, out->keypoints, out->undistorted_px, out->undistorted_valid);
  out->slam_features.resize(out->keypoints.size());
  for (std::size_t i = 0; i < out->keypoints.size(); ++i) {
    map::KeyframeFeature& sf = out->slam_features[i];
    const bool valid = out->undistorted_valid[i] != 0;
    sf.u = valid ? static_cast<float>(out->undistorted_px[i].x()) : std::numeric_limits<float>::quiet_NaN();
    sf.v = valid ? static_cast<float>(out->undistorted_px[i].y()) : std::numeric_limits<float>::quiet_NaN();
    sf.angle_deg = out->keypoints[i].angle_deg;
    sf.level = static_cast<std::int16_t>(out->keypoints[i].level);
    sf.descriptor = out->descriptors[i];
  }
  return Status::ok_status();
}

Status extract_all_keyframes(const EurocKeyframes& kf, std::vector<FrameFeatures>* out) {
  frontend::FramePath extractor;
  ALE_RETURN_IF_ERROR(extractor.configure(default_keyframe_extractor()));
  out->assign(kf.frames.size(), FrameFeatures{});
  for (std::size_t i = 0; i < kf.frames.size(); ++i)
    ALE_RETURN_IF_ERROR(extract_keyframe(kf, static_cast<int>(i), extractor, &(*out)[i]));
  return Status::ok_status();
}

std::vector<std::pair<int, int>> match_features(const FrameFeatures& a, const FrameFeatures& b,
                                                const slam::PairSearchParams& params) {
  std::vector<std::pair<int, int>> out;
  slam::MatcherScratch scratch;
  slam::match_all_pairs(a.view(), b.view(), params, out, scratch);
  return out;
}

void matched_pixels(const FrameFeatures& a, const FrameFeatures& b, const std::vector<std::pair<int, int>>& matches,
                    std::vector<Vec2>* x1, std::vector<Vec2>* x2) {
  x1->clear();
  x2->clear();
  for (const auto& [ia, ib] : matches) {
    const auto ua = static_cast<std::size_t>(ia);
    const auto ub = static_cast<std::size_t>(ib);
    if (!a.undistorted_valid[ua] || !b.undistorted_valid[ub]) continue;
    x1->push_back(a.undistorted_px[ua]);
    x2->push_back(b.undistorted_px[ub]);
  }
}

std::vector<std::pair<int, int>> match_along_epipolar_lines(const FrameFeatures& a, const FrameFeatures& b,
                                                            const Mat3& F_21) {
  slam::EpipolarBandParams params;
  params.match.rotation.enabled = false;
  std::vector<std::pair<int, int>> out;
  slam::MatcherScratch scratch;
  slam::match_along_epipolar_lines(a.view(), b.view(), F_21, params, out, scratch);
  return out;
}

std::vector<KeyframePair> select_pairs(const EurocKeyframes& kf, const std::vector<FrameFeatures>& features,
                                       const PairSelection& selection, PairCounts* counts) {
  std::vector<KeyframePair> pairs;
  *counts = PairCounts{};
  const int frames = static_cast<int>(std::min(kf.frames.size(), features.size()));
  for (int gap = 1; gap <= 2; ++gap) {
    for (int i = 0; i + gap < frames; ++i) {
      ++counts->considered;
      KeyframePair pair;
      pair.i = i;
      pair.j = i + gap;
      pair.T_ji = relative_pose(kf, pair.i, pair.j);
      const double baseline = pair.T_ji.t.norm();
      if (baseline < selection.min_baseline_m || baseline > selection.max_baseline_m ||
          rotation_error_deg(Mat3::Identity(), pair.T_ji.R) > selection.max_rotation_deg) {
        ++counts->skipped_gt;
        continue;
      }
      const FrameFeatures& a = features[static_cast<std::size_t>(pair.i)];
      const FrameFeatures& b = features[static_cast<std::size_t>(pair.j)];
      matched_pixels(a, b, match_features(a, b, selection.match), &pair.x1, &pair.x2);
      if (static_cast<int>(pair.x1.size()) < selection.min_matches) {
        ++counts->skipped_matches;
        continue;
      }
      pairs.push_back(std::move(pair));
    }
  }
  return pairs;
}

Status load_keyframe_pairs(const std::string& keyframes_dir, const std::string& sensor_yaml,
                           const PairSelection& selection, EurocKeyframes* kf, std::vector<FrameFeatures>* features,
                           std::vector<KeyframePair>* pairs, PairCounts* counts) {
  ALE_RETURN_IF_ERROR(load_euroc_keyframes(keyframes_dir, sensor_yaml, kf));
  ALE_RETURN_IF_ERROR(extract_all_keyframes(*kf, features));
  *pairs = select_pairs(*kf, *features, selection, counts);
  return Status::ok_status();
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t k = static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(k, v.size() - 1)];
}

}  // namespace ale::test
