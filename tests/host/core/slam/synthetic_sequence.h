// A synthetic sequence for the SLAM system's tests: frames of keypoints along a known motion.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "tests/host/core/slam/synthetic_scene.h"

namespace ale::slam::test {


// The keypoints a 752 x 480 camera at T_cw sees of `points` (at most 1000, in point order):
// +-0.3 px of noise, descriptors with 6 of 256 bits flipped.
inline std::vector<map::KeyframeFeature> keypoints_seen(const geometry::Camera& cam, const SE3& T_cw,
                                                        const std::vector<Vec3>& points,
                                                        const std::vector<features::Descriptor>& truth, SplitMix64& g) {
  std::vector<map::KeyframeFeature> out;
  for (std::size_t i = 0; i < points.size() && out.size() < 1000; ++i) {
    geometry::Vec2 uv;
    if (!cam.project(T_cw * points[i], &uv)) continue;
    if (uv.x() < 0 || uv.x() >= 752 || uv.y() < 0 || uv.y() >= 480) continue;
    map::KeyframeFeature k;
    k.u = static_cast<float>(uv.x() + 0.6 * (g.uniform_double() - 0.5));
    k.v = static_cast<float>(uv.y() + 0.6 * (g.uniform_double() - 0.5));
    k.angle_deg = 10.0f;
    k.descriptor = perturbed(truth[i], g, 6);
    out.push_back(k);
  }
  return out;
}

// A camera sliding sideways past a deep field of textured points, yawing gently: what a sweeper
// sees moving along a room.
struct Sequence {
  geometry::Camera cam = pinhole();
  std::vector<Vec3> points;
  std::vector<features::Descriptor> truth;
  std::vector<SE3> T_cw;  // truth, metres

  Sequence(std::uint64_t seed, int frames) {
    SplitMix64 g(seed);
    for (int i = 0; i < 3000; ++i) {
      points.emplace_back(g.uniform_double() * 10.0 - 3.0, g.uniform_double() * 3.0 - 1.5, 3.0 + g.uniform_double() * 5.0);
      truth.push_back(random_descriptor(g));
    }
    for (int f = 0; f < frames; ++f) {
      const double x = 0.04 * f;
      const SE3 T_wc(SO3::exp(Vec3(0.0, 0.01 * std::sin(0.2 * f), 0.0)), Vec3(x, 0.0, 0.0));
      T_cw.push_back(T_wc.inverse());
    }
  }

  std::vector<map::KeyframeFeature> frame(int f, std::uint64_t noise_seed) const {
    SplitMix64 g(noise_seed * 7919 + static_cast<std::uint64_t>(f));
    return keypoints_seen(cam, T_cw[static_cast<std::size_t>(f)], points, truth, g);
  }
};

}  // namespace ale::slam::test
