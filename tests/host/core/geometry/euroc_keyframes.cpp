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
  return Status::ok_status();
}

namespace {

struct Nearest {
  int index = -1;
  int best = std::numeric_limits<int>::max();
  int second = std::numeric_limits<int>::max();
};

Nearest nearest_two(const features::Descriptor& d, const std::vector<features::Descriptor>& to) {
  Nearest n;
  for (std::size_t j = 0; j < to.size(); ++j) {
    const int h = features::hamming_distance(d, to[j]);
    if (h < n.best) {
      n.second = n.best;
      n.best = h;
      n.index = static_cast<int>(j);
    } else if (h < n.second) {
      n.second = h;
    }
  }
  return n;
}

bool passes(const Nearest& n, const MatchParams& p) {
  return n.index >= 0 && n.best <= p.max_distance &&
         (n.second == std::numeric_limits<int>::max() || static_cast<double>(n.best) < p.ratio * n.second);
}

}  // namespace

std::vector<std::pair<int, int>> match_features(const FrameFeatures& a, const FrameFeatures& b, const MatchParams& params) {
  std::vector<int> b_to_a;
  if (params.mutual) {
    b_to_a.resize(b.descriptors.size());
    for (std::size_t j = 0; j < b.descriptors.size(); ++j) b_to_a[j] = nearest_two(b.descriptors[j], a.descriptors).index;
  }
  std::vector<std::pair<int, int>> out;
  for (std::size_t i = 0; i < a.descriptors.size(); ++i) {
    const Nearest n = nearest_two(a.descriptors[i], b.descriptors);
    if (!passes(n, params)) continue;
    if (params.mutual && b_to_a[static_cast<std::size_t>(n.index)] != static_cast<int>(i)) continue;
    out.push_back({static_cast<int>(i), n.index});
  }
  return out;
}

}  // namespace ale::test
