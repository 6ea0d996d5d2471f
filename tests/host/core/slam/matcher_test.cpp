#include "core/slam/matcher.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tests/host/core/slam/synthetic_scene.h"

namespace ale::slam {
namespace {

using test::Scene;

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
