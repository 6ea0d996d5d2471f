#include "core/slam/matcher.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/base/rng.h"

namespace ale::slam {
namespace {

using geometry::SE3;
using geometry::SO3;
using geometry::Vec3;

features::Descriptor random_descriptor(SplitMix64& g) {
  features::Descriptor d;
  for (auto& b : d.bytes) b = static_cast<std::uint8_t>(g.next());
  return d;
}

features::Descriptor perturbed(features::Descriptor d, SplitMix64& g, int flips) {
  for (int i = 0; i < flips; ++i) {
    const std::uint32_t bit = g.below(256);
    d.bytes[bit / 8] = static_cast<std::uint8_t>(d.bytes[bit / 8] ^ (1u << (bit % 8)));
  }
  return d;
}

geometry::Camera pinhole() {
  geometry::CameraIntrinsics k;
  k.fx = 458.0;
  k.fy = 457.0;
  k.cx = 367.0;
  k.cy = 248.0;
  k.width = 752;
  k.height = 480;
  return *geometry::Camera::create(k);
}

// Points in front of two cameras 0.3 m apart, each seen by both with its own descriptor noise,
// plus unrelated keypoints in each frame.
struct Scene {
  geometry::Camera cam = pinhole();
  ScalePyramid pyr = ScalePyramid::make(8, 1.2f);
  SE3 T1w, T2w;
  std::vector<Vec3> points;
  std::vector<features::Descriptor> truth;
  std::vector<map::KeyframeFeature> f1, f2;
  std::vector<int> point_of_f1, point_of_f2;  // -1 for distractors
  FeatureGrid g1, g2;
  ImageBounds bounds{0.0f, 0.0f, 752.0f, 480.0f};

  explicit Scene(std::uint64_t seed, int n = 300, int distractors = 100) {
    SplitMix64 g(seed);
    T1w = SE3();
    T2w = SE3(SO3::exp(Vec3(0.0, 0.05, 0.0)), Vec3(-0.3, 0.0, 0.02));
    for (int i = 0; i < n; ++i) {
      const Vec3 p(g.uniform_double() * 4.0 - 2.0, g.uniform_double() * 2.4 - 1.2, 2.0 + g.uniform_double() * 4.0);
      points.push_back(p);
      truth.push_back(random_descriptor(g));
    }
    observe(T1w, f1, point_of_f1, g, distractors);
    observe(T2w, f2, point_of_f2, g, distractors);
    g1.build(f1.data(), static_cast<int>(f1.size()), bounds);
    g2.build(f2.data(), static_cast<int>(f2.size()), bounds);
  }

