// ale-calibrate's library against ground truth: checkerboard views rendered through a known lens
// (pinhole with radial-tangential distortion, and fisheye) give back its focal lengths and
// principal point within 0.5 px and its distortion within 0.1 px of the true projection over
// the whole image, its edges and corners included (docs/calibration.md); the parameters'
// standard deviations agree with OpenCV's; a blurred view measures wider edges. On real
// photographs not ours (OpenCV's sample left01..left14.jpg, read from the OpenCV source tarball
// scripts/setup-deps.sh downloads) the reprojection error stays under 0.5 px RMS and the lens
// agrees with cv::calibrateCamera's (same model) on the same images.
#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "app/tools/lib/calib/calibration.h"
#include "app/tools/lib/render/checkerboard.h"
#include "core/io/image_io.h"
#include "tests/host/support/test_data.h"

namespace ale::calib {
namespace {

using render::CheckerboardSpec;
using render::PinholeCamera;
using Corners = std::vector<std::vector<Eigen::Vector2d>>;

// The largest distance, over a grid of pixels every `step` px covering the whole image (its
// edges and corners included), between where `estimate` projects the ray `truth` sees at a pixel
// and that pixel.
// Every `step` px from 0, and the last pixel.
std::vector<double> grid(int size, double step) {
  std::vector<double> g;
  for (double x = 0.0; x < size - 1; x += step) g.push_back(x);
  g.push_back(size - 1);
  return g;
}

// The convex hull of every corner seen: the part of the image the calibration observed.
std::vector<cv::Point2f> corner_hull(const Corners& views) {
  std::vector<cv::Point2f> all, hull;
  for (const auto& v : views)
    for (const Eigen::Vector2d& p : v) all.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
  cv::convexHull(all, hull);
  return hull;
}

// With a hull, only the pixels inside it count.
double max_projection_error_px(const PinholeCamera& truth, const PinholeCamera& estimate, double step, int* pixels,
                               const std::vector<cv::Point2f>* hull = nullptr) {
  double worst = 0.0;
  *pixels = 0;
  for (double v : grid(truth.height, step))
    for (double u : grid(truth.width, step)) {
      if (hull != nullptr && cv::pointPolygonTest(*hull, cv::Point2f(static_cast<float>(u), static_cast<float>(v)), false) < 0) continue;
      const Eigen::Vector3d ray = truth.ray(u, v);
      if (ray.isZero()) continue;
      const Eigen::Vector2d uv = estimate.project(ray);
      worst = std::max(worst, std::isfinite(uv.x()) ? (uv - Eigen::Vector2d(u, v)).norm() : 1e9);
      ++*pixels;
    }
  return worst;
}

struct RenderedViews {
  std::vector<GrayImage> images;
  Corners corners;
  Corners truth;  // the true projections of the corners, in the detector's numbering
};

// RMS distance between detected corners and their true projections.
double corner_rms_px(const Corners& detected, const Corners& truth) {
  double sse = 0.0;
  std::size_t n = 0;
  for (std::size_t v = 0; v < detected.size(); ++v)
    for (std::size_t k = 0; k < detected[v].size(); ++k, ++n) sse += (detected[v][k] - truth[v][k]).squaredNorm();
  return std::sqrt(sse / static_cast<double>(std::max<std::size_t>(n, 1)));
}

RenderedViews render_and_detect(const PinholeCamera& camera, const CheckerboardSpec& board, int views, std::uint64_t seed) {
  const std::vector<render::BoardPose> poses = render::checkerboard_poses(camera, board, views, seed);
  const render::CheckerboardRenderer renderer(camera, board, 4);
  RenderedViews out;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    GrayImage image(camera.width, camera.height);
    EXPECT_TRUE(renderer.render(poses[k], 1.5, 1000 + k, image.view()).ok());
    const Detection d = detect_board(image.view(), board);
    EXPECT_TRUE(d.found) << "view " << k;
    if (!d.found) continue;
    std::vector<Eigen::Vector2d> truth;
    for (int j = 0; j < board.rows; ++j)
      for (int i = 0; i < board.cols; ++i) truth.push_back(camera.project(poses[k].R_cb * board.corner(i, j) + poses[k].t_cb));
    // The detector may number the board from its other end (a half turn looks the same).
    std::vector<Eigen::Vector2d> reversed(truth.rbegin(), truth.rend());
    double same = 0.0, other = 0.0;
    for (std::size_t i = 0; i < truth.size(); ++i) {
      same += (d.corners[i] - truth[i]).norm();
      other += (d.corners[i] - reversed[i]).norm();
    }
    out.truth.push_back(same <= other ? truth : reversed);
    out.corners.push_back(d.corners);
    out.images.push_back(std::move(image));
  }
  return out;
}

struct LensCase {
  const char* lens;
  LensModel model;
};

class RenderedLens : public ::testing::TestWithParam<LensCase> {};

// The seeds of the view sets: 7, or ALE_CALIB_SEEDS ("1-7" or "3,7") for the figure over several
// (docs/calibration.md, Measured).
std::vector<std::uint64_t> view_seeds() {
  const char* env = std::getenv("ALE_CALIB_SEEDS");
  if (env == nullptr || *env == '\0') return {7};
  std::vector<std::uint64_t> seeds;
  unsigned a = 0, b = 0;
  if (std::sscanf(env, "%u-%u", &a, &b) == 2 && a <= b && b - a < 100) {
    for (unsigned k = a; k <= b; ++k) seeds.push_back(k);
    return seeds;
  }
  for (const char* p = env; *p != '\0';) {
    char* end = nullptr;
    const unsigned long v = std::strtoul(p, &end, 10);
    if (end == p) break;
    seeds.push_back(v);
    p = *end == ',' ? end + 1 : end;
  }
  EXPECT_FALSE(seeds.empty()) << "ALE_CALIB_SEEDS='" << env << "' is not N-M or N,M,...";
  return seeds;
}

// 40 views (a 5 x 4 grid of aims over the image, twice), 1.5 grey levels of noise, through
// ale-calibrate's two passes: corners fitted with straight edges in the image, a first lens,
// the corners fitted again with edges straight through that lens (refit_with_lens), the lens
// fitted again. The corners come out about 0.01 px rms from the true projection, which leaves fx
// fy cx cy a few hundredths of a pixel from the truth. The distortion is checked with the true
// fx fy cx cy and the fitted coefficients, over the whole image (its edges and corners, where
// the fit extrapolates beyond the corners seen) and inside the hull of the corners seen; the
// whole lens is checked too.
TEST_P(RenderedLens, RecoversTheTrueLens) {
  const Result<PinholeCamera> truth = PinholeCamera::named(GetParam().lens, 640, 480);
  ASSERT_TRUE(truth.ok());
  CheckerboardSpec board;  // 9x6, 3 cm
  for (const std::uint64_t seed : view_seeds()) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    RenderedViews rendered = render_and_detect(*truth, board, 40, seed);
    Corners& views = rendered.corners;
    ASSERT_EQ(views.size(), 40u);
    const Result<Calibration> first = calibrate(views, board, GetParam().model, 640, 480);
    ASSERT_TRUE(first.ok()) << first.status().message();
    const double corners_first = corner_rms_px(views, rendered.truth);
    const auto image_of = [&](std::size_t v, GrayImage& out) {
      out = rendered.images[v];
      return Status{};
    };
    const Result<Calibration> cal = refit_with_lens(image_of, views, board, GetParam().model, 640, 480, *first);
    ASSERT_TRUE(cal.ok()) << cal.status().message();
    const PinholeCamera& est = cal->camera;
    std::printf("%s seed %llu: corners against the true projection: %.4f px rms, with the first lens %.4f px rms\n",
                GetParam().lens, static_cast<unsigned long long>(seed), corners_first, corner_rms_px(views, rendered.truth));
    std::printf("%s seed %llu: fx %.3f (true %.3f, sd %.3f) fy %.3f (%.3f, %.3f) cx %.3f (%.3f, %.3f) cy %.3f (%.3f, %.3f) "
                "rms %.4f px (first pass %.4f)\n",
                GetParam().lens, static_cast<unsigned long long>(seed), est.fx, truth->fx, cal->stddev[0], est.fy, truth->fy,
                cal->stddev[1], est.cx, truth->cx, cal->stddev[2], est.cy, truth->cy, cal->stddev[3], cal->rms_px, first->rms_px);
    EXPECT_NEAR(est.fx, truth->fx, 0.5);
    EXPECT_NEAR(est.fy, truth->fy, 0.5);
    EXPECT_NEAR(est.cx, truth->cx, 0.5);
    EXPECT_NEAR(est.cy, truth->cy, 0.5);
    EXPECT_EQ(est.distortion, truth->distortion);
    EXPECT_LT(cal->rms_px, 0.1);

    PinholeCamera distortion_only = *truth;
    distortion_only.coeffs = est.coeffs;
    const std::vector<cv::Point2f> hull = corner_hull(views);
    int all = 0, inside = 0;
    const double lens_image = max_projection_error_px(*truth, est, 8.0, &all);
    const double distortion_image = max_projection_error_px(*truth, distortion_only, 8.0, &all);
    const double lens_hull = max_projection_error_px(*truth, est, 8.0, &inside, &hull);
    const double distortion_hull = max_projection_error_px(*truth, distortion_only, 8.0, &inside, &hull);
    std::printf("%s seed %llu: inside the corners' hull (%d of %d pixels, every 8 px): distortion %.3f px, whole lens %.3f px; "
                "whole image: distortion %.3f px, whole lens %.3f px\n",
                GetParam().lens, static_cast<unsigned long long>(seed), inside, all, distortion_hull, lens_hull, distortion_image,
                lens_image);
    EXPECT_GT(inside, all / 2);
    EXPECT_LT(distortion_hull, 0.1);
    EXPECT_LT(distortion_image, 0.1);
    // The whole lens adds the fx fy cx cy errors: within 0.5 px as they are.
    EXPECT_LT(lens_hull, 0.5);
    EXPECT_LT(lens_image, 0.5);
  }
}

