#include "core/slam/matcher.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/geometry/two_view.h"
#include "core/slam/pair_reconstruction.h"
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

// A decoy with f1's own descriptor on the epipolar line, where the ray's point would be 100 m
// away: beyond the depth the triangulation can use (max_depth), the search must not look there.
TEST(Matcher, TriangulationSearchStopsAtTheMaximumDepth) {
  Scene s(6);
  const std::size_t real2 = s.f2.size();
  std::vector<int> decoy_of(s.f1.size(), -1);
  const geometry::SE3 T21 = s.T2w * s.T1w.inverse();
  int decoys = 0;
  for (std::size_t i = 0; i < s.f1.size() && decoys < 30; ++i) {
    if (s.point_of_f1[i] < 0) continue;
    const geometry::Vec3 ray((s.f1[i].u - s.cam.intrinsics().cx) / s.cam.intrinsics().fx,
                             (s.f1[i].v - s.cam.intrinsics().cy) / s.cam.intrinsics().fy, 1.0);
    geometry::Vec2 uv;
    if (!s.cam.project(T21 * (100.0 * ray), &uv) || !s.bounds.contains(static_cast<float>(uv.x()), static_cast<float>(uv.y()))) continue;
    map::KeyframeFeature d = s.f1[i];
    d.u = static_cast<float>(uv.x());
    d.v = static_cast<float>(uv.y());
    decoy_of[i] = static_cast<int>(s.f2.size());
    s.f2.push_back(d);
    s.point_of_f2.push_back(-1);
    ++decoys;
  }
  ASSERT_EQ(decoys, 30);
  s.g2.build(s.f2.data(), static_cast<int>(s.f2.size()), s.bounds);
  std::vector<std::pair<int, int>> pairs;
  MatcherScratch scratch;
  auto decoys_taken = [&](double max_depth) {
    search_for_triangulation(s.view1(), s.T1w, nullptr, s.view2(), s.T2w, nullptr, s.cam, s.pyr, MatcherParams{}, pairs,
                             scratch, max_depth);
    int taken = 0, correct = 0;
    for (auto [a, b] : pairs) {
      if (static_cast<std::size_t>(b) >= real2) ++taken;
      if (s.point_of_f1[static_cast<std::size_t>(a)] >= 0 &&
          s.point_of_f1[static_cast<std::size_t>(a)] == s.point_of_f2[static_cast<std::size_t>(b)]) ++correct;
    }
    EXPECT_GT(correct, 150) << "max_depth " << max_depth;
    return taken;
  };
  // the whole line: the decoys (Hamming 0) beat the true matches
  EXPECT_GE(decoys_taken(0.0), 25);
  // 15 m (50 baselines): the points are 2-6 m deep, the decoys are out of reach
  EXPECT_EQ(decoys_taken(15.0), 0);
}

// Repeated texture along the epipolar line: a twin of the true keypoint at another depth, its
// descriptor one bit nearer kf1's, makes the match ambiguous. Without the ratio test the search
// takes the twin (a point at the wrong depth); with it, neither.
TEST(Matcher, TriangulationSearchRejectsAMatchRepeatedAlongTheLine) {
  Scene s(7);
  const std::size_t real2 = s.f2.size();
  std::vector<bool> twinned(s.f1.size(), false);
  int twins = 0;
  for (std::size_t i = 0; i < s.f1.size() && twins < 30; ++i) {
    const int p = s.point_of_f1[i];
    if (p < 0) continue;
    const auto it = std::find(s.point_of_f2.begin(), s.point_of_f2.end(), p);
    if (it == s.point_of_f2.end()) continue;
    // the same point 1.5 times as deep along kf1's ray, seen in kf2
    geometry::Vec2 uv;
    if (!s.cam.project(s.T2w * (1.5 * s.points[static_cast<std::size_t>(p)]), &uv) ||
        !s.bounds.contains(static_cast<float>(uv.x()), static_cast<float>(uv.y())))
      continue;
    map::KeyframeFeature twin = s.f2[static_cast<std::size_t>(it - s.point_of_f2.begin())];
    for (std::size_t b = 0; b < twin.descriptor.bytes.size(); ++b) {
      const std::uint8_t diff = static_cast<std::uint8_t>(twin.descriptor.bytes[b] ^ s.f1[i].descriptor.bytes[b]);
      if (diff == 0) continue;
      twin.descriptor.bytes[b] ^= static_cast<std::uint8_t>(diff & -diff);  // one differing bit taken over
      break;
    }
    twin.u = static_cast<float>(uv.x());
    twin.v = static_cast<float>(uv.y());
    s.f2.push_back(twin);
    s.point_of_f2.push_back(-1);
    twinned[i] = true;
    ++twins;
  }
  ASSERT_EQ(twins, 30);
  s.g2.build(s.f2.data(), static_cast<int>(s.f2.size()), s.bounds);
  std::vector<std::pair<int, int>> pairs;
  MatcherScratch scratch;
  auto run = [&](float ratio, int* twinned_matched, int* twins_taken, int* correct) {
    MatcherParams params;
    params.ratio_triangulation = ratio;
    search_for_triangulation(s.view1(), s.T1w, nullptr, s.view2(), s.T2w, nullptr, s.cam, s.pyr, params, pairs, scratch);
    *twinned_matched = *twins_taken = *correct = 0;
    for (auto [a, b] : pairs) {
      if (twinned[static_cast<std::size_t>(a)]) ++*twinned_matched;
      if (static_cast<std::size_t>(b) >= real2) ++*twins_taken;
      const int pa = s.point_of_f1[static_cast<std::size_t>(a)];
      if (pa >= 0 && pa == s.point_of_f2[static_cast<std::size_t>(b)]) ++*correct;
    }
  };
  int matched = 0, taken = 0, correct = 0;
  run(1.0f, &matched, &taken, &correct);
  EXPECT_GE(matched, 25);   // without the test the twinned keypoints are matched, right or wrong
  EXPECT_GE(taken, 25);     // ... to the twin
  const int correct_without = correct;
  run(MatcherParams{}.ratio_triangulation, &matched, &taken, &correct);
  EXPECT_EQ(matched, 0);
  EXPECT_EQ(taken, 0);
  EXPECT_GT(correct, 150);  // the unambiguous rest still pairs
  EXPECT_GE(correct, correct_without - 40);
}

