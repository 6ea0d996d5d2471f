// Small maps built by hand for the map store's tests.
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "core/map/map_store.h"

namespace ale::map::fixtures {

inline std::vector<KeyframeFeature> features_of(int n, int seed) {
  std::vector<KeyframeFeature> f(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    f[static_cast<std::size_t>(i)].u = static_cast<float>(i);
    f[static_cast<std::size_t>(i)].v = static_cast<float>(seed);
    f[static_cast<std::size_t>(i)].level = static_cast<std::int16_t>(i % 3);
    f[static_cast<std::size_t>(i)].descriptor.bytes[0] = static_cast<std::uint8_t>(i + seed);
  }
  return f;
}

inline geometry::SE3 pose_at(double x) { return geometry::SE3(geometry::SO3(), geometry::Vec3(-x, 0.0, 0.0)); }

inline KeyframeId add_kf(MapStore& m, int n, int seed, double x = 0.0) {
  const auto f = features_of(n, seed);
  Result<KeyframeId> id = m.add_keyframe(seed * 0.1, static_cast<std::uint64_t>(seed), pose_at(x), f.data(), n);
  EXPECT_TRUE(id.ok()) << id.status().to_string();
  return *id;
}

inline LandmarkId add_lm(MapStore& m, KeyframeId first) {
  Result<LandmarkId> id = m.add_landmark(geometry::Vec3(0.0, 0.0, 2.0), features::Descriptor{}, first);
  EXPECT_TRUE(id.ok());
  return *id;
}

// Three keyframes: k0 and k1 share 20 landmarks, k1 and k2 share 16, k0 and k2 share 3.
struct Chain {
  MapStore m{MapCapacity{8, 100, 64}};
  KeyframeId k0, k1, k2;
  Chain() {
    k0 = add_kf(m, 40, 0, 0.0);
    k1 = add_kf(m, 40, 1, 0.1);
    k2 = add_kf(m, 40, 2, 0.2);
    for (int i = 0; i < 20; ++i) link({k0, k1}, i);
    for (int i = 20; i < 36; ++i) link({k1, k2}, i);
    for (int i = 36; i < 39; ++i) link({k0, k2}, i);
    m.update_connections(k0);
    m.update_connections(k1);
    m.update_connections(k2);
  }
  void link(std::vector<KeyframeId> kfs, int kp) {
    const LandmarkId l = add_lm(m, kfs[0]);
    for (KeyframeId k : kfs) ASSERT_TRUE(m.add_observation(l, k, kp).ok());
  }
  int weight(KeyframeId a, KeyframeId b) const {
    for (const Covisible& c : m.covisible_of(a)) {
      if (c.keyframe == b) return c.weight;
    }
    return 0;
  }
};

}  // namespace ale::map::fixtures