INSTANTIATE_TEST_SUITE_P(Lenses, RenderedLens,
                         ::testing::Values(LensCase{"radtan", LensModel::kPinholeRadTan},
                                           LensCase{"fisheye", LensModel::kFisheye}),
                         [](const ::testing::TestParamInfo<LensCase>& p) { return std::string(p.param.lens); });

// Views far into the image's corners (checkerboard_poses' into_corners), exact corners from the
// true radtan lens plus 0.06 px of noise (the detector's scatter on rendered views). The fit must
// reach the true lens's RMS, not stop where OpenCV's own start leads with these views (0.28 px
// rms, fx 5 px off).
TEST(Calibration, RadTanFitOfViewsReachingTheImageCorners) {
  const Result<PinholeCamera> truth = PinholeCamera::named("radtan", 640, 480);
  ASSERT_TRUE(truth.ok());
  const CheckerboardSpec board;  // 9x6, 3 cm
  std::mt19937 gen(5);
  std::normal_distribution<double> noise(0.0, 0.06);
  Corners views;
  double sse_true = 0.0;
  for (const render::BoardPose& pose : render::checkerboard_poses(*truth, board, 40, 7, true)) {
    std::vector<Eigen::Vector2d> corners;
    for (int j = 0; j < board.rows; ++j)
      for (int i = 0; i < board.cols; ++i) {
        const Eigen::Vector2d e(noise(gen), noise(gen));
        sse_true += e.squaredNorm();
        corners.push_back(truth->project(pose.R_cb * board.corner(i, j) + pose.t_cb) + e);
      }
    views.push_back(corners);
  }
  ASSERT_EQ(views.size(), 40u);
  // ale-calibrate's RMS is per corner (the distance, not per coordinate).
  const double rms_true = std::sqrt(sse_true / static_cast<double>(views.size() * board.cols * board.rows));
  const Result<Calibration> cal = calibrate(views, board, LensModel::kPinholeRadTan, 640, 480);
  ASSERT_TRUE(cal.ok()) << cal.status().message();
  std::printf("40 views into the corners: rms %.4f px (the true lens: %.4f), fx %.3f (true %.3f) cy %.3f (%.3f)\n",
              cal->rms_px, rms_true, cal->camera.fx, truth->fx, cal->camera.cy, truth->cy);
  EXPECT_LT(cal->rms_px, rms_true * 1.05);
  EXPECT_NEAR(cal->camera.fx, truth->fx, 0.5);
  EXPECT_NEAR(cal->camera.fy, truth->fy, 0.5);
  EXPECT_NEAR(cal->camera.cx, truth->cx, 0.5);
  EXPECT_NEAR(cal->camera.cy, truth->cy, 0.5);
}

