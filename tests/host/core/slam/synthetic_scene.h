// A synthetic two-view scene for the SLAM core's tests: points in front of two cameras, each
// seen by both with its own descriptor noise and sub-pixel position noise, plus unrelated
// keypoints in each frame.
#pragma once

#include <cmath>
#include <vector>

#include "core/base/rng.h"
#include "core/geometry/camera.h"
#include "core/map/map_store.h"
#include "core/slam/frame.h"
#include "core/slam/match/base.h"
#include "core/slam/match/feature_grid.h"

namespace ale::slam::test {

using geometry::SE3;
using geometry::SO3;
using geometry::Vec3;

inline features::Descriptor random_descriptor(SplitMix64& g) {
  features::Descriptor d;
  for (auto& b : d.bytes) b = static_cast<std::uint8_t>(g.next());
  return d;
}

inline features::Descriptor perturbed(features::Descriptor d, SplitMix64& g, int flips) {
  for (int i = 0; i < flips; ++i) {
    const std::uint32_t bit = g.below(256);
    d.bytes[bit / 8] = static_cast<std::uint8_t>(d.bytes[bit / 8] ^ (1u << (bit % 8)));
  }
  return d;
}

inline geometry::Camera pinhole() {
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

  explicit Scene(std::uint64_t seed, int n = 300, int distractors = 100,
                 SE3 T2 = SE3(SO3::exp(Vec3(0.0, 0.05, 0.0)), Vec3(-0.3, 0.0, 0.02))) {
    SplitMix64 g(seed);
    T1w = SE3();
    T2w = T2;
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

// A frame record of features over the scene's 752x480 image, indexed.
inline Frame frame_of(const std::vector<map::KeyframeFeature>& f, double t, std::uint64_t seq) {
  Frame fr;
  fr.timestamp_s = t;
  fr.sequence = seq;
  fr.features = f;
  fr.index(ImageBounds{0.0f, 0.0f, 752.0f, 480.0f});
  return fr;
}

}  // namespace ale::slam::test
