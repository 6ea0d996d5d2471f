// Pieces of the ORB front end on synthetic input: quadtree distribution, the generated BRIEF
// pattern, orientation, rotation of descriptors, undistortion round trips, the extractor's
// configuration checks, budgets and determinism.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "core/features/brief.h"
#include "core/features/orb.h"
#include "core/frontend/frame_path.h"
#include "core/features/quadtree.h"
#include "core/features/undistort.h"
#include "tests/host/support/euroc_cam0.h"

namespace ale::features {
namespace {

TEST(Quadtree, KeepsEverythingUnderBudget) {
  const std::vector<FastCorner> in = {{10, 10, 30}, {50, 12, 20}, {90, 40, 25}};
  QuadtreeScratch s;
  std::vector<FastCorner> out;
  distribute_quadtree(in, {0, 0, 100, 50}, 5, s, out);
  EXPECT_EQ(out.size(), 3u);
}

TEST(Quadtree, SpreadsOverClustersAndKeepsTheStrongest) {
  // A dense cluster of 400 corners top-left and 4 lone corners in the other quadrants.
  std::vector<FastCorner> in;
  for (int y = 0; y < 20; ++y)
    for (int x = 0; x < 20; ++x)
      in.push_back({static_cast<std::int16_t>(5 + x), static_cast<std::int16_t>(5 + y),
                    static_cast<std::uint8_t>(10 + (x * 7 + y * 3) % 50)});
  in.push_back({150, 20, 8});
  in.push_back({170, 80, 8});
  in.push_back({30, 90, 8});
  in.push_back({120, 60, 8});
  QuadtreeScratch s;
  std::vector<FastCorner> out;
  distribute_quadtree(in, {0, 0, 200, 100}, 16, s, out);
  ASSERT_LE(out.size(), 16u);
  EXPECT_GE(out.size(), 14u);
  int lone = 0;
  std::set<std::pair<int, int>> seen;
  for (const FastCorner& c : out) {
    EXPECT_TRUE(seen.insert({c.x, c.y}).second) << "duplicate";
    if (c.score == 8) ++lone;
  }
  EXPECT_EQ(lone, 4) << "every isolated corner has its own node";
  // The cluster's picks are the best of their nodes: never the weakest score of the cluster.
  for (const FastCorner& c : out) {
    if (c.score != 8) {
      EXPECT_GT(c.score, 10);
    }
  }
}

TEST(BriefPattern, DeterministicInsideTheDiskWithoutEqualPairs) {
  const BriefPattern a = make_brief_pattern();
  const BriefPattern b = make_brief_pattern();
  EXPECT_EQ(a.xy, b.xy);
  EXPECT_NE(a.xy, make_brief_pattern(kPatternSeed + 1).xy);
  double sum2 = 0.0;
  for (int i = 0; i < kDescriptorBits; ++i) {
    const int x0 = a.xy[4 * i], y0 = a.xy[4 * i + 1], x1 = a.xy[4 * i + 2], y1 = a.xy[4 * i + 3];
    EXPECT_LE(x0 * x0 + y0 * y0, kPatchRadius * kPatchRadius);
    EXPECT_LE(x1 * x1 + y1 * y1, kPatchRadius * kPatchRadius);
    EXPECT_FALSE(x0 == x1 && y0 == y1);
    sum2 += x0 * x0 + x1 * x1 + y0 * y0 + y1 * y1;
  }
  // sigma^2 = 31^2 / 25 = 38.4 per coordinate before clipping to the disk.
  const double var = sum2 / (4.0 * kDescriptorBits);
  EXPECT_GT(var, 25.0);
  EXPECT_LT(var, 40.0);
}

TEST(Orientation, PointsTowardsTheBrightSide) {
  GrayImage img(64, 64);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) img.view().at(x, y) = static_cast<std::uint8_t>(x * 3);
  EXPECT_NEAR(ic_angle_deg(img.view(), 32, 32), 0.0f, 0.5f);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) img.view().at(x, y) = static_cast<std::uint8_t>(y * 3);
  EXPECT_NEAR(ic_angle_deg(img.view(), 32, 32), 90.0f, 0.5f);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) img.view().at(x, y) = static_cast<std::uint8_t>(255 - x * 3);
  EXPECT_NEAR(ic_angle_deg(img.view(), 32, 32), 180.0f, 0.5f);
}