// Our standard deviations (numeric Jacobian of the daemon's camera model, each view's pose
// marginalised through its 6 x 6 block) against the same quantity built another way: OpenCV's
// analytic Jacobian (cv::projectPoints) of every corner with respect to the eight parameters and
// every view's rotation vector and translation, the whole J^T J inverted at once. Agreement
// within 1 %. (OpenCV's own stdDeviationsIntrinsics are not the reference: they divide by
// corners - parameters instead of residuals - parameters, and on one rendered view set here they
// came out 32 times larger than this.)
TEST(Calibration, StandardDeviationsAgreeWithADenseAnalyticInverse) {
  const Result<PinholeCamera> truth = PinholeCamera::named("radtan", 640, 480);
  ASSERT_TRUE(truth.ok());
  CheckerboardSpec board;
  const Corners views = render_and_detect(*truth, board, 12, 3).corners;
  ASSERT_EQ(views.size(), 12u);
  const Result<Calibration> cal = calibrate(views, board, LensModel::kPinholeRadTan, 640, 480);
  ASSERT_TRUE(cal.ok());
  const int n_views = static_cast<int>(views.size());
  const int per_view = board.cols * board.rows;
  const int params = 8 + 6 * n_views;
  cv::Mat J = cv::Mat::zeros(2 * per_view * n_views, params, CV_64F);
  const cv::Matx33d K(cal->camera.fx, 0, cal->camera.cx, 0, cal->camera.fy, cal->camera.cy, 0, 0, 1);
  const std::vector<double> D{cal->camera.coeffs[0], cal->camera.coeffs[1], cal->camera.coeffs[2], cal->camera.coeffs[3], 0.0};
  double sse = 0.0;
  for (int v = 0; v < n_views; ++v) {
    std::vector<cv::Point3d> object;
    for (int k = 0; k < per_view; ++k) {
      const Eigen::Vector3d p = board.corner(k % board.cols, k / board.cols);
      object.emplace_back(p.x(), p.y(), p.z());
    }
    const Eigen::AngleAxisd aa(cal->poses[static_cast<std::size_t>(v)].R_cb);
    const Eigen::Vector3d r = aa.angle() * aa.axis();
    const Eigen::Vector3d& t = cal->poses[static_cast<std::size_t>(v)].t_cb;
    std::vector<cv::Point2d> projected;
    cv::Mat jac;  // columns: rvec (3), tvec (3), fx fy, cx cy, k1 k2 p1 p2 k3
    cv::projectPoints(object, cv::Vec3d(r.x(), r.y(), r.z()), cv::Vec3d(t.x(), t.y(), t.z()), K, D, projected, jac);
    for (int k = 0; k < per_view; ++k) {
      sse += std::pow(projected[static_cast<std::size_t>(k)].x - views[static_cast<std::size_t>(v)][static_cast<std::size_t>(k)].x(), 2) +
             std::pow(projected[static_cast<std::size_t>(k)].y - views[static_cast<std::size_t>(v)][static_cast<std::size_t>(k)].y(), 2);
      for (int row = 0; row < 2; ++row) {
        const int out = 2 * (v * per_view + k) + row;
        for (int q = 0; q < 8; ++q) J.at<double>(out, q) = jac.at<double>(2 * k + row, 6 + q);
        for (int q = 0; q < 6; ++q) J.at<double>(out, 8 + 6 * v + q) = jac.at<double>(2 * k + row, q);
      }
    }
  }
  const double sigma2 = sse / (2.0 * per_view * n_views - params);
  const cv::Mat cov = sigma2 * (J.t() * J).inv(cv::DECOMP_SVD);
  for (int k = 0; k < 8; ++k) {
    const double dense = std::sqrt(cov.at<double>(k, k));
    EXPECT_NEAR(cal->stddev[static_cast<std::size_t>(k)], dense, 0.01 * dense)
        << parameter_names(LensModel::kPinholeRadTan)[static_cast<std::size_t>(k)];
  }
  std::printf("sd fx: ours %.4f px, dense analytic %.4f px\n", cal->stddev[0], std::sqrt(cov.at<double>(0, 0)));
}