  void observe(const SE3& T, std::vector<map::KeyframeFeature>& f, std::vector<int>& owner, SplitMix64& g,
               int distractors) {
    for (std::size_t i = 0; i < points.size(); ++i) {
      geometry::Vec2 uv;
      if (!cam.project(T * points[i], &uv) || !bounds.contains(static_cast<float>(uv.x()), static_cast<float>(uv.y()))) continue;
      map::KeyframeFeature k;
      k.u = static_cast<float>(uv.x() + (g.uniform_double() - 0.5));
      k.v = static_cast<float>(uv.y() + (g.uniform_double() - 0.5));
      k.level = 0;
      k.angle_deg = 40.0f;
      k.descriptor = perturbed(truth[i], g, 8);
      f.push_back(k);
      owner.push_back(static_cast<int>(i));
    }
    for (int i = 0; i < distractors; ++i) {
      map::KeyframeFeature k;
      k.u = static_cast<float>(g.uniform_double() * 751.0);
      k.v = static_cast<float>(g.uniform_double() * 479.0);
      k.angle_deg = static_cast<float>(g.uniform_double() * 360.0);
      k.descriptor = random_descriptor(g);
      f.push_back(k);
      owner.push_back(-1);
    }
  }
  FrameFeatures view1() const { return {f1.data(), static_cast<int>(f1.size()), &g1}; }
  FrameFeatures view2() const { return {f2.data(), static_cast<int>(f2.size()), &g2}; }
};

TEST(FeatureGrid, QueryFindsExactlyTheFeaturesInTheSquare) {
  Scene s(1);
  std::vector<int> got;
  s.g1.query(300.0f, 200.0f, 40.0f, 0, -1, got);
  std::vector<int> want;
  for (std::size_t i = 0; i < s.f1.size(); ++i) {
    if (std::fabs(s.f1[i].u - 300.0f) <= 40.0f && std::fabs(s.f1[i].v - 200.0f) <= 40.0f) want.push_back(static_cast<int>(i));
  }
  EXPECT_EQ(got, want);
  EXPECT_FALSE(want.empty());
}

TEST(ScalePyramid, PredictsTheLevelFromTheDistance) {
  const ScalePyramid p = ScalePyramid::make(8, 1.2f);
  EXPECT_EQ(p.predict_level(10.0f, 10.0f), 0);
  // 1.2^1 < 1.3 <= 1.2^2: the second level (ORB-SLAM rounds the octave up)
  EXPECT_EQ(p.predict_level(10.0f / 1.3f, 10.0f), 2);
  EXPECT_EQ(p.predict_level(10.0f / 1.1f, 10.0f), 1);
  EXPECT_EQ(p.predict_level(0.001f, 10.0f), 7);
  EXPECT_EQ(p.predict_level(20.0f, 10.0f), 0);
  EXPECT_NEAR(p.scale[2], 1.44f, 1e-6f);
  EXPECT_NEAR(p.sigma2[2], 1.44f * 1.44f, 1e-6f);
}

TEST(Matcher, InitializationSearchFindsTrueMatches) {
  Scene s(2);
  std::vector<std::pair<float, float>> predicted;
  for (const auto& k : s.f1) predicted.emplace_back(k.u, k.v);
  std::vector<int> m;
  MatcherScratch scratch;
  const int n = search_for_initialization(s.view1(), s.view2(), predicted, 100.0f, MatcherParams{}, m, scratch);
  int correct = 0, wrong = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    if (m[i] < 0) continue;
    (s.point_of_f1[i] >= 0 && s.point_of_f1[i] == s.point_of_f2[static_cast<std::size_t>(m[i])]) ? ++correct : ++wrong;
  }
  EXPECT_EQ(correct + wrong, n);
  EXPECT_GT(correct, 150);
  EXPECT_LE(wrong, 2);
  // one-to-one
  std::vector<int> used(s.f2.size(), 0);
  for (int j : m) {
    if (j >= 0) {
      EXPECT_EQ(++used[static_cast<std::size_t>(j)], 1);
    }
  }
}

TEST(Matcher, ProjectionSearchMatchesLandmarksAtTheirPixels) {
  Scene s(3);
  map::MapStore store(map::MapCapacity{2, 1000, 1000});
  const map::KeyframeId kf = *store.add_keyframe(0.0, 0, s.T1w, s.f1.data(), static_cast<int>(s.f1.size()));
  std::vector<map::LandmarkId> ids;
  for (std::size_t i = 0; i < s.f1.size(); ++i) {
    if (s.point_of_f1[i] < 0) continue;
    const map::LandmarkId id = *store.add_landmark(s.points[static_cast<std::size_t>(s.point_of_f1[i])], s.f1[i].descriptor, kf);
    ASSERT_TRUE(store.add_observation(id, kf, static_cast<int>(i)).ok());
    const float scales[8] = {1.0f, 1.2f, 1.44f, 1.728f, 2.0736f, 2.48832f, 2.985984f, 3.5831808f};
    store.update_normal_and_depth(id, scales, 8);
    ids.push_back(id);
  }
  std::vector<map::LandmarkId> frame_lms(s.f2.size());
  MatcherScratch scratch;
  const int n = search_by_projection(s.view2(), s.T2w, s.cam, store, ids, s.pyr, 1.0f, MatcherParams{}, frame_lms, scratch);
  int correct = 0;
  for (std::size_t i = 0; i < frame_lms.size(); ++i) {
    const map::Landmark* lm = store.landmark(frame_lms[i]);
    if (!lm) continue;
    ASSERT_GE(s.point_of_f2[i], 0) << "matched a distractor";
    if ((lm->p_w - s.points[static_cast<std::size_t>(s.point_of_f2[i])]).norm() < 1e-12) ++correct;
  }
  EXPECT_GT(n, 150);
  EXPECT_EQ(correct, n);
  // a second search adds nothing: every landmark found is skipped
  EXPECT_EQ(search_by_projection(s.view2(), s.T2w, s.cam, store, ids, s.pyr, 1.0f, MatcherParams{}, frame_lms, scratch), 0);
}

TEST(Matcher, TriangulationSearchPairsAlongEpipolarLines) {
  Scene s(4);
  std::vector<std::pair<int, int>> pairs;
  MatcherScratch scratch;
  const int n = search_for_triangulation(s.view1(), s.T1w, nullptr, s.view2(), s.T2w, nullptr, s.cam, s.pyr, MatcherParams{},
                                         pairs, scratch);
  int correct = 0;
  for (auto [a, b] : pairs) {
    if (s.point_of_f1[static_cast<std::size_t>(a)] >= 0 &&
        s.point_of_f1[static_cast<std::size_t>(a)] == s.point_of_f2[static_cast<std::size_t>(b)]) {
      ++correct;
    }
  }
  EXPECT_EQ(n, static_cast<int>(pairs.size()));
  EXPECT_GT(correct, 150);
  EXPECT_GE(correct, n - 2);
}

TEST(Matcher, SearchesAreDeterministic) {
  Scene a(5), b(5);
  std::vector<std::pair<int, int>> pa, pb;
  MatcherScratch sa, sb;
  search_for_triangulation(a.view1(), a.T1w, nullptr, a.view2(), a.T2w, nullptr, a.cam, a.pyr, MatcherParams{}, pa, sa);
  search_for_triangulation(b.view1(), b.T1w, nullptr, b.view2(), b.T2w, nullptr, b.cam, b.pyr, MatcherParams{}, pb, sb);
  EXPECT_EQ(pa, pb);
}

}  // namespace
}  // namespace ale::slam