TEST(Brief, RotatedPatchGivesTheSameDescriptor) {
  // A random patch and the same patch turned by 90 degrees (exact pixel rotation).
  const int n = 61;
  GrayImage a(n, n), b(n, n);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> v(0, 255);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) a.view().at(x, y) = static_cast<std::uint8_t>(v(rng));
  // b(x', y') = a(x, y) with (x', y') = centre + R90 (x - c, y - c): x' = c - (y - c), y' = c + (x - c).
  const int c = n / 2;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) b.view().at(c - (y - c), c + (x - c)) = a.view().at(x, y);
  const float angle_a = ic_angle_deg(a.view(), c, c);
  const float angle_b = ic_angle_deg(b.view(), c, c);
  EXPECT_NEAR(std::fmod(angle_b - angle_a + 720.0f, 360.0f), 90.0f, 0.01f);
  RotatedPattern rot;
  rot.build(make_brief_pattern(), n);
  Descriptor da, db, other;
  describe(a.view(), c, c, rot, angle_bin(angle_a), da);
  describe(b.view(), c, c, rot, (angle_bin(angle_a) + kAngleBins / 4) % kAngleBins, db);
  EXPECT_EQ(hamming_distance(da, db), 0);
  describe(a.view(), c, c, rot, (angle_bin(angle_a) + kAngleBins / 4) % kAngleBins, other);
  EXPECT_GT(hamming_distance(da, other), 80) << "a wrong rotation must not match";
}

TEST(Brief, HammingDistanceCountsBits) {
  Descriptor a, b;
  EXPECT_EQ(hamming_distance(a, b), 0);
  b.bytes[0] = 0xFF;
  b.bytes[31] = 0x01;
  EXPECT_EQ(hamming_distance(a, b), 9);
}

// EuRoC cam0 (sensor.yaml).
geometry::Camera euroc_cam0() {
  Result<geometry::Camera> cam = geometry::Camera::create(ale::test::euroc_cam0_intrinsics());
  EXPECT_TRUE(cam.ok()) << cam.status().to_string();
  return cam.ok() ? *cam : geometry::Camera();
}

TEST(Undistort, KeypointsRoundTripThroughTheCameraModel) {
  const geometry::Camera cam = euroc_cam0();
  std::vector<Keypoint> kps;
  for (int y = 0; y <= 480; y += 20)
    for (int x = 0; x <= 752; x += 20) {
      Keypoint kp;
      kp.x = static_cast<float>(x);
      kp.y = static_cast<float>(y);
      kps.push_back(kp);
    }
  std::vector<geometry::Vec2> ideal;
  std::vector<std::uint8_t> valid;
  ASSERT_EQ(undistort_keypoints(cam, kps, ideal, valid), static_cast<int>(kps.size()));
  ASSERT_EQ(ideal.size(), kps.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < kps.size(); ++i) {
    EXPECT_EQ(valid[i], 1);
    geometry::Vec2 expected;
    ASSERT_TRUE(cam.undistort_pixel(geometry::Vec2(kps[i].x, kps[i].y), &expected));
    EXPECT_EQ(ideal[i], expected);
    // distorting the ideal pixel again gives the keypoint back
    geometry::Vec2 again;
    const auto& k = cam.intrinsics();
    ASSERT_TRUE(cam.project(geometry::Vec3((ideal[i].x() - k.cx) / k.fx, (ideal[i].y() - k.cy) / k.fy, 1.0), &again));
    worst = std::max(worst, (again - geometry::Vec2(kps[i].x, kps[i].y)).norm());
  }
  EXPECT_LT(worst, 1e-9) << "worst round-trip error " << worst << " px";
  // Distortion really moves the corners (the test is not trivially an identity).
  EXPECT_GT(ideal[0].norm(), 20.0);
}

TEST(Undistort, MarksPixelsThatCannotBeUndistorted) {
  // x_d = x (1 - 0.45 r^2) has no preimage beyond r_d ~ 0.52; such keypoints are flagged.
  geometry::CameraIntrinsics k = euroc_cam0().intrinsics();
  k.distortion = {-0.45, 0.0, 0.0, 0.0, 0.0};
  const Result<geometry::Camera> cam = geometry::Camera::create(k);
  ASSERT_TRUE(cam.ok());
  std::vector<Keypoint> kps(2);
  kps[0].x = static_cast<float>(k.cx + 10.0);
  kps[0].y = static_cast<float>(k.cy);
  kps[1].x = static_cast<float>(k.cx + 0.6 * k.fx);
  kps[1].y = static_cast<float>(k.cy);
  std::vector<geometry::Vec2> ideal;
  std::vector<std::uint8_t> valid;
  EXPECT_EQ(undistort_keypoints(*cam, kps, ideal, valid), 1);
  EXPECT_EQ(valid[0], 1);
  EXPECT_EQ(valid[1], 0);
  EXPECT_TRUE(std::isnan(ideal[1].x()));
}