TEST(Calibration, BlurWidensTheMeasuredEdges) {
  const Result<PinholeCamera> cam = PinholeCamera::named("radtan", 640, 480);
  ASSERT_TRUE(cam.ok());
  CheckerboardSpec board;
  const std::vector<render::BoardPose> poses = render::checkerboard_poses(*cam, board, 1, 11);
  ASSERT_EQ(poses.size(), 1u);
  GrayImage image(640, 480);
  ASSERT_TRUE(render::CheckerboardRenderer(*cam, board, 4).render(poses[0], 1.5, 5, image.view()).ok());
  const Detection sharp = detect_board(image.view(), board);
  ASSERT_TRUE(sharp.found);
  cv::Mat m(480, 640, CV_8UC1, image.pixels.data());
  cv::GaussianBlur(m.clone(), m, cv::Size(0, 0), 2.5);
  const Detection blurred = detect_board(image.view(), board);
  ASSERT_TRUE(blurred.found);
  std::printf("edges 10-90 %%: sharp %.2f px, Gaussian sigma 2.5 px: %.2f px\n", sharp.blur_px, blurred.blur_px);
  EXPECT_LT(sharp.blur_px, 2.0);
  EXPECT_GT(blurred.blur_px, 5.0);  // ale-calibrate's default --max-blur
  EXPECT_LT(mean_corner_distance(sharp.corners, blurred.corners), 0.5);
}

