#include "core/slam/match/base.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/geometry/two_view.h"
#include "core/slam/match/fuse.h"
#include "core/slam/match/pairs.h"
#include "core/slam/match/projection.h"
#include "core/slam/match/triangulation.h"
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

TEST(FeatureGrid, QueryKeepsOnlyTheLevelRange) {
  Scene s(2);
  for (std::size_t i = 0; i < s.f1.size(); ++i) s.f1[i].level = static_cast<std::int16_t>(i % 4);  // the grid reads them
  std::vector<int> got;
  s.g1.query(320.0f, 240.0f, 120.0f, 1, 2, got);
  std::vector<int> want;
  for (std::size_t i = 0; i < s.f1.size(); ++i) {
    const map::KeyframeFeature& f = s.f1[i];
    if (f.level >= 1 && f.level <= 2 && std::fabs(f.u - 320.0f) <= 120.0f && std::fabs(f.v - 240.0f) <= 120.0f)
      want.push_back(static_cast<int>(i));
  }
  EXPECT_EQ(got, want);
  EXPECT_FALSE(want.empty());
}

TEST(FeatureGrid, ARowsCellsAreOneRunInColumnOrder) {
  // What the epipolar walk and query() rely on: cells c0..c1 of a row, read as one run from
  // cell_begin(c0, row) to cell_end(c1, row), are those cells' features cell after cell.
  Scene s(3);
  int nonempty = 0;
  for (int row = 0; row < FeatureGrid::kRows; row += 5) {
    for (int c0 = 0; c0 < FeatureGrid::kCols; c0 += 7) {
      for (int c1 = c0; c1 < FeatureGrid::kCols; c1 += 9) {
        std::vector<int> cells;
        for (int col = c0; col <= c1; ++col) cells.insert(cells.end(), s.g1.cell_begin(col, row), s.g1.cell_end(col, row));
        const std::vector<int> run(s.g1.cell_begin(c0, row), s.g1.cell_end(c1, row));
        ASSERT_EQ(run, cells) << row << " " << c0 << " " << c1;
        nonempty += cells.empty() ? 0 : 1;
      }
    }
  }
  EXPECT_GT(nonempty, 0);
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

// Keypoints with the given orientations, one match i -> i per entry.
struct RotatedPairs {
  std::vector<map::KeyframeFeature> a, b;
  std::vector<int> matches;
  void add(float angle_a_deg, float angle_b_deg, int copies) {
    for (int k = 0; k < copies; ++k) {
      map::KeyframeFeature fa, fb;
      fa.angle_deg = angle_a_deg;
      fb.angle_deg = angle_b_deg;
      matches.push_back(static_cast<int>(a.size()));
      a.push_back(fa);
      b.push_back(fb);
    }
  }
  FrameFeatures view_a() const { return {a.data(), static_cast<int>(a.size()), nullptr}; }
  FrameFeatures view_b() const { return {b.data(), static_cast<int>(b.size()), nullptr}; }
};

// 30 bins of 12 deg; a rotation r (a - b, mod 360) falls in bin round(r / 12), 30 -> 0.
TEST(RotationCheck, KeepsTheThreeStrongestBinsThatHoldATenthOfTheStrongest) {
  RotatedPairs p;
  p.add(50.0f, 40.0f, 40);    // +10 deg: bin 1
  p.add(90.0f, 0.0f, 10);     // +90: bin 8 (a quarter of bin 1)
  p.add(0.0f, 180.0f, 3);     // 180: bin 15 (under a tenth of bin 1: dropped)
  p.add(100.0f, 10.0f, 1);    // +90 again: bin 8
  std::vector<std::vector<int>> bins;
  std::vector<int> dropped;
  std::vector<int> m = p.matches;
  const int n = drop_inconsistent_rotations(p.view_a(), p.view_b(), 30, m, bins,
                                            [&](int i, int j) {
                                              EXPECT_EQ(j, i);  // reported before it is unset
                                              dropped.push_back(i);
                                            });
  EXPECT_EQ(n, 3);
  std::sort(dropped.begin(), dropped.end());
  EXPECT_EQ(dropped, (std::vector<int>{50, 51, 52}));
  for (int i = 0; i < static_cast<int>(m.size()); ++i)
    EXPECT_EQ(m[static_cast<std::size_t>(i)], i >= 50 && i < 53 ? kNoMatch : i) << i;
  // at a tenth exactly a bin counts: 4 of 40
  p.add(0.0f, 180.0f, 1);
  m = p.matches;
  EXPECT_EQ(drop_inconsistent_rotations(p.view_a(), p.view_b(), 30, m, bins), 0);
}

TEST(RotationCheck, DropsAllButTheThreeStrongestAndWrapsAround) {
  RotatedPairs p;
  p.add(0.0f, 1.0f, 20);      // -1 deg = 359: bin 30, which is bin 0
  p.add(0.5f, 0.0f, 20);      // +0.5: bin 0 as well (40 in all)
  p.add(130.0f, 10.0f, 10);   // +120: bin 10
  p.add(250.0f, 10.0f, 9);    // +240: bin 20
  p.add(10.0f, 250.0f, 8);    // -240 = 120: bin 10 (18 in all)
  p.add(60.0f, 0.0f, 7);      // +60: bin 5, fourth strongest
  std::vector<std::vector<int>> bins;
  std::vector<int> m = p.matches;
  EXPECT_EQ(drop_inconsistent_rotations(p.view_a(), p.view_b(), 30, m, bins), 7);
  EXPECT_EQ(std::count(m.begin(), m.end(), kNoMatch), 7);
  for (int i = 67; i < 74; ++i) EXPECT_EQ(m[static_cast<std::size_t>(i)], kNoMatch);
  // unmatched entries are left alone; one dominant bin keeps only itself
  RotatedPairs q;
  q.add(10.0f, 10.0f, 30);
  q.add(10.0f, 100.0f, 2);
  std::vector<int> mq = q.matches;
  mq[0] = kNoMatch;
  EXPECT_EQ(drop_inconsistent_rotations(q.view_a(), q.view_b(), 30, mq, bins), 2);
  EXPECT_EQ(mq[0], kNoMatch);
  EXPECT_EQ(std::count(mq.begin(), mq.end(), kNoMatch), 3);
}

// One landmark 2 m ahead of a camera at the origin, its mean viewing direction along the ray.
struct OneLandmark {
  geometry::Camera cam = test::pinhole();
  ScalePyramid pyr = ScalePyramid::make(8, 1.2f);
  ImageBounds bounds{0.0f, 0.0f, 752.0f, 480.0f};
  map::Landmark lm;
  OneLandmark() {
    lm.p_w = geometry::Vec3(0.2, -0.1, 2.0);
    lm.normal = lm.p_w.normalized();
    lm.min_distance = 1.0f;
    lm.max_distance = static_cast<float>(lm.p_w.norm());  // predicted at level 0 from here
  }
  bool in_view(const geometry::SE3& T_cw, LandmarkView* v) const {
    return landmark_in_view(lm, T_cw, T_cw.inverse().translation(), cam, bounds, pyr, v);
  }
};

TEST(LandmarkInView, AcceptsALandmarkInFrontWithinItsRangeAndAngle) {
  OneLandmark s;
  LandmarkView v;
  ASSERT_TRUE(s.in_view(geometry::SE3(), &v));
  geometry::Vec2 uv;
  ASSERT_TRUE(s.cam.project(s.lm.p_w, &uv));
  EXPECT_EQ(v.uv, uv);
  EXPECT_EQ(v.u, static_cast<float>(uv.x()));
  EXPECT_EQ(v.level, 0);
  EXPECT_NEAR(v.distance, s.lm.p_w.norm(), 1e-6);
  EXPECT_NEAR(v.view_cos, 1.0, 1e-6);  // the distance is a float
  // 1.5 times nearer: predicted at level 3 (1.2^2 < 1.5 <= 1.2^3, rounded up as ORB-SLAM does)
  const geometry::SE3 nearer(geometry::SO3(), -s.lm.p_w / 3.0);
  ASSERT_TRUE(s.in_view(nearer, &v));
  EXPECT_EQ(v.level, 3);
}

TEST(LandmarkInView, RejectsBehindOutsideTooNearTooFarAndOblique) {
  OneLandmark s;
  LandmarkView v;
  // behind: the camera turned around
  EXPECT_FALSE(s.in_view(geometry::SE3(geometry::SO3::exp(geometry::Vec3(0.0, M_PI, 0.0)), geometry::Vec3::Zero()), &v));
  // in front but outside the image: turned 60 deg about the vertical
  EXPECT_FALSE(s.in_view(geometry::SE3(geometry::SO3::exp(geometry::Vec3(0.0, 1.0, 0.0)), geometry::Vec3::Zero()), &v));
  // nearer than 0.8 min_distance (0.8 m) and farther than 1.2 max_distance, along its ray
  const geometry::Vec3 dir = s.lm.p_w.normalized();
  EXPECT_TRUE(s.in_view(geometry::SE3(geometry::SO3(), -(s.lm.p_w - 0.81 * dir)), &v));
  EXPECT_FALSE(s.in_view(geometry::SE3(geometry::SO3(), -(s.lm.p_w - 0.79 * dir)), &v));
  EXPECT_TRUE(s.in_view(geometry::SE3(geometry::SO3(), -(s.lm.p_w - 1.19 * s.lm.p_w.norm() * dir)), &v));
  EXPECT_FALSE(s.in_view(geometry::SE3(geometry::SO3(), -(s.lm.p_w - 1.21 * s.lm.p_w.norm() * dir)), &v));
  // seen more than 60 deg off its mean viewing direction (the camera where it is, same image)
  OneLandmark o;
  const geometry::Vec3 axis = o.lm.p_w.cross(geometry::Vec3::UnitX()).normalized();
  o.lm.normal = geometry::SO3::exp(axis * (59.0 * M_PI / 180.0)) * o.lm.p_w.normalized();
  ASSERT_TRUE(o.in_view(geometry::SE3(), &v));
  EXPECT_NEAR(v.view_cos, std::cos(59.0 * M_PI / 180.0), 1e-6);
  o.lm.normal = geometry::SO3::exp(axis * (61.0 * M_PI / 180.0)) * o.lm.p_w.normalized();
  EXPECT_FALSE(o.in_view(geometry::SE3(), &v));
}

// The keypoints of f2 matched to the landmark of their own point; -1 when one of them is matched
// to anything at all and is a distractor.
int right_landmarks(const Scene& s, const map::MapStore& store, const std::vector<map::LandmarkId>& f2_landmarks) {
  int right = 0;
  for (std::size_t i = 0; i < f2_landmarks.size(); ++i) {
    const map::Landmark* lm = store.landmark(f2_landmarks[i]);
    if (!lm) continue;
    if (s.point_of_f2[i] < 0) return -1;
    if ((lm->p_w - s.points[static_cast<std::size_t>(s.point_of_f2[i])]).norm() < 1e-12) ++right;
  }
  return right;
}

// The constant-velocity step's search: the last frame's landmarks found again in the current
// frame; keypoints whose orientation turned against the rest lose their match.
TEST(Matcher, LastFrameSearchFollowsTheLastMatchesWithTheRotationCheck) {
  Scene s(9);
  map::MapStore store(map::MapCapacity{2, 1000, 1000});
  const map::KeyframeId kf = *store.add_keyframe(0.0, 0, s.T1w, s.f1.data(), static_cast<int>(s.f1.size()));
  std::vector<map::LandmarkId> last_lms(s.f1.size());
  for (std::size_t i = 0; i < s.f1.size(); ++i) {
    if (s.point_of_f1[i] < 0) continue;
    last_lms[i] = *store.add_landmark(s.points[static_cast<std::size_t>(s.point_of_f1[i])], s.f1[i].descriptor, kf);
  }
  MatcherScratch scratch;
  const MatcherParams params;
  const MatchContext ctx{s.cam, s.pyr, params, scratch};
  auto search = [&](std::vector<map::LandmarkId>& lms) {
    lms.assign(s.f2.size(), map::LandmarkId{});
    return search_last_frame(ctx, {s.view2(), s.T2w, lms}, s.view1(), last_lms, store, 15.0f);
  };
  std::vector<map::LandmarkId> lms;
  const int n = search(lms);
  EXPECT_GT(n, 150);
  EXPECT_EQ(right_landmarks(s, store, lms), n);
  // ten matched keypoints turned by 90 deg: their matches go, the rest stay
  std::vector<std::size_t> turned;
  for (std::size_t i = 0; i < lms.size() && turned.size() < 10; ++i) {
    if (!lms[i].valid()) continue;
    s.f2[i].angle_deg += 90.0f;
    turned.push_back(i);
  }
  std::vector<map::LandmarkId> after;
  EXPECT_EQ(search(after), n - 10);
  for (std::size_t i : turned) EXPECT_FALSE(after[i].valid()) << i;
  for (std::size_t i = 0; i < lms.size(); ++i) {
    if (std::find(turned.begin(), turned.end(), i) == turned.end()) {
      EXPECT_EQ(after[i], lms[i]) << i;
    }
  }
}

// The projection search's radius is in pixels at level 0: radius_px near the landmark's mean
// viewing direction, 1.6 x radius_px more than 3.6 deg off it.
TEST(Matcher, ProjectionSearchRadiusIsInPixels) {
  OneLandmark s;
  map::MapStore store(map::MapCapacity{2, 10, 10});
  map::KeyframeFeature f0;
  SplitMix64 g(3);
  f0.descriptor = test::random_descriptor(g);
  const map::KeyframeId kf = *store.add_keyframe(0.0, 0, geometry::SE3(), &f0, 1);
  const map::LandmarkId id = *store.add_landmark(s.lm.p_w, f0.descriptor, kf);
  map::Landmark& lm = *store.landmark(id);
  lm.normal = s.lm.normal;
  lm.min_distance = s.lm.min_distance;
  lm.max_distance = s.lm.max_distance;
  geometry::Vec2 uv;
  ASSERT_TRUE(s.cam.project(s.lm.p_w, &uv));
  MatcherScratch scratch;
  const MatcherParams params;
  const MatchContext ctx{s.cam, s.pyr, params, scratch};
  // one keypoint with the landmark's descriptor, offset_px to the right of its projection
  auto matched = [&](double offset_px) {
    map::KeyframeFeature f = f0;
    f.u = static_cast<float>(uv.x() + offset_px);
    f.v = static_cast<float>(uv.y());
    FeatureGrid grid;
    grid.build(&f, 1, s.bounds);
    std::vector<map::LandmarkId> lms(1);
    return search_by_projection(ctx, {{&f, 1, &grid}, geometry::SE3(), lms}, store, {id}, 2.5f);
  };
  EXPECT_EQ(matched(2.4), 1);
  EXPECT_EQ(matched(2.6), 0);
  const geometry::Vec3 axis = s.lm.p_w.cross(geometry::Vec3::UnitX()).normalized();
  lm.normal = geometry::SO3::exp(axis * (10.0 * M_PI / 180.0)) * s.lm.p_w.normalized();
  EXPECT_EQ(matched(3.9), 1);
  EXPECT_EQ(matched(4.1), 0);
}

TEST(Matcher, InitializationSearchFindsTrueMatches) {
  Scene s(2);
  std::vector<std::pair<float, float>> predicted;
  for (const auto& k : s.f1) predicted.emplace_back(k.u, k.v);
  std::vector<int> m;
  MatcherScratch scratch;
  const MatcherParams params;
  const int n = search_for_initialization({s.cam, s.pyr, params, scratch}, s.view1(), s.view2(), predicted, 100.0f, m);
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
  const MatcherParams params;
  const MatchContext ctx{s.cam, s.pyr, params, scratch};
  const int n = search_by_projection(ctx, {s.view2(), s.T2w, frame_lms}, store, ids, 2.5f);
  EXPECT_GT(n, 150);
  EXPECT_EQ(right_landmarks(s, store, frame_lms), n);
  // a second search adds nothing: every landmark found is skipped
  EXPECT_EQ(search_by_projection(ctx, {s.view2(), s.T2w, frame_lms}, store, ids, 2.5f), 0);
}

// Landmarks made from f1's keypoints, fused into a keyframe of f2: each finds the keypoint of
// its own point; one the keyframe observes already is not searched.
TEST(Matcher, FusionSearchFindsTheDuplicateKeypoint) {
  Scene s(8);
  map::MapStore store(map::MapCapacity{2, 1000, 1000});
  const map::KeyframeId kf1 = *store.add_keyframe(0.0, 0, s.T1w, s.f1.data(), static_cast<int>(s.f1.size()));
  const map::KeyframeId kf2 = *store.add_keyframe(0.1, 1, s.T2w, s.f2.data(), static_cast<int>(s.f2.size()));
  std::vector<map::LandmarkId> ids;
  std::vector<int> point_of_id;
  for (std::size_t i = 0; i < s.f1.size(); ++i) {
    if (s.point_of_f1[i] < 0) continue;
    const map::LandmarkId id = *store.add_landmark(s.points[static_cast<std::size_t>(s.point_of_f1[i])], s.f1[i].descriptor, kf1);
    ASSERT_TRUE(store.add_observation(id, kf1, static_cast<int>(i)).ok());
    store.update_normal_and_depth(id, s.pyr.scale, s.pyr.levels);
    ids.push_back(id);
    point_of_id.push_back(s.point_of_f1[i]);
  }
  MatcherScratch scratch;
  const MatcherParams params;
  const MatchContext ctx{s.cam, s.pyr, params, scratch};
  const FusionTarget target{kf2, s.view2(), s.T2w, s.T2w.inverse().translation()};
  int correct = 0, wrong = 0;
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const int j = search_for_fusion(ctx, target, *store.landmark(ids[k]), 3.0f);
    if (j == kNoMatch) continue;
    (s.point_of_f2[static_cast<std::size_t>(j)] == point_of_id[k]) ? ++correct : ++wrong;
  }
  EXPECT_GT(correct, 150);
  EXPECT_LE(wrong, 2);
  // observed by the target: nothing to fuse there
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const int j = search_for_fusion(ctx, target, *store.landmark(ids[k]), 3.0f);
    if (j == kNoMatch) continue;
    ASSERT_TRUE(store.add_observation(ids[k], kf2, j).ok());
    EXPECT_EQ(search_for_fusion(ctx, target, *store.landmark(ids[k]), 3.0f), kNoMatch);
    break;
  }
}

TEST(Matcher, TriangulationSearchPairsAlongEpipolarLines) {
  Scene s(4);
  std::vector<std::pair<int, int>> pairs;
  MatcherScratch scratch;
  const MatcherParams params;
  const int n = search_for_triangulation({s.cam, s.pyr, params, scratch}, {s.view1(), s.T1w}, {s.view2(), s.T2w}, 0.0, pairs);
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
  const MatcherParams params;
  auto decoys_taken = [&](double max_depth) {
    search_for_triangulation({s.cam, s.pyr, params, scratch}, {s.view1(), s.T1w}, {s.view2(), s.T2w}, max_depth, pairs);
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
    search_for_triangulation({s.cam, s.pyr, params, scratch}, {s.view1(), s.T1w}, {s.view2(), s.T2w}, 0.0, pairs);
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
  const MatcherParams params;
  search_for_triangulation({a.cam, a.pyr, params, sa}, {a.view1(), a.T1w}, {a.view2(), a.T2w}, 0.0, pa);
  search_for_triangulation({b.cam, b.pyr, params, sb}, {b.view1(), b.T1w}, {b.view2(), b.T2w}, 0.0, pb);
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
  PairSearchParams params;
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
