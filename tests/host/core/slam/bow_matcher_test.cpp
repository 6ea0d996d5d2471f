// search_by_bow on a synthetic keyframe and frame: the frame sees the keyframe's corners again
// (descriptor noise, another order, the image turned by 20 deg) among corners of another place.
#include "core/slam/match/bow.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "core/frontend/frame_path.h"
#include "core/io/image_io.h"
#include "core/place/embedded/embedded_vocabulary.h"
#include "tests/host/core/place/place_fixtures.h"
#include "tests/host/core/slam/synthetic_scene.h"
#include "tests/host/support/test_data.h"

namespace ale::slam {
namespace {

TEST(SearchByBow, MatchesTheKeyframesLandmarksUnderSharedNodesOnly) {
  const place::fixtures::World world(8, 40, 41);
  const place::Vocabulary vocab = place::fixtures::small_vocabulary(world);
  constexpr int kLevelsUp = 1;
  map::MapStore map(map::MapCapacity{4, 100, 40});

  // the keyframe: place 3, a landmark on every keypoint but the first five
  const std::vector<features::Descriptor> kd = world.image(3, 4, 1);
  std::vector<map::KeyframeFeature> kf(kd.size());
  for (std::size_t i = 0; i < kd.size(); ++i) {
    kf[i].descriptor = kd[i];
    kf[i].angle_deg = static_cast<float>(i * 9 % 360);
  }
  const map::KeyframeId kid = *map.add_keyframe(0.0, 0, geometry::SE3(), kf.data(), 40);
  std::vector<map::LandmarkId> kf_lm(kd.size());
  for (int i = 5; i < 40; ++i) {
    kf_lm[static_cast<std::size_t>(i)] = *map.add_landmark(geometry::Vec3(0, 0, 1), kd[static_cast<std::size_t>(i)], kid);
    ASSERT_TRUE(map.add_observation(kf_lm[static_cast<std::size_t>(i)], kid, i).ok());
  }

  // the frame: the keyframe's corners in reverse order, turned by 20 deg, except four turned
  // each its own way (the rotation check drops them); then ten corners of place 6
  const std::vector<features::Descriptor> fd = world.image(3, 6, 2);
  std::vector<map::KeyframeFeature> frame;
  std::vector<int> source;  // keyframe keypoint of each frame keypoint, -1 for the distractors
  for (int i = 39; i >= 0; --i) {
    map::KeyframeFeature f;
    f.descriptor = fd[static_cast<std::size_t>(i)];
    const float turn = i >= 10 && i < 14 ? 100.0f + 50.0f * static_cast<float>(i - 10) : 20.0f;
    f.angle_deg = std::fmod(kf[static_cast<std::size_t>(i)].angle_deg + turn, 360.0f);
    frame.push_back(f);
    source.push_back(i);
  }
  const std::vector<features::Descriptor> other = world.image(6, 6, 3);
  for (int i = 0; i < 10; ++i) {
    map::KeyframeFeature f;
    f.descriptor = other[static_cast<std::size_t>(i)];
    frame.push_back(f);
    source.push_back(-1);
  }
  const int n = static_cast<int>(frame.size());
  // two frame keypoints are matched already: left alone
  std::vector<map::LandmarkId> landmarks(static_cast<std::size_t>(n));
  const map::LandmarkId preset = kf_lm[20];
  landmarks[static_cast<std::size_t>(39 - 20)] = preset;  // frame keypoint 19 is keyframe keypoint 20
  landmarks[static_cast<std::size_t>(39 - 30)] = preset;

  place::BowVector kbow, fbow;
  place::FeatureVector kfv, ffv;
  vocab.transform(kd.data(), 40, kbow, kfv, kLevelsUp);
  std::vector<features::Descriptor> frame_desc;
  for (const map::KeyframeFeature& f : frame) frame_desc.push_back(f.descriptor);
  vocab.transform(frame_desc.data(), n, fbow, ffv, kLevelsUp);

  const geometry::Camera cam = test::pinhole();
  const ScalePyramid pyr = ScalePyramid::make(8, 1.2f);
  MatcherParams params;
  MatcherScratch scratch;
  const MatchContext ctx{cam, pyr, params, scratch};
  const BowTarget target{FrameFeatures{frame.data(), n, nullptr}, ffv, landmarks};
  const int matched = search_by_bow(ctx, target, map, kid, kfv);

  int correct = 0, wrong = 0, rotated = 0;
  for (int f = 0; f < n; ++f) {
    const map::LandmarkId lm = landmarks[static_cast<std::size_t>(f)];
    if (f == 39 - 20 || f == 39 - 30) {
      EXPECT_EQ(lm, preset);  // untouched
      continue;
    }
    if (!lm.valid()) continue;
    const int s = source[static_cast<std::size_t>(f)];
    if (s >= 10 && s < 14) ++rotated;
    if (s >= 0 && lm == kf_lm[static_cast<std::size_t>(s)]) {
      ++correct;
    } else {
      ++wrong;
    }
  }
  EXPECT_EQ(matched, correct + wrong);
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(rotated, 0);
  // 35 keypoints with landmarks, 4 turned the wrong way, 2 already matched: 29 could match;
  // a few fall under another node than their keyframe twin
  EXPECT_GE(correct, 22);

  // without the rotation check the wrongly turned ones come back
  params.rotation.enabled = false;
  std::vector<map::LandmarkId> again(static_cast<std::size_t>(n));
  const BowTarget target2{FrameFeatures{frame.data(), n, nullptr}, ffv, again};
  EXPECT_GT(search_by_bow(ctx, target2, map, kid, kfv), matched);

  // a keyframe without matching nodes gives nothing
  place::FeatureVector empty;
  std::vector<map::LandmarkId> none(static_cast<std::size_t>(n));
  const BowTarget target3{FrameFeatures{frame.data(), n, nullptr}, ffv, none};
  EXPECT_EQ(search_by_bow(ctx, target3, map, kid, empty), 0);
}

// Two real EuRoC frames 0.5 s apart while the vehicle sits still, through the daemon's front end
// and the built-in vocabulary: a keyframe with a landmark on every keypoint and the later frame.
// The camera has not moved, so a right match is the same corner: within 2 px (x the level's
// scale) of where it was.
TEST(SearchByBow, MatchesTheSameCornersOfTwoRealFramesOfAStillCamera) {
  ALE_REQUIRE_DATA(dir, "euroc_v101_micro/mav0/cam0/data");
  const Result<place::Vocabulary> vocab = place::load_embedded_vocabulary();
  ASSERT_TRUE(vocab.ok()) << vocab.status().to_string();
  frontend::FramePath path;
  ASSERT_TRUE(path.configure(features::ExtractorConfig{}).ok());
  std::vector<map::KeyframeFeature> frames[2];
  for (int k = 0; k < 2; ++k) {
    GrayImage image;
    const std::string file = dir + (k == 0 ? "/1403715273262142976.png" : "/1403715273762142976.png");
    ASSERT_TRUE(io::read_gray(file, image).ok()) << file;
    std::vector<features::Keypoint> kps;
    std::vector<features::Descriptor> desc;
    ASSERT_TRUE(path.extract(image.view(), kps, desc).ok());
    for (std::size_t i = 0; i < kps.size(); ++i) {
      map::KeyframeFeature f;
      f.u = kps[i].x;
      f.v = kps[i].y;
      f.angle_deg = kps[i].angle_deg;
      f.level = static_cast<std::int16_t>(kps[i].level);
      f.descriptor = desc[i];
      frames[k].push_back(f);
    }
  }
  const int n0 = static_cast<int>(frames[0].size()), n1 = static_cast<int>(frames[1].size());
  ASSERT_GT(n0, 500);
  map::MapStore map(map::MapCapacity{2, 2000, n0});
  const map::KeyframeId kid = *map.add_keyframe(0.0, 0, geometry::SE3(), frames[0].data(), n0);
  std::vector<map::LandmarkId> kf_lm(static_cast<std::size_t>(n0));
  for (int i = 0; i < n0; ++i) {
    kf_lm[static_cast<std::size_t>(i)] = *map.add_landmark(geometry::Vec3(0, 0, 1), frames[0][static_cast<std::size_t>(i)].descriptor, kid);
    ASSERT_TRUE(map.add_observation(kf_lm[static_cast<std::size_t>(i)], kid, i).ok());
  }
  std::vector<features::Descriptor> d0, d1;
  for (const auto& f : frames[0]) d0.push_back(f.descriptor);
  for (const auto& f : frames[1]) d1.push_back(f.descriptor);
  place::BowVector b0, b1;
  place::FeatureVector fv0, fv1;
  vocab->transform(d0.data(), n0, b0, fv0, 2);
  vocab->transform(d1.data(), n1, b1, fv1, 2);

  const geometry::Camera cam = test::pinhole();
  const ScalePyramid pyr = ScalePyramid::make(8, 1.2f);
  const MatcherParams params;
  MatcherScratch scratch;
  std::vector<map::LandmarkId> landmarks(static_cast<std::size_t>(n1));
  const int matched = search_by_bow(MatchContext{cam, pyr, params, scratch},
                                    BowTarget{FrameFeatures{frames[1].data(), n1, nullptr}, fv1, landmarks}, map, kid, fv0);
  int same_corner = 0;
  for (int f = 0; f < n1; ++f) {
    const map::LandmarkId lm = landmarks[static_cast<std::size_t>(f)];
    if (!lm.valid()) continue;
    const int i = static_cast<int>(std::find(kf_lm.begin(), kf_lm.end(), lm) - kf_lm.begin());
    const map::KeyframeFeature& a = frames[0][static_cast<std::size_t>(i)];
    const map::KeyframeFeature& b = frames[1][static_cast<std::size_t>(f)];
    const float tol = 2.0f * pyr.scale[static_cast<std::size_t>(std::max(a.level, b.level))];
    same_corner += std::abs(a.u - b.u) <= tol && std::abs(a.v - b.v) <= tol;
  }
  std::printf("[ figures  ] search_by_bow on two still EuRoC frames: %d + %d keypoints, %d matches, %d on the same corner, "
              "BoW score %.3f\n", n0, n1, matched, same_corner, place::Vocabulary::score(b0, b1));
  EXPECT_GE(matched, n0 / 4);
  EXPECT_GE(same_corner, matched * 95 / 100);  // measured: 464 of 475
}

}  // namespace
}  // namespace ale::slam