TEST(ExtractorConfig, RejectsOutOfRangeValuesByName) {
  const auto rejected = [](auto change, const char* key) {
    ExtractorConfig c;
    change(c);
    const Status st = validate(c);
    EXPECT_FALSE(st.ok()) << key;
    EXPECT_NE(st.message().find(key), std::string::npos) << st.message();
  };
  rejected([](ExtractorConfig& c) { c.num_features = 0; }, "num_features");
  rejected([](ExtractorConfig& c) { c.num_levels = 0; }, "num_levels");
  rejected([](ExtractorConfig& c) { c.num_levels = kMaxLevels + 1; }, "num_levels");
  rejected([](ExtractorConfig& c) { c.scale_factor = 1.0; }, "scale_factor");
  rejected([](ExtractorConfig& c) { c.cell_size_px = 4; }, "cell_size_px");
  rejected([](ExtractorConfig& c) { c.t_higher = c.t_high; }, "t_higher");
  rejected([](ExtractorConfig& c) { c.t_low = 30; }, "t_high");
  EXPECT_TRUE(validate(ExtractorConfig{}).ok());
  EXPECT_FALSE(parse_extractor_mode("orb").ok());
  EXPECT_EQ(*parse_extractor_mode("baseline"), ExtractorMode::kBaseline);
  EXPECT_EQ(*parse_extractor_mode("off"), ExtractorMode::kBaseline);  // the config's enhancement.mode
  EXPECT_EQ(*parse_extractor_mode("he"), ExtractorMode::kHe);
  EXPECT_EQ(*parse_extractor_mode("gamma"), ExtractorMode::kGamma);
  EXPECT_STREQ(to_string(ExtractorMode::kBaseline), "baseline");  // overlays and golden tables keep it
  EXPECT_STREQ(to_string(ExtractorMode::kHe), "he");
  EXPECT_STREQ(to_string(ExtractorMode::kGamma), "gamma");
}

GrayImage textured(int w, int h, std::uint32_t seed) {
  GrayImage img(w, h);
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(-12, 12);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int block = ((x / 9) * 31 + (y / 7) * 17) % 5 * 40;
      img.view().at(x, y) = static_cast<std::uint8_t>(std::clamp(40 + block + noise(rng), 0, 255));
    }
  return img;
}

TEST(FramePath, BudgetDeterminismAndBounds) {
  const GrayImage img = textured(320, 240, 3);
  for (ExtractorMode mode : {ExtractorMode::kAle, ExtractorMode::kBaseline, ExtractorMode::kClahe}) {
    ExtractorConfig cfg;
    cfg.mode = mode;
    cfg.num_features = 300;
    frontend::FramePath ex;
    ASSERT_TRUE(ex.configure(cfg).ok());
    std::vector<Keypoint> k1, k2;
    std::vector<Descriptor> d1, d2;
    ASSERT_TRUE(ex.extract(img.view(), k1, d1).ok());
    ex.reset();
    ASSERT_TRUE(ex.extract(img.view(), k2, d2).ok());
    ASSERT_EQ(k1.size(), d1.size());
    EXPECT_LE(k1.size(), 300u);
    EXPECT_GE(k1.size(), 270u) << to_string(mode);
    ASSERT_EQ(k1.size(), k2.size());
    for (std::size_t i = 0; i < k1.size(); ++i) {
      EXPECT_EQ(k1[i].x, k2[i].x);
      EXPECT_EQ(k1[i].angle_deg, k2[i].angle_deg);
      EXPECT_EQ(d1[i].bytes, d2[i].bytes);
      const double s = ex.level_scale(k1[i].level);
      EXPECT_GE(k1[i].lx, kEdgePx);
      EXPECT_LT(k1[i].lx, ex.level_image(k1[i].level).width - kEdgePx);
      EXPECT_NEAR(k1[i].x, k1[i].lx * s, 1e-3);
      EXPECT_GE(k1[i].angle_deg, 0.0f);
      EXPECT_LT(k1[i].angle_deg, 360.0f);
    }
    int sum = 0;
    for (int l = 0; l < ex.stats().levels; ++l) sum += ex.stats().level[static_cast<std::size_t>(l)].kept;
    EXPECT_EQ(sum, ex.stats().total);
  }
}

TEST(FramePath, RejectsBadInput) {
  frontend::FramePath ex;
  std::vector<Keypoint> k;
  std::vector<Descriptor> d;
  const GrayImage img = textured(100, 100, 1);
  EXPECT_FALSE(ex.extract(img.view(), k, d).ok()) << "not configured";
  ASSERT_TRUE(ex.configure(ExtractorConfig{}).ok());
  const GrayImage tiny = textured(30, 100, 1);
  EXPECT_FALSE(ex.extract(tiny.view(), k, d).ok());
  EXPECT_FALSE(ex.extract(GrayView{}, k, d).ok());
  ExtractorConfig bad;
  bad.num_levels = 0;
  EXPECT_FALSE(ex.configure(bad).ok());
  EXPECT_EQ(ex.config().num_levels, 8) << "a rejected configuration leaves the old one";
  EXPECT_TRUE(ex.extract(img.view(), k, d).ok());
}

}  // namespace
}  // namespace ale::features