TEST(Matcher, SearchesAreDeterministic) {
  Scene a(5), b(5);
  std::vector<std::pair<int, int>> pa, pb;
  MatcherScratch sa, sb;
  search_for_triangulation(a.view1(), a.T1w, nullptr, a.view2(), a.T2w, nullptr, a.cam, a.pyr, MatcherParams{}, pa, sa);
  search_for_triangulation(b.view1(), b.T1w, nullptr, b.view2(), b.T2w, nullptr, b.cam, b.pyr, MatcherParams{}, pb, sb);
  EXPECT_EQ(pa, pb);
  EXPECT_GE(pa.size(), 100u) << "two empty searches are equal too (measured: 291 pairs)";
}

// The pair searches: right matches, the same result through the near-pair list as from all
// keypoint pairs, and the band of the true epipolar geometry keeping right matches only.
int count_wrong(const Scene& s, const std::vector<std::pair<int, int>>& pairs) {
  int wrong = 0;
  for (const auto& [i, j] : pairs)
    wrong += !(s.point_of_f1[static_cast<std::size_t>(i)] >= 0 &&
               s.point_of_f1[static_cast<std::size_t>(i)] == s.point_of_f2[static_cast<std::size_t>(j)]);
  return wrong;
}

geometry::Mat3 true_fundamental(const Scene& s) {
  const geometry::SE3 T21 = s.T2w * s.T1w.inverse();
  return geometry::fundamental_from_pose(s.cam.intrinsics(), T21.rotation(), T21.translation());
}

TEST(Matcher, PairSearchesMatchWithoutAndAlongTheEpipolarGeometry) {
  Scene s(4);
  MatcherScratch scratch;
  PairMatchParams params;
  std::vector<std::pair<int, int>> all, listed, band;
  const int n = match_all_pairs(s.view1(), s.view2(), params, all, scratch);
  EXPECT_EQ(n, static_cast<int>(all.size()));
  EXPECT_GT(n, 100);
  EXPECT_LE(count_wrong(s, all), n / 50);
  std::vector<DescriptorPair> near;
  near_descriptor_pairs(s.view1(), s.view2(), params, near);
  EXPECT_LT(near.size(), s.f1.size() * s.f2.size());
  match_all_pairs(s.view1(), s.view2(), near, params, listed, scratch);
  EXPECT_EQ(listed, all);
  EpipolarBandParams bp;
  const int nb = match_along_epipolar_lines(s.view1(), s.view2(), true_fundamental(s), bp, band, scratch);
  EXPECT_GE(nb, n - n / 20);
  EXPECT_EQ(count_wrong(s, band), 0);
  // a geometry far from the truth keeps few of them
  const geometry::Mat3 wrong_F =
      geometry::fundamental_from_pose(s.cam.intrinsics(), geometry::Mat3::Identity(), geometry::Vec3(0.0, 1.0, 0.0));
  EXPECT_LT(match_along_epipolar_lines(s.view1(), s.view2(), wrong_F, bp, band, scratch), nb / 4);
}

TEST(PairReconstruction, RecoversTheSyntheticPoseAndRejectsBadParameters) {
  Scene s(5);
  PairReconstructionParams params;
  PairScratch scratch;
  PairReconstruction r;
  const Status st = reconstruct_pair(s.view1(), s.view2(), s.cam.intrinsics(), params, &r, scratch);
  ASSERT_TRUE(st.ok()) << st.to_string();
  const geometry::SE3 T21 = s.T2w * s.T1w.inverse();
  const double rot_err_deg =
      geometry::SO3::from_matrix(r.two_view.R_21.transpose() * T21.rotation()).log().norm() * 180.0 / M_PI;
  const double cos_dir = r.two_view.t_21.dot(T21.translation().normalized());
  EXPECT_LT(rot_err_deg, 0.5);
  EXPECT_GT(cos_dir, std::cos(2.0 * M_PI / 180.0));
  EXPECT_GT(r.support, 100);
  EXPECT_EQ(count_wrong(s, r.matches), 0);
  params.guided_rounds = 0;
  EXPECT_EQ(reconstruct_pair(s.view1(), s.view2(), s.cam.intrinsics(), params, &r, scratch).code(),
            StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace ale::slam
