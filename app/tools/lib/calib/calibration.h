// Camera calibration from checkerboard views, behind ale-calibrate (docs/calibration.md).
//
// Detection and the fit use OpenCV calib3d (findChessboardCorners, cornerSubPix,
// calibrateCamera, fisheye::calibrate): a host tool's dependency, never the daemon's. Every
// figure reported about the result (per-view and overall reprojection error, the parameters'
// standard deviations) is computed again with the daemon's own camera model
// (core/geometry/camera.h), so it describes the lens as ale-slamd will use it.
#pragma once

#include <Eigen/Core>

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "core/base/image.h"
#include "core/base/status.h"
#include "app/tools/lib/render/camera.h"
#include "app/tools/lib/render/checkerboard.h"

namespace ale::calib {

enum class LensModel { kPinholeRadTan, kFisheye };

struct Detection {
  bool found = false;
  std::vector<Eigen::Vector2d> corners;  // cols x rows, row by row, sub-pixel
  // Median 10-90 % rise distance of the board's edges across their direction, pixels: about 1.3
  // for a sharp edge, 1.3 + 2.56 sigma for a Gaussian blur of sigma.
  double blur_px = 0.0;
};

// Finds the board's inner corners. `found` false when the whole board is not seen.
Detection detect_board(GrayView image, const render::CheckerboardSpec& board);

// Moves each of a board's inner corners (cols x rows, row by row) to the point a model of the
// corner fitted to the pixels around it gives (two edges through it, blurred, averaged over each
// pixel's area); a corner whose fit fails keeps its place. With a lens (a first calibration of
// this camera) the edges are straight in the plane square to the corner's ray, not in the
// image, where the lens bends them.
void refine_corners(GrayView image, const render::CheckerboardSpec& board, std::vector<Eigen::Vector2d>& corners,
                    const render::PinholeCamera* lens);

// Mean distance between the same corners of two detections, pixels, whichever end of the board
// each detection numbered from.
double mean_corner_distance(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b);

struct Coverage {
  int cols = 8, rows = 6;    // grid over the image
  std::vector<int> counts;   // corners per cell, row by row
  double share = 0.0;        // cells holding at least one corner
};
Coverage corner_coverage(const std::vector<std::vector<Eigen::Vector2d>>& views, int width, int height);

struct Calibration {
  render::PinholeCamera camera;
  // Standard deviations of fx fy cx cy and the four coefficients (radtan k1 k2 p1 p2, fisheye
  // k1..k4): sigma^2 (J^T J)^-1 with the board poses marginalised out, sigma^2 the residual
  // variance per coordinate.
  std::array<double, 8> stddev{};
  std::vector<render::BoardPose> poses;  // per view
  std::vector<double> view_rms_px;        // per view
  double rms_px = 0.0;                    // over every corner
  int corners = 0;
};

// Names of the eight parameters, in `stddev`'s order.
std::array<const char*, 8> parameter_names(LensModel model);

// Fits the lens to the views' corners (at least three views). The radial-tangential model has
// k1 k2 p1 p2 (k3 fixed at 0: the daemon's calibration file has four coefficients).
// kInvalidArgument when the fit fails or gives a lens the daemon's model rejects.
Result<Calibration> calibrate(const std::vector<std::vector<Eigen::Vector2d>>& views,
                              const render::CheckerboardSpec& board, LensModel model, int width, int height);

// The fit again after every view's corners are refined with the lens of a first fit
// (refine_corners with `first.camera`): the edges a lens bends near the image's edges otherwise
// pull the corners there off by a few hundredths of a pixel, all the same way, and the
// distortion's r^4 term carries that to the image's corners (docs/calibration.md, Measured).
// `image_of(v, out)` gives view v's image. `views` is updated in place.
Result<Calibration> refit_with_lens(const std::function<Status(std::size_t, GrayImage&)>& image_of,
                                    std::vector<std::vector<Eigen::Vector2d>>& views, const render::CheckerboardSpec& board,
                                    LensModel model, int width, int height, const Calibration& first);

// The reprojection error of each view and overall, and the standard deviations, with the
// daemon's camera model (fills view_rms_px, rms_px, corners, stddev).
Status evaluate(const std::vector<std::vector<Eigen::Vector2d>>& views, const render::CheckerboardSpec& board,
                Calibration& calibration);

}  // namespace ale::calib
