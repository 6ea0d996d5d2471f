#include "core/features/undistort.h"

#include <limits>

namespace ale::features {

int undistort_keypoints(const geometry::Camera& cam, const std::vector<Keypoint>& keypoints,
                        std::vector<geometry::Vec2>& ideal_px, std::vector<std::uint8_t>& valid) {
  ideal_px.resize(keypoints.size());
  valid.resize(keypoints.size());
  const double nan = std::numeric_limits<double>::quiet_NaN();
  int n_valid = 0;
  for (std::size_t i = 0; i < keypoints.size(); ++i) {
    const geometry::Vec2 px(keypoints[i].x, keypoints[i].y);
    const bool ok = cam.undistort_pixel(px, &ideal_px[i]);
    if (!ok) ideal_px[i] = geometry::Vec2(nan, nan);
    valid[i] = ok ? 1 : 0;
    n_valid += ok ? 1 : 0;
  }
  return n_valid;
}

}  // namespace ale::features
