#include "core/slam/match/base.h"

#include <algorithm>
#include <cmath>

namespace ale::slam {

bool project_pinhole(const geometry::Camera& pinhole, const geometry::Vec3& p_c, float* u, float* v) {
  geometry::Vec2 uv;
  if (!pinhole.project(p_c, &uv)) return false;
  *u = static_cast<float>(uv.x());
  *v = static_cast<float>(uv.y());
  return true;
}

namespace detail {

void add_rotation(std::vector<std::vector<int>>& bin_storage, float angle1_deg, float angle2_deg, int item) {
  const int bins = static_cast<int>(bin_storage.size());
  float rot = angle1_deg - angle2_deg;
  if (rot < 0.0f) rot += 360.0f;
  int bin = static_cast<int>(std::lround(rot * static_cast<float>(bins) / 360.0f));
  if (bin >= bins) bin = 0;
  if (bin < 0) bin = 0;
  bin_storage[static_cast<std::size_t>(bin)].push_back(item);
}

void strongest_rotation_bins(const std::vector<std::vector<int>>& bin_storage, int kept[3]) {
  int* m = kept;
  m[0] = m[1] = m[2] = -1;
  std::size_t c[3] = {0, 0, 0};
  for (int i = 0; i < static_cast<int>(bin_storage.size()); ++i) {
    const std::size_t s = bin_storage[static_cast<std::size_t>(i)].size();
    if (s > c[0]) {
      c[2] = c[1]; m[2] = m[1];
      c[1] = c[0]; m[1] = m[0];
      c[0] = s; m[0] = i;
    } else if (s > c[1]) {
      c[2] = c[1]; m[2] = m[1];
      c[1] = s; m[1] = i;
    } else if (s > c[2]) {
      c[2] = s; m[2] = i;
    }
  }
  if (c[1] * 10 < c[0]) m[1] = m[2] = -1;
  else if (c[2] * 10 < c[0]) m[2] = -1;
}

}  // namespace detail

int drop_inconsistent_rotations(const FrameFeatures& first, const FrameFeatures& second, int bins,
                                std::vector<int>& matches12, std::vector<std::vector<int>>& bin_storage) {
  return drop_inconsistent_rotations(first, second, bins, matches12, bin_storage, [](int, int) {});
}

int list_matched_pairs(const FrameFeatures& first, const FrameFeatures& second, const RotationCheck& rotation,
                       MatcherScratch& scratch, std::vector<std::pair<int, int>>& pairs) {
  if (rotation.enabled) drop_inconsistent_rotations(first, second, rotation.bins, scratch.matched, scratch.bins);
  for (int i = 0; i < first.count; ++i) {
    const int j = scratch.matched[static_cast<std::size_t>(i)];
    if (j != kNoMatch) pairs.emplace_back(i, j);
  }
  return static_cast<int>(pairs.size());
}

bool landmark_in_view(const map::Landmark& lm, const geometry::SE3& T_cw, const geometry::Vec3& centre_w,
                      const geometry::Camera& pinhole, const ImageBounds& bounds, const ScalePyramid& pyramid,
                      LandmarkView* view) {
  geometry::Vec2 uv;
  if (!pinhole.project(T_cw * lm.p_w, &uv)) return false;
  const float u = static_cast<float>(uv.x()), v = static_cast<float>(uv.y());
  if (!bounds.contains(u, v)) return false;
  const geometry::Vec3 ray = lm.p_w - centre_w;
  const float dist = static_cast<float>(ray.norm());
  if (dist < 0.8f * lm.min_distance || dist > 1.2f * lm.max_distance) return false;
  const double view_cos = ray.dot(lm.normal) / std::max(static_cast<double>(dist), 1e-12);
  if (view_cos < 0.5) return false;
  view->uv = uv;
  view->u = u;
  view->v = v;
  view->distance = dist;
  view->view_cos = view_cos;
  view->level = pyramid.predict_level(dist, lm.max_distance);
  return true;
}

namespace {
constexpr ConfigField kRotationFields[] = {
    flag<&RotationCheck::enabled>("enabled", "drop matches outside the three strongest bins of orientation change"),
    number<&RotationCheck::bins>("bins", 1, 360, "bins of the orientation-change histogram over 360 deg"),
};
constexpr ConfigField kMatcherFields[] = {
    number<&MatcherParams::th_high>("th_high", 0, 256, "Hamming gate of the projection searches (of 256 bits)"),
    number<&MatcherParams::th_low>("th_low", 0, 256, "Hamming gate of initialisation, triangulation and fusion"),
    number<&MatcherParams::ratio_initialization>("ratio_initialization", 0.01, 1,
                                                  "nearest / second nearest at most, initialisation search"),
    number<&MatcherParams::ratio_projection>("ratio_projection", 0.01, 1,
                                              "nearest / second nearest at most when both are on one level, projection searches"),
    number<&MatcherParams::ratio_bow>("ratio_bow", 0.01, 1, "nearest / second nearest at most, bag-of-words search"),
    number<&MatcherParams::ratio_triangulation>("ratio_triangulation", 0.01, 1,
                                                 "the epipolar match against candidates at another depth (1: off)"),
    number<&MatcherParams::ratio_separation>("ratio_separation", 0, 100,
                                              "x the level's scale: candidates farther along the line are another depth"),
    number<&MatcherParams::initialization_max_level>("initialization_max_level", 0, ScalePyramid::kMaxLevels - 1,
                                                      "reference keypoints up to this level take part in initialisation"),
    nested<&MatcherParams::rotation>("rotation", kRotationCheckConfig),
};
}  // namespace

extern constexpr ConfigTable kRotationCheckConfig = table_of<RotationCheck>(kRotationFields);
extern constexpr ConfigTable kMatcherConfig = table_of<MatcherParams>(kMatcherFields);

}  // namespace ale::slam
