#include "core/slam/undistortion.h"

#include <algorithm>

namespace ale::slam {
namespace {

ImageBounds undistorted_bounds(const geometry::Camera& camera) {
  const geometry::CameraIntrinsics& k = camera.intrinsics();
  const double w = k.width, h = k.height;
  ImageBounds b{0.0f, 0.0f, static_cast<float>(w), static_cast<float>(h)};
  if (!camera.has_distortion()) return b;
  float min_u = 1e30f, min_v = 1e30f, max_u = -1e30f, max_v = -1e30f;
  const int steps = 16;
  for (int i = 0; i <= steps; ++i) {
    const double s = static_cast<double>(i) / steps;
    const geometry::Vec2 border[4] = {{s * w, 0.0}, {s * w, h}, {0.0, s * h}, {w, s * h}};
    for (const geometry::Vec2& p : border) {
      geometry::Vec2 q;
      if (!camera.undistort_pixel(p, &q)) continue;
      min_u = std::min(min_u, static_cast<float>(q.x()));
      max_u = std::max(max_u, static_cast<float>(q.x()));
      min_v = std::min(min_v, static_cast<float>(q.y()));
      max_v = std::max(max_v, static_cast<float>(q.y()));
    }
  }
  if (min_u < max_u && min_v < max_v) b = ImageBounds{min_u, min_v, max_u, max_v};
  return b;
}

}  // namespace

KeypointUndistorter::KeypointUndistorter(const geometry::Camera& camera)
    : camera_(camera), pinhole_(camera.undistorted()), bounds_(undistorted_bounds(camera)) {}

void KeypointUndistorter::apply(const std::vector<map::KeyframeFeature>& features, int max_keypoints,
                                Frame& frame) const {
  frame.features.clear();
  for (const map::KeyframeFeature& f : features) {
    if (static_cast<int>(frame.features.size()) >= max_keypoints) break;
    geometry::Vec2 ideal;
    if (!camera_.undistort_pixel(geometry::Vec2(f.u, f.v), &ideal)) continue;
    map::KeyframeFeature g = f;
    g.u = static_cast<float>(ideal.x());
    g.v = static_cast<float>(ideal.y());
    frame.features.push_back(g);
  }
  frame.index(bounds_);
}

}  // namespace ale::slam
