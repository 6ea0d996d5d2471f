// Keypoint undistortion through the tree's one camera model (core/geometry/camera.h: pinhole
// radial-tangential or equidistant, inverted by Newton's method with a convergence check).
// This file only adapts it to the extractor's keypoints; the model lives in geometry.
#pragma once

#include <cstdint>
#include <vector>

#include "core/features/orb.h"
#include "core/geometry/camera.h"

namespace ale::features {

// The pixels the ideal pinhole with the camera's fx fy cx cy sees for the keypoints' level-0
// positions (geometry::Camera::undistort_pixel). ideal_px and valid are resized to match
// `keypoints` (kept by the caller, so a frame does not allocate after the first); valid[i] is 0
// where the distortion cannot be inverted at that pixel, and ideal_px[i] is then NaN so that an
// unchecked use fails loudly in the solvers (which reject non-finite input). Returns how many
// are valid.
int undistort_keypoints(const geometry::Camera& cam, const std::vector<Keypoint>& keypoints,
                        std::vector<geometry::Vec2>& ideal_px, std::vector<std::uint8_t>& valid);

}  // namespace ale::features