// OpenCV's sample photographs (9x6 inner corners, 640x480, 13 views), extracted from the
// OpenCV source tarball at test time; never copied into the repository.
std::string extract_opencv_samples() {
  const char* env = std::getenv("ALE_OPENCV_TARBALL");
  const std::string tarball = env != nullptr ? env : ALE_OPENCV_TARBALL;
  if (!std::filesystem::exists(tarball)) return "";
  const std::string dir = test::make_temp_dir("opencv_samples");
  const std::string cmd = "tar -xJf '" + tarball + "' -C '" + dir +
                          "' --wildcards 'opencv-4.6.0/samples/data/left[01]*.jpg' 2>/dev/null";
  if (std::system(cmd.c_str()) != 0) return "";
  return dir + "/opencv-4.6.0/samples/data";
}

TEST(Calibration, OpenCvSamplePhotographs) {
  const std::string dir = extract_opencv_samples();
  if (dir.empty()) {
    if (test::running_in_ci()) FAIL() << "CI=true but the OpenCV source tarball (left01..left14.jpg) is missing: " << ALE_OPENCV_TARBALL;
    GTEST_SKIP() << "OpenCV's sample photographs are not here (" << ALE_OPENCV_TARBALL
                 << "; scripts/setup-deps.sh downloads it, or set ALE_OPENCV_TARBALL)";
  }
  CheckerboardSpec board;
  board.square_m = 0.025;
  Corners ours;
  std::vector<std::string> paths;
  for (int i = 1; i <= 14; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "/left%02d.jpg", i);
    if (!std::filesystem::exists(dir + name)) continue;  // the set has no left10
    GrayImage image;
    ASSERT_TRUE(io::read_gray(dir + name, image).ok());
    const Detection d = detect_board(image.view(), board);
    ASSERT_TRUE(d.found) << name;
    ours.push_back(d.corners);
    paths.push_back(dir + name);
  }
  ASSERT_EQ(ours.size(), 13u);
  // ale-calibrate's two passes: a first lens, the corners refined with it, the lens again.
  const Result<Calibration> first = calibrate(ours, board, LensModel::kPinholeRadTan, 640, 480);
  ASSERT_TRUE(first.ok()) << first.status().message();
  const auto image_of = [&](std::size_t v, GrayImage& out) { return io::read_gray(paths[v], out); };
  const Result<Calibration> cal = refit_with_lens(image_of, ours, board, LensModel::kPinholeRadTan, 640, 480, *first);
  ASSERT_TRUE(cal.ok()) << cal.status().message();
  std::printf("first pass: rms %.3f px\n", first->rms_px);
  std::printf("ours: fx %.2f fy %.2f cx %.2f cy %.2f k1 %.4f k2 %.4f p1 %.5f p2 %.5f, rms %.3f px over %d corners\n",
              cal->camera.fx, cal->camera.fy, cal->camera.cx, cal->camera.cy, cal->camera.coeffs[0], cal->camera.coeffs[1],
              cal->camera.coeffs[2], cal->camera.coeffs[3], cal->rms_px, cal->corners);
  EXPECT_LT(cal->rms_px, 0.5);

  // cv::calibrateCamera on the same corners, with the daemon's model (k3 fixed at 0) and with its
  // default one (k1 k2 p1 p2 k3). What is compared is the projection where the board was seen: at
  // every observed corner, the pixel our lens gives for OpenCV's ray through it. With the same
  // model the tolerance is 0.1 px (our fit, its second start and the daemon's camera model
  // against OpenCV's own). With k3 free the two lenses reach the same RMS (0.157 px) yet differ
  // by up to 0.104 px at the outermost corners: these corners (refined with the lens) are precise
  // enough to show this lens's k3 there, which the daemon's four coefficients cannot hold; it is
  // printed, not asserted (docs/calibration.md, Measured).
  std::vector<std::vector<cv::Point3f>> object(ours.size());
  std::vector<std::vector<cv::Point2f>> same(ours.size());
  for (std::size_t v = 0; v < ours.size(); ++v)
    for (int k = 0; k < 54; ++k) {
      object[v].emplace_back(0.025f * static_cast<float>(k % 9), 0.025f * static_cast<float>(k / 9), 0.0f);
      same[v].emplace_back(static_cast<float>(ours[v][static_cast<std::size_t>(k)].x()), static_cast<float>(ours[v][static_cast<std::size_t>(k)].y()));
    }
  const auto print_lens = [](const char* what, const cv::Mat& K, const cv::Mat& D, double rms) {
    std::printf("%s: fx %.2f fy %.2f cx %.2f cy %.2f k1 %.4f k2 %.4f p1 %.5f p2 %.5f k3 %.4f, rms %.3f px\n", what,
                K.at<double>(0, 0), K.at<double>(1, 1), K.at<double>(0, 2), K.at<double>(1, 2), D.at<double>(0),
                D.at<double>(1), D.at<double>(2), D.at<double>(3), D.at<double>(4), rms);
  };
  const auto worst_at_corners = [&](const cv::Mat& K, const cv::Mat& D) {
    double worst = 0.0;
    for (const auto& view : ours)
      for (const Eigen::Vector2d& uv : view) {
        std::vector<cv::Point2f> in{cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()))}, norm;
        cv::undistortPoints(in, norm, K, D);  // OpenCV's ray through the pixel
        const Eigen::Vector2d back = cal->camera.project(Eigen::Vector3d(norm[0].x, norm[0].y, 1.0));
        worst = std::max(worst, (back - uv).norm());
      }
    return worst;
  };
  cv::Mat K, D;
  std::vector<cv::Mat> rv, tv;
  const double cv_k3_rms = cv::calibrateCamera(object, same, cv::Size(640, 480), K, D, rv, tv, cv::CALIB_FIX_K3);
  print_lens("cv::calibrateCamera, same corners, k3 fixed at 0", K, D, cv_k3_rms);
  const double worst = worst_at_corners(K, D);
  std::printf("projection: ours and cv::calibrateCamera's (k3 0) differ by at most %.3f px at the %d observed corners\n",
              worst, cal->corners);
  EXPECT_LT(worst, 0.1);
  const double cv_rms = cv::calibrateCamera(object, same, cv::Size(640, 480), K, D, rv, tv);
  print_lens("cv::calibrateCamera, same corners, its default model", K, D, cv_rms);
  std::printf("projection: ours and cv::calibrateCamera's (k3 free) differ by at most %.3f px at the observed corners\n",
              worst_at_corners(K, D));

  // OpenCV's published calibration of these images (samples/data/left_intrinsics.yml, made by its
  // calibration sample: fixed aspect ratio, corners refined in 11 x 11 windows) has 0.39 px rms.
  // The sample's recipe run here reproduces it; its wide refinement windows reach into the
  // neighbouring squares on this board (squares ~25 px), which is what separates it from ours.
  // Printed for the record, not a pass criterion.
  std::vector<std::vector<cv::Point2f>> recipe;
  for (int i = 1; i <= 14; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "/left%02d.jpg", i);
    if (!std::filesystem::exists(dir + name)) continue;
    GrayImage image;
    ASSERT_TRUE(io::read_gray(dir + name, image).ok());
    const cv::Mat m(image.height, image.width, CV_8UC1, image.pixels.data());
    std::vector<cv::Point2f> c;
    ASSERT_TRUE(cv::findChessboardCorners(m, cv::Size(9, 6), c, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE));
    cv::cornerSubPix(m, c, cv::Size(11, 11), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.0001));
    recipe.push_back(c);
  }
  cv::Mat K2, D2;
  const double recipe_rms = cv::calibrateCamera(object, recipe, cv::Size(640, 480), K2, D2, rv, tv, cv::CALIB_FIX_ASPECT_RATIO);
  print_lens("OpenCV's sample recipe (11x11 windows, fixed aspect)", K2, D2, recipe_rms);
  std::printf("projection: ours and the sample recipe's differ by at most %.3f px at the observed corners\n",
              worst_at_corners(K2, D2));
}

}  // namespace
}  // namespace ale::calib
