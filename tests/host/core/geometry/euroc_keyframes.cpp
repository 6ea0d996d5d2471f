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

Status extract_all_keyframes(const EurocKeyframes& kf, std::vector<FrameFeatures>* out) {
  frontend::FramePath extractor;
  ALE_RETURN_IF_ERROR(extractor.configure(default_keyframe_extractor()));
  out->assign(kf.frames.size(), FrameFeatures{});
  for (std::size_t i = 0; i < kf.frames.size(); ++i)
    ALE_RETURN_IF_ERROR(extract_keyframe(kf, static_cast<int>(i), extractor, &(*out)[i]));
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

Mat3 fundamental_from_pose(const geometry::CameraIntrinsics& pinhole, const Mat3& R_21, const Vec3& t_21) {
  Mat3 K_inv = Mat3::Identity();
  K_inv(0, 0) = 1.0 / pinhole.fx;
  K_inv(1, 1) = 1.0 / pinhole.fy;
  K_inv(0, 2) = -pinhole.cx / pinhole.fx;
  K_inv(1, 2) = -pinhole.cy / pinhole.fy;
  return K_inv.transpose() * geometry::hat(t_21) * R_21 * K_inv;
}

std::vector<std::pair<int, int>> match_along_epipolar_lines(const FrameFeatures& a, const FrameFeatures& b,
                                                            const Mat3& F_21, const GuidedMatchParams& params) {
  const std::size_t na = a.descriptors.size();
  const std::size_t nb = b.descriptors.size();
  // Squared distance of b's keypoint to a's epipolar line in image b, against the gate of the
  // coarser level.
  std::vector<Vec3> lines(na);
  for (std::size_t i = 0; i < na; ++i) {
    if (!a.undistorted_valid[i]) continue;
    const Vec3 l = F_21 * a.undistorted_px[i].homogeneous();
    const double norm = l.head<2>().norm();
    lines[i] = norm > 0.0 ? Vec3(l / norm) : Vec3::Zero();
  }
  const auto candidate = [&](std::size_t i, std::size_t j) {
    if (!a.undistorted_valid[i] || !b.undistorted_valid[j] || lines[i].isZero()) return false;
    const int la = a.keypoints[i].level;
    const int lb = b.keypoints[j].level;
    if (std::abs(la - lb) > params.max_level_diff) return false;
    const double sigma = params.sigma_px * std::pow(1.2, std::max(la, lb));
    const double d = lines[i].dot(b.undistorted_px[j].homogeneous());
    return d * d <= params.chi2 * sigma * sigma;
  };
  // The nearest and second-nearest candidate of each keypoint, both ways.
  std::vector<Nearest> a_to_b(na), b_to_a(nb);
  for (std::size_t i = 0; i < na; ++i) {
    for (std::size_t j = 0; j < nb; ++j) {
      if (!candidate(i, j)) continue;
      const int h = features::hamming_distance(a.descriptors[i], b.descriptors[j]);
      for (auto [n, index] : {std::pair<Nearest*, int>{&a_to_b[i], static_cast<int>(j)},
                              std::pair<Nearest*, int>{&b_to_a[j], static_cast<int>(i)}}) {
        if (h < n->best) {
          n->second = n->best;
          n->best = h;
          n->index = index;
        } else if (h < n->second) {
          n->second = h;
        }
      }
    }
  }
  std::vector<std::pair<int, int>> out;
  for (std::size_t i = 0; i < na; ++i) {
    const Nearest& n = a_to_b[i];
    if (!passes(n, params.match)) continue;
    if (params.match.mutual && b_to_a[static_cast<std::size_t>(n.index)].index != static_cast<int>(i)) continue;
    out.push_back({static_cast<int>(i), n.index});
  }
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
