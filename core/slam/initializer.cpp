#include "core/slam/initializer.h"

#include <algorithm>
#include <cmath>

#include "core/base/median.h"
#include "core/geometry/chi_square.h"
#include "core/optim/bundle_adjuster.h"

namespace ale::slam {

namespace {
void make_reference(const Frame& frame, Frame& reference, std::vector<std::pair<float, float>>& predicted) {
  reference.timestamp_s = frame.timestamp_s;
  reference.sequence = frame.sequence;
  reference.features = frame.features;
  reference.index(frame.grid.bounds());
  predicted.clear();
  for (const map::KeyframeFeature& f : reference.features) predicted.emplace_back(f.u, f.v);
}
}  // namespace

InitReport Initializer::add_frame(Frame& frame, map::MapStore& map, map::KeyframeId* first, map::KeyframeId* second) {
  InitReport report;
  if (frame.size() <= params_.min_features) {
    has_reference_ = false;
    report.message = "initialiser: " + std::to_string(frame.size()) + " keypoints, more than " +
                     std::to_string(params_.min_features) + " needed";
    return report;
  }
  if (!has_reference_ || frame.timestamp_s - reference_.timestamp_s > params_.max_reference_age_s ||
      frame.timestamp_s <= reference_.timestamp_s) {
    make_reference(frame, reference_, predicted_);
    has_reference_ = true;
    report.state = InitState::kWaiting;
    report.message = "initialiser: new reference frame";
    return report;
  }
  report.state = InitState::kWaiting;
  report.matches = search_for_initialization({pinhole_, pyramid_, matcher_, matcher_scratch_}, reference_.view(),
                                             frame.view(), predicted_, params_.window_px, matches_);
  if (report.matches < params_.min_matches) {
    // ORB-SLAM starts over from the next frame: the reference no longer overlaps enough
    has_reference_ = false;
    report.state = InitState::kNeedReference;
    report.message = "initialiser: " + std::to_string(report.matches) + " matches to the reference, " +
                     std::to_string(params_.min_matches) + " needed";
    return report;
  }
  x1_.clear();
  x2_.clear();
  match_index_.clear();
  for (int i = 0; i < reference_.size(); ++i) {
    const int j = matches_[static_cast<std::size_t>(i)];
    if (j < 0) continue;
    const map::KeyframeFeature& a = reference_.features[static_cast<std::size_t>(i)];
    const map::KeyframeFeature& b = frame.features[static_cast<std::size_t>(j)];
    predicted_[static_cast<std::size_t>(i)] = {b.u, b.v};
    x1_.emplace_back(a.u, a.v);
    x2_.emplace_back(b.u, b.v);
    match_index_.push_back(i);
  }
  if (params_.probe_samples > 0 && params_.probe_samples < params_.two_view.ransac.max_iterations) {
    geometry::TwoViewParams quick = params_.two_view;
    quick.ransac.max_iterations = params_.probe_samples;
    const Status probe =
        geometry::reconstruct_two_view(x1_, x2_, pinhole_.intrinsics(), quick, &two_view_, two_view_scratch_);
    const double floor_deg = params_.probe_parallax_share * params_.two_view.min_parallax_deg;
    if (!probe.ok() && two_view_.failure == geometry::TwoViewFailure::kLowParallax &&
        two_view_.parallax_deg < floor_deg) {
      report.model = two_view_.model;
      report.failure = two_view_.failure;
      report.message = "initialiser: quick look (" + std::to_string(params_.probe_samples) + " samples): " +
                       probe.message() + ", under " + std::to_string(floor_deg) + " deg";
      return report;
    }
  }
  const Status st = geometry::reconstruct_two_view(x1_, x2_, pinhole_.intrinsics(), params_.two_view, &two_view_,
                                                   two_view_scratch_);
  report.model = two_view_.model;
  report.failure = two_view_.failure;
  if (!st.ok()) {
    report.message = "initialiser: " + st.message();
    return report;
  }
  const Status made = create_map(frame, map, first, second, report);
  if (!made.ok()) {
    report.message = "initialiser: " + made.message();
    return report;
  }
  report.state = InitState::kInitialized;
  has_reference_ = false;
  return report;
}

Status Initializer::create_map(Frame& frame, map::MapStore& map, map::KeyframeId* first, map::KeyframeId* second,
                               InitReport& report) {
  const geometry::SE3 T_1w;  // the first keyframe defines the map frame
  const geometry::SE3 T_2w(geometry::SO3::from_matrix(two_view_.R_21), two_view_.t_21);
  Result<map::KeyframeId> k1 =
      map.add_keyframe(reference_.timestamp_s, reference_.sequence, T_1w, reference_.features.data(), reference_.size());
  if (!k1.ok()) return k1.status();
  Result<map::KeyframeId> k2 = map.add_keyframe(frame.timestamp_s, frame.sequence, T_2w, frame.features.data(), frame.size());
  if (!k2.ok()) {
    map.erase_keyframe(*k1);
    return k2.status();
  }
  std::vector<map::LandmarkId> created;
  std::vector<std::pair<int, int>> keypoints;  // (reference index, frame index) per landmark
  for (std::size_t m = 0; m < match_index_.size(); ++m) {
    if (!two_view_.valid[m]) continue;
    const int i = match_index_[m];
    const int j = matches_[static_cast<std::size_t>(i)];
    Result<map::LandmarkId> lm = map.add_landmark(two_view_.points_1[m], reference_.features[static_cast<std::size_t>(i)].descriptor, *k1);
    if (!lm.ok()) break;  // the map is full: keep what fits
    if (!map.add_observation(*lm, *k1, i).ok() || !map.add_observation(*lm, *k2, j).ok()) {
      map.erase_landmark(*lm);
      continue;
    }
    created.push_back(*lm);
    keypoints.emplace_back(i, j);
  }

  // Two-keyframe bundle adjustment, the first keyframe fixed (ORB-SLAM's global BA, 20 iterations).
  MapBundleAdjustment& ba = ba_;
  ba.reset(map);
  ba.add_keyframe(*k1, true);
  ba.add_keyframe(*k2, false);
  for (map::LandmarkId l : created) ba.add_landmark(l);  // observed by k1, then k2
  optim::BaOptions options;
  options.lm.max_iterations = params_.ba_iterations;
  options.passes = 1;
  const optim::BaSummary summary = ba.solve(options);
  auto discard = [&](const std::string& why) {
    for (map::LandmarkId l : created) map.erase_landmark(l);
    map.erase_keyframe(*k2);
    map.erase_keyframe(*k1);
    return invalid_argument(why);
  };
  if (!MapBundleAdjustment::usable(summary)) return discard("initial bundle adjustment: " + summary.status.message());

  // Landmarks BA could not explain go; the rest take the refined positions.
  std::vector<double> depths;
  std::size_t kept = 0;
  for (std::size_t n = 0; n < created.size(); ++n) {
    const bool inlier = ba.is_inlier(static_cast<int>(2 * n)) && ba.is_inlier(static_cast<int>(2 * n + 1));
    const geometry::Vec3 p = ba.point(static_cast<int>(n));
    if (!inlier || !p.allFinite() || p.z() <= 0.0) {
      map.erase_landmark(created[n]);
      continue;
    }
    map.landmark(created[n])->p_w = p;
    depths.push_back(p.z());
    created[kept] = created[n];
    keypoints[kept] = keypoints[n];
    ++kept;
  }
  created.resize(kept);
  keypoints.resize(kept);
  if (static_cast<int>(kept) < params_.min_map_points || depths.empty()) {
    return discard(std::to_string(kept) + " landmarks after bundle adjustment, " +
                   std::to_string(params_.min_map_points) + " needed");
  }
  const double median_depth = median_in_place(depths);
  if (!(median_depth > 0.0)) return discard("median depth is not positive");
  const double scale = 1.0 / median_depth;
  const geometry::SE3 T_2w_ba = ba.pose(1);
  const geometry::SE3 T_2w_scaled(T_2w_ba.so3(), T_2w_ba.translation() * scale);
  map.keyframe(*k2)->T_cw = T_2w_scaled;
  for (map::LandmarkId l : created) {
    map::Landmark* lm = map.landmark(l);
    lm->p_w *= scale;
    map.update_descriptor(l);
    map.update_normal_and_depth(l, pyramid_.scale, pyramid_.levels);
  }
  map.update_connections(*k1);
  map.update_connections(*k2);

  frame.T_cw = T_2w_scaled;
  frame.has_pose = true;
  std::fill(frame.landmarks.begin(), frame.landmarks.end(), map::LandmarkId{});
  std::fill(frame.outlier.begin(), frame.outlier.end(), std::uint8_t{0});
  for (std::size_t n = 0; n < created.size(); ++n) {
    frame.landmarks[static_cast<std::size_t>(keypoints[n].second)] = created[n];
  }
  report.landmarks = static_cast<int>(created.size());
  *first = *k1;
  *second = *k2;
  return Status::ok_status();
}

namespace {
constexpr ConfigField kInitializerFields[] = {
    number<&InitializerParams::min_features>("min_features", 8, 100000, "keypoints a reference frame needs"),
    number<&InitializerParams::min_matches>("min_matches", 8, 100000, "matches to the reference to try a reconstruction"),
    number<&InitializerParams::min_map_points>("min_map_points", 8, 100000, "landmarks the first map needs after BA"),
    number<&InitializerParams::ba_iterations>("ba_iterations", 0, 1000, "iterations of the two-keyframe BA"),
    number<&InitializerParams::max_reference_age_s>("max_reference_age_s", 0.01, 1000,
                                                     "a reference frame older than this is replaced"),
    number<&InitializerParams::probe_samples>("probe_samples", 0, 100000,
                                               "RANSAC samples of a quick look before each full try (0: none)"),
    number<&InitializerParams::probe_parallax_share>("probe_parallax_share", 0, 1,
                                                      "the full try is skipped below this share of the minimum parallax"),
};
}  // namespace

extern constexpr ConfigTable kInitializerConfig = table_of<InitializerParams>(kInitializerFields);

}  // namespace ale::slam
