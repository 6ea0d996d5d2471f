// Checkerboard views through a known lens: the ground truth a camera calibration is tested
// against (ale-render --checkerboard, docs/calibration.md).
//
// The board frame has its origin at the first inner corner, x along a row of COLS inner corners,
// y along a column of ROWS, z into the board (OpenCV's object points (i s, j s, 0)). The board is
// (COLS + 1) x (ROWS + 1) squares, the square at the origin's upper left black, inside a white
// border one square wide.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/image.h"
#include "core/base/status.h"
#include "app/tools/lib/render/camera.h"

namespace ale::render {

struct CheckerboardSpec {
  int cols = 9;  // inner corners along a row
  int rows = 6;  // inner corners along a column
  double square_m = 0.03;

  // Inner corner (i, j) in the board frame.
  Eigen::Vector3d corner(int i, int j) const { return {i * square_m, j * square_m, 0.0}; }
};

// "9x6" -> cols 9, rows 6; kInvalidArgument naming the text unless both are whole numbers in
// 2..64.
Result<CheckerboardSpec> parse_board(const std::string& text);

// The board's pose in the camera frame: p_c = R_cb p_b + t_cb.
struct BoardPose {
  Eigen::Matrix3d R_cb = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_cb = Eigen::Vector3d(0.0, 0.0, 1.0);
};

// `n` poses, the same for the same seed, that put the board (with half its border) inside the
// image at varied distance, tilt (up to 40 degrees) and roll, aimed in turn at the cells of a
// grid over the image so that the corners cover it, its edges and corners included.
// `into_corners`: views pushed into the image's corners: aims on the edges with little roll, the
// board moved away (down to 15 % of the field of view) before the aim is pulled towards the
// centre; the corners come closer to the image's corners (docs/calibration.md, Measured).
std::vector<BoardPose> checkerboard_poses(const PinholeCamera& camera, const CheckerboardSpec& board, int n,
                                          std::uint64_t seed, bool into_corners = false);

// Renders views of the board: supersample x supersample rays per pixel (antialiased edges; a pixel
// they do not all agree on, which an edge crosses, 16 x 16 rays), a
// mild illumination gradient over the board, Gaussian noise of `noise_grey` grey levels drawn
// from the seed. Rays are computed once, for every view.
class CheckerboardRenderer {
 public:
  CheckerboardRenderer(const PinholeCamera& camera, const CheckerboardSpec& board, int supersample);

  // `out` must be the camera's size.
  Status render(const BoardPose& pose, double noise_grey, std::uint64_t noise_seed, MutableGrayView out) const;

 private:
  PinholeCamera camera_;
  CheckerboardSpec board_;
  int supersample_;
  std::vector<Eigen::Vector3f> rays_c_;  // per sub-pixel, pixel-major; zero where the lens has none
  std::vector<Eigen::Vector3d> corner_rays_;  // through the pixels' corners, (width + 1) x (height + 1)
};

}  // namespace ale::render
