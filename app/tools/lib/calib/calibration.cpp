#include "app/tools/lib/calib/calibration.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/geometry/camera.h"

namespace ale::calib {

namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

// The corner model's fit (fit_corner_model). Pixels within this share of the distance to the
// nearest neighbouring corner. Measured on 20 rendered radtan views (view set 7), corner error
// against the true projection without noise: 0.3 gives 0.0119 px rms, 0.4 0.0123, 0.5 0.0151;
// with 1.5 grey levels of noise 0.3 and 0.4 both 0.0127. The wider of the two keeps more pixels
// against a real camera's noise.
constexpr double kCornerWindowShare = 0.4;
// Points per side of a pixel the model is averaged over, and the narrowest edge it may take (in
// erf units: 0.3 is a Gaussian sigma of 0.21 px, which with 2 x 2 points still gives a smooth
// step). Same views without noise: 2 x 2 points 0.0123 px rms, 4 x 4 (width from 0.2) 0.0124;
// one point at the pixel's centre 0.029 px with the width held to a box's (0.41) and 0.066 px
// with 0.3, an edge along the pixel grid then having no position between two pixel centres.
constexpr int kCornerSubSamples = 2;
constexpr double kCornerMinEdgeWidth = 0.3;

double bilinear(GrayView img, double x, double y) {
  const int x0 = static_cast<int>(std::floor(x));
  const int y0 = static_cast<int>(std::floor(y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= img.width || y0 + 1 >= img.height) return -1.0;
  const double fx = x - x0;
  const double fy = y - y0;
  const std::uint8_t* r0 = img.row(y0) + x0;
  const std::uint8_t* r1 = img.row(y0 + 1) + x0;
  return (1 - fy) * ((1 - fx) * r0[0] + fx * r0[1]) + fy * ((1 - fx) * r1[0] + fx * r1[1]);
}

// 10-90 % rise distance across the edge between two neighbouring corners (which is the side of
// a square): -1 when the profile leaves the image or has too little contrast.
double edge_rise_px(GrayView img, const Vec2& a, const Vec2& b) {
  const Vec2 along = b - a;
  const double length = along.norm();
  if (length < 4.0) return -1.0;
  const Vec2 across(-along.y() / length, along.x() / length);
  const Vec2 mid = 0.5 * (a + b);
  constexpr double kStep = 0.25;
  const double half = 0.4 * length;
  std::vector<double> profile;
  for (double t = -half; t <= half + 1e-9; t += kStep) {
    const Vec2 p = mid + t * across;
    const double v = bilinear(img, p.x(), p.y());
    if (v < 0.0) return -1.0;
    profile.push_back(v);
  }
  const std::size_t n = profile.size();
  if (n < 12) return -1.0;
  const double lo = (profile[0] + profile[1] + profile[2]) / 3.0;
  const double hi = (profile[n - 1] + profile[n - 2] + profile[n - 3]) / 3.0;
  if (std::abs(hi - lo) < 30.0) return -1.0;
  int inside = 0;
  for (double v : profile) {
    const double f = (v - lo) / (hi - lo);
    inside += (f > 0.1 && f < 0.9) ? 1 : 0;
  }
  return inside * kStep;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t m = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(m), v.end());
  return v[m];
}

// Sub-pixel position of one inner corner by fitting a model of it to the pixels around it: two
// straight edges through the corner c with unit normals n1 n2 (angles th1 th2), each an erf
// step of width w, under light with a slope g over the window (x the pixel, x0 the start),
//   grey(x) = (m + a erf(n1.(p - c) / w) erf(n2.(p - c) / w)) (1 + g.(x - x0)),
// the erf product averaged over sub x sub points of each pixel (a pixel integrates over its area:
// an edge along the pixel grid is otherwise seen as a step whose position nothing fixes between
// two pixel centres). Dark in two opposite quadrants, light in the other two, at any angle
// between the edges (a tilted board's corners are not square). p is the point x - x0 within the
// pixel or, with a lens, where its ray meets the plane square to the start's ray (scaled to
// pixels there), in which the board's edges are straight. Gauss-Newton over the pixels
// within `radius` of the start. On rendered views cv::cornerSubPix leaves the corners 0.065 to
// 0.07 px rms from the true projection, this model about 0.012 px (docs/calibration.md). False
// (the start kept) when the fitted point is not finite or lies over half the radius from the
// start, or the contrast |a| is under 10 grey levels.
bool fit_corner_model(GrayView img, Vec2& corner, const Vec2& dir1, const Vec2& dir2, double radius,
                      const render::PinholeCamera* lens) {
  const int r = static_cast<int>(std::ceil(radius));
  const int x0 = static_cast<int>(std::lround(corner.x())), y0 = static_cast<int>(std::lround(corner.y()));
  if (x0 - r < 0 || y0 - r < 0 || x0 + r >= img.width || y0 + r >= img.height) return false;
  constexpr int sub = kCornerSubSamples;
  constexpr double w_min = kCornerMinEdgeWidth;
  // Where the fit happens: pixel offsets from the start, or with a lens the plane square to the
  // corner's ray (a gnomonic view, in which the board's edges are straight lines whatever the
  // lens bends them to), scaled to pixels there by the inverse of the local Jacobian A.
  const Vec2 start = corner;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Matrix2d A = Eigen::Matrix2d::Identity(), A_inv = Eigen::Matrix2d::Identity();
  const auto tangent = [&](double u, double v, Vec2& t) {
    const Vec3 ray = R.transpose() * lens->ray(u, v);
    if (!(ray.z() > 1e-6)) return false;
    t = ray.head<2>() / ray.z();
    return true;
  };
  if (lens != nullptr) {
    const Vec3 axis = lens->ray(start.x(), start.y());
    if (axis.isZero()) return false;
    R = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), axis).toRotationMatrix();
    Vec2 px, mx, py, my;
    if (!tangent(start.x() + 0.5, start.y(), px) || !tangent(start.x() - 0.5, start.y(), mx) ||
        !tangent(start.x(), start.y() + 0.5, py) || !tangent(start.x(), start.y() - 0.5, my))
      return false;
    A.col(0) = px - mx;
    A.col(1) = py - my;
    if (std::abs(A.determinant()) < 1e-12) return false;
    A_inv = A.inverse();
  }
  std::vector<Vec3> pixels;  // grey, then sub x sub sample points in `samples`
  std::vector<Vec2> samples;
  for (int y = y0 - r; y <= y0 + r; ++y)
    for (int x = x0 - r; x <= x0 + r; ++x) {
      if (std::hypot(x - start.x(), y - start.y()) > radius) continue;
      bool ok = true;
      for (int j = 0; j < sub && ok; ++j)
        for (int i = 0; i < sub && ok; ++i) {
          const double u = x + (i + 0.5) / sub - 0.5, v = y + (j + 0.5) / sub - 0.5;
          Vec2 t(u - start.x(), v - start.y());
          if (lens != nullptr) {
            ok = tangent(u, v, t);
            t = A_inv * t;
          }
          samples.push_back(t);
        }
      if (!ok) return false;
      pixels.emplace_back(x, y, img.row(y)[x]);
    }
  constexpr int kParams = 9;  // cx cy th1 th2 w m a gx gy
  using VecP = Eigen::Matrix<double, kParams, 1>;
  using MatP = Eigen::Matrix<double, kParams, kParams>;
  // The edges run along the board's rows and columns: their normals are perpendicular to the
  // directions towards the neighbouring corners.
  VecP q;
  q << 0.0, 0.0, std::atan2(dir1.x(), -dir1.y()), std::atan2(dir2.x(), -dir2.y()), 0.8, 0.0, 0.0, 0.0, 0.0;
  // The model's grey level at pixel px and its derivatives (parameters in q's order).
  const auto model = [&](const VecP& t, std::size_t pixel, VecP* J) {
    const double c1 = std::cos(t(2)), s1 = std::sin(t(2)), c2 = std::cos(t(3)), s2 = std::sin(t(3)), w = t(4);
    double sum = 0.0;
    VecP dsum = VecP::Zero();
    for (int k = 0; k < sub * sub; ++k) {
        const Vec2& at = samples[pixel * static_cast<std::size_t>(sub * sub) + static_cast<std::size_t>(k)];
        const double dx = at.x() - t(0), dy = at.y() - t(1);
        const double u1 = (c1 * dx + s1 * dy) / w, u2 = (c2 * dx + s2 * dy) / w;
        const double e1 = std::erf(u1), e2 = std::erf(u2);
        sum += e1 * e2;
        if (J == nullptr) continue;
        const double d1 = 1.1283791670955126 * std::exp(-u1 * u1) * e2;  // d(e1 e2) / du1
        const double d2 = 1.1283791670955126 * std::exp(-u2 * u2) * e1;
        dsum(0) -= (d1 * c1 + d2 * c2) / w;
        dsum(1) -= (d1 * s1 + d2 * s2) / w;
        dsum(2) += d1 * (-s1 * dx + c1 * dy) / w;
        dsum(3) += d2 * (-s2 * dx + c2 * dy) / w;
        dsum(4) -= (d1 * u1 + d2 * u2) / w;
      }
    const double n = sub * sub;
    const Vec3& px = pixels[pixel];
    const double X = px.x() - start.x(), Y = px.y() - start.y();
    const double light = 1.0 + t(7) * X + t(8) * Y;
    const double base = t(5) + t(6) * sum / n;
    if (J != nullptr) {
      *J = light * t(6) * dsum / n;
      (*J)(5) = light;
      (*J)(6) = light * sum / n;
      (*J)(7) = base * X;
      (*J)(8) = base * Y;
    }
    return base * light;
  };
  {  // m and a enter linearly: their least-squares values for the start.
    Eigen::Matrix2d N = Eigen::Matrix2d::Zero();
    Vec2 b = Vec2::Zero();
    for (std::size_t k = 0; k < pixels.size(); ++k) {
      const Vec3& px = pixels[k];
      q(5) = 0.0;
      q(6) = 1.0;
      const Vec2 g(1.0, model(q, k, nullptr));
      N += g * g.transpose();
      b += g * px.z();
    }
    const Vec2 ma = N.ldlt().solve(b);
    q(5) = ma.x();
    q(6) = ma.y();
  }
  for (int iter = 0; iter < 30; ++iter) {
    MatP H = MatP::Zero();
    VecP g = VecP::Zero();
    for (std::size_t k = 0; k < pixels.size(); ++k) {
      const Vec3& px = pixels[k];
      VecP J;
      const double e = model(q, k, &J);
      H += J * J.transpose();
      g += J * (px.z() - e);
    }
    H.diagonal() *= 1.0 + 1e-6;
    const VecP step = H.ldlt().solve(g);
    if (!step.allFinite()) return false;
    q += step;
    q(4) = std::clamp(q(4), w_min, radius);
    if (std::hypot(step(0), step(1)) < 1e-5) break;
  }
  Vec2 fitted = start + q.head<2>();
  if (lens != nullptr) {
    const Vec2 t = A * q.head<2>();
    fitted = lens->project(R * Vec3(t.x(), t.y(), 1.0));
  }
  if (!fitted.allFinite() || (fitted - corner).norm() > 0.5 * radius || std::abs(q(6)) < 10.0) return false;
  corner = fitted;
  return true;
}

render::PinholeCamera with_parameters(render::PinholeCamera c, const double* p) {
  c.fx = p[0];
  c.fy = p[1];
  c.cx = p[2];
  c.cy = p[3];
  for (int i = 0; i < 4; ++i) c.coeffs[static_cast<std::size_t>(i)] = p[4 + i];
  return c;
}

}  // namespace

std::array<const char*, 8> parameter_names(LensModel model) {
  if (model == LensModel::kFisheye) return {"fx", "fy", "cx", "cy", "k1", "k2", "k3", "k4"};
  return {"fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2"};
}

Detection detect_board(GrayView image, const render::CheckerboardSpec& board) {
  Detection d;
  const cv::Mat img(image.height, image.width, CV_8UC1, const_cast<std::uint8_t*>(image.data),
                    static_cast<std::size_t>(image.stride));
  const cv::Size pattern(board.cols, board.rows);
  std::vector<cv::Point2f> corners;
  bool found = cv::findChessboardCorners(img, pattern, corners,
                                         cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE | cv::CALIB_CB_FAST_CHECK);
  if (found) {
    // The refinement window reaches a third of the way to the nearest corner. On OpenCV's sample
    // photographs (squares ~25 px) 0.35 gives 0.18 px rms against 0.31 for 0.5; on rendered views
    // with known corners 0.35 and 0.5 do about as well (0.065 and 0.06 px rms), 0.2 and 0.65
    // worse (0.09, 0.12).
    double spacing = 1e9;
    for (int j = 0; j < board.rows; ++j)
      for (int i = 0; i + 1 < board.cols; ++i) {
        const cv::Point2f e = corners[static_cast<std::size_t>(j * board.cols + i + 1)] - corners[static_cast<std::size_t>(j * board.cols + i)];
        spacing = std::min(spacing, std::hypot(static_cast<double>(e.x), static_cast<double>(e.y)));
      }
    const int half = std::clamp(static_cast<int>(0.35 * spacing), 2, 10);
    cv::cornerSubPix(img, corners, cv::Size(half, half), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 0.001));
  } else {
    // The sector-based detector copes with strongly curved (fisheye) boards and boards whose
    // white border leaves the image; its corners are sub-pixel already.
    found = cv::findChessboardCornersSB(img, pattern, corners, cv::CALIB_CB_ACCURACY);
  }
  if (!found || corners.size() != static_cast<std::size_t>(board.cols * board.rows)) return d;
  d.found = true;
  for (const cv::Point2f& c : corners) d.corners.emplace_back(c.x, c.y);
  refine_corners(image, board, d.corners, nullptr);
  std::vector<double> rises;
  for (int j = 0; j < board.rows; ++j)
    for (int i = 0; i < board.cols; ++i) {
      const Vec2& c = d.corners[static_cast<std::size_t>(j * board.cols + i)];
      if (i + 1 < board.cols) rises.push_back(edge_rise_px(image, c, d.corners[static_cast<std::size_t>(j * board.cols + i + 1)]));
      if (j + 1 < board.rows) rises.push_back(edge_rise_px(image, c, d.corners[static_cast<std::size_t>((j + 1) * board.cols + i)]));
    }
  rises.erase(std::remove_if(rises.begin(), rises.end(), [](double r) { return r < 0.0; }), rises.end());
  d.blur_px = median(rises);
  return d;
}

void refine_corners(GrayView image, const render::CheckerboardSpec& board, std::vector<Vec2>& corners,
                    const render::PinholeCamera* lens) {
  if (corners.size() != static_cast<std::size_t>(board.cols * board.rows)) return;
  const std::vector<Vec2> start = corners;
  const auto at = [&](int i, int j) { return start[static_cast<std::size_t>(j * board.cols + i)]; };
  const double share = kCornerWindowShare;
  for (int j = 0; j < board.rows; ++j)
    for (int i = 0; i < board.cols; ++i) {
      const Vec2 c = at(i, j);
      const Vec2 along_row = at(std::min(i + 1, board.cols - 1), j) - at(std::max(i - 1, 0), j);
      const Vec2 along_col = at(i, std::min(j + 1, board.rows - 1)) - at(i, std::max(j - 1, 0));
      double nearest = 1e9;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di)
          if ((di != 0 || dj != 0) && i + di >= 0 && i + di < board.cols && j + dj >= 0 && j + dj < board.rows)
            nearest = std::min(nearest, (at(i + di, j + dj) - c).norm());
      Vec2 refined = c;
      if (fit_corner_model(image, refined, along_row.normalized(), along_col.normalized(), std::clamp(share * nearest, 2.5, 15.0), lens))
        corners[static_cast<std::size_t>(j * board.cols + i)] = refined;
    }
}

double mean_corner_distance(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  if (a.size() != b.size() || a.empty()) return 1e9;
  // The detector may number a board from either end (a half turn of it looks the same).
  double same = 0.0, reversed = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    same += (a[i] - b[i]).norm();
    reversed += (a[i] - b[b.size() - 1 - i]).norm();
  }
  return std::min(same, reversed) / static_cast<double>(a.size());
}

Coverage corner_coverage(const std::vector<std::vector<Vec2>>& views, int width, int height) {
  Coverage c;
  c.counts.assign(static_cast<std::size_t>(c.cols * c.rows), 0);
  for (const auto& v : views)
    for (const Vec2& p : v) {
      const int gx = std::clamp(static_cast<int>(p.x() / width * c.cols), 0, c.cols - 1);
      const int gy = std::clamp(static_cast<int>(p.y() / height * c.rows), 0, c.rows - 1);
      ++c.counts[static_cast<std::size_t>(gy * c.cols + gx)];
    }
  const auto covered = std::count_if(c.counts.begin(), c.counts.end(), [](int n) { return n > 0; });
  c.share = static_cast<double>(covered) / static_cast<double>(c.counts.size());
  return c;
}

Result<Calibration> calibrate(const std::vector<std::vector<Vec2>>& views, const render::CheckerboardSpec& board,
                              LensModel model, int width, int height) {
  if (views.size() < 3) return invalid_argument("calibration needs at least 3 views");
  std::vector<std::vector<cv::Point3d>> object(views.size());
  std::vector<std::vector<cv::Point2d>> image(views.size());
  for (std::size_t v = 0; v < views.size(); ++v) {
    for (int k = 0; k < board.cols * board.rows; ++k) {
      const Vec3 p = board.corner(k % board.cols, k / board.cols);
      object[v].emplace_back(p.x(), p.y(), p.z());
      image[v].emplace_back(views[v][static_cast<std::size_t>(k)].x(), views[v][static_cast<std::size_t>(k)].y());
    }
  }
  Calibration out;
  out.camera.width = width;
  out.camera.height = height;
  std::vector<cv::Vec3d> rvecs, tvecs;
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 200, 1e-12);
  try {
    if (model == LensModel::kFisheye) {
      // OpenCV starts the fisheye fit at f = width / pi with no distortion, where the corners of a
      // wide lens's image lie past 90 degrees and the fit stops where it began. It starts here
      // from a few focal lengths (180 down to 65 degrees across the width) and keeps the best.
      double best_rms = INFINITY;
      for (const double share : {0.32, 0.45, 0.6, 0.8}) {
        cv::Matx33d K(share * width, 0.0, 0.5 * (width - 1), 0.0, share * width, 0.5 * (height - 1), 0.0, 0.0, 1.0);
        cv::Vec4d D(0.0, 0.0, 0.0, 0.0);
        std::vector<cv::Vec3d> rv, tv;
        double rms = INFINITY;
        try {
          rms = cv::fisheye::calibrate(object, image, cv::Size(width, height), K, D, rv, tv,
                                       cv::fisheye::CALIB_USE_INTRINSIC_GUESS | cv::fisheye::CALIB_RECOMPUTE_EXTRINSIC |
                                           cv::fisheye::CALIB_FIX_SKEW,
                                       criteria);
        } catch (const cv::Exception&) {
          continue;  // another start may do
        }
        if (!std::isfinite(rms) || rms >= best_rms || rv.size() != views.size()) continue;
        best_rms = rms;
        out.camera.fx = K(0, 0);
        out.camera.fy = K(1, 1);
        out.camera.cx = K(0, 2);
        out.camera.cy = K(1, 2);
        out.camera.distortion = render::PinholeCamera::Distortion::kEquidistant;
        out.camera.coeffs = {D[0], D[1], D[2], D[3]};
        rvecs = rv;
        tvecs = tv;
      }
      if (!std::isfinite(best_rms)) return invalid_argument("the fisheye fit failed from every start");
    } else {
      std::vector<std::vector<cv::Point3f>> object_f(views.size());
      std::vector<std::vector<cv::Point2f>> image_f(views.size());
      for (std::size_t v = 0; v < views.size(); ++v) {
        for (const cv::Point3d& p : object[v]) object_f[v].emplace_back(static_cast<float>(p.x), static_cast<float>(p.y), 0.0f);
        for (const cv::Point2d& p : image[v]) image_f[v].emplace_back(static_cast<float>(p.x), static_cast<float>(p.y));
      }
      cv::Mat K, D;
      std::vector<cv::Mat> rv, tv;
      const double opencv_rms = cv::calibrateCamera(object_f, image_f, cv::Size(width, height), K, D, rv, tv, cv::CALIB_FIX_K3, criteria);
      // OpenCV starts from the views' homographies without distortion. With views far into the
      // corners of a strongly distorted lens that start ends in a local minimum (measured on
      // exact corners with 0.06 px noise: 0.28 px rms and fx 5 px off, where the true lens gives
      // 0.083 px). The views whose corners all stay within 70 % of the half-diagonal, where the
      // distortion is mild, give a start from which the fit of every view reaches it. The lower
      // RMS of the two wins.
      std::vector<std::vector<cv::Point3f>> central_object;
      std::vector<std::vector<cv::Point2f>> central_image;
      const double limit_px = 0.7 * std::hypot(0.5 * width, 0.5 * height);
      for (std::size_t v = 0; v < views.size(); ++v) {
        const bool central = std::all_of(image_f[v].begin(), image_f[v].end(), [&](const cv::Point2f& q) {
          return std::hypot(q.x - 0.5 * width, q.y - 0.5 * height) < limit_px;
        });
        if (central) {
          central_object.push_back(object_f[v]);
          central_image.push_back(image_f[v]);
        }
      }
      if (central_object.size() >= 3 && central_object.size() < views.size()) {
        cv::Mat K2, D2;
        std::vector<cv::Mat> rv2, tv2;
        cv::calibrateCamera(central_object, central_image, cv::Size(width, height), K2, D2, rv2, tv2, cv::CALIB_FIX_K3, criteria);
        const double rms = cv::calibrateCamera(object_f, image_f, cv::Size(width, height), K2, D2, rv2, tv2,
                                               cv::CALIB_FIX_K3 | cv::CALIB_USE_INTRINSIC_GUESS, criteria);
        if (rms < opencv_rms) {
          K = K2;
          D = D2;
          rv = rv2;
          tv = tv2;
        }
      }
      out.camera.fx = K.at<double>(0, 0);
      out.camera.fy = K.at<double>(1, 1);
      out.camera.cx = K.at<double>(0, 2);
      out.camera.cy = K.at<double>(1, 2);
      out.camera.distortion = render::PinholeCamera::Distortion::kRadTan;
      out.camera.coeffs = {D.at<double>(0), D.at<double>(1), D.at<double>(2), D.at<double>(3)};
      for (std::size_t v = 0; v < rv.size(); ++v) {
        rvecs.emplace_back(rv[v].at<double>(0), rv[v].at<double>(1), rv[v].at<double>(2));
        tvecs.emplace_back(tv[v].at<double>(0), tv[v].at<double>(1), tv[v].at<double>(2));
      }
    }
  } catch (const cv::Exception& e) {
    return invalid_argument(std::string("the fit failed (OpenCV: ") + e.err + ")");
  }
  if (rvecs.size() != views.size()) return invalid_argument("the fit failed: no board pose for every view");
  Result<geometry::Camera> lens = out.camera.lens();
  if (!lens.ok()) return invalid_argument("the fit gave a lens the daemon cannot use: " + lens.status().message());
  for (std::size_t v = 0; v < views.size(); ++v) {
    render::BoardPose p;
    const Vec3 r(rvecs[v][0], rvecs[v][1], rvecs[v][2]);
    p.R_cb = r.norm() > 0 ? Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix() : Eigen::Matrix3d::Identity();
    p.t_cb = Vec3(tvecs[v][0], tvecs[v][1], tvecs[v][2]);
    out.poses.push_back(p);
  }
  const Status checked = evaluate(views, board, out);
  if (!checked.ok()) {
    char buf[256];
    std::snprintf(buf, sizeof buf, " (the fit gave fx %.2f fy %.2f cx %.2f cy %.2f, coefficients %.4g %.4g %.4g %.4g)",
                  out.camera.fx, out.camera.fy, out.camera.cx, out.camera.cy, out.camera.coeffs[0], out.camera.coeffs[1],
                  out.camera.coeffs[2], out.camera.coeffs[3]);
    return invalid_argument(checked.message() + buf);
  }
  return out;
}

Result<Calibration> refit_with_lens(const std::function<Status(std::size_t, GrayImage&)>& image_of,
                                    std::vector<std::vector<Vec2>>& views, const render::CheckerboardSpec& board,
                                    LensModel model, int width, int height, const Calibration& first) {
  GrayImage image;
  for (std::size_t v = 0; v < views.size(); ++v) {
    if (Status s = image_of(v, image); !s.ok()) return s;
    if (image.width != width || image.height != height) return invalid_argument("refit_with_lens: an image is not the calibrated size");
    refine_corners(image.view(), board, views[v], &first.camera);
  }
  return calibrate(views, board, model, width, height);
}

Status evaluate(const std::vector<std::vector<Vec2>>& views, const render::CheckerboardSpec& board, Calibration& c) {
  if (views.size() != c.poses.size()) return invalid_argument("evaluate: one board pose per view needed");
  double params[8] = {c.camera.fx, c.camera.fy, c.camera.cx, c.camera.cy,
                      c.camera.coeffs[0], c.camera.coeffs[1], c.camera.coeffs[2], c.camera.coeffs[3]};
  Result<geometry::Camera> lens = c.camera.lens();
  if (!lens.ok()) return lens.status();
  // Pixel of board point X seen from pose (R, t) through `cam`; false behind the lens.
  const auto project = [&](const geometry::Camera& cam, const Eigen::Matrix3d& R, const Vec3& t, const Vec3& X, Vec2& uv) {
    return cam.project(R * X + t, &uv);
  };
  using Mat8 = Eigen::Matrix<double, 8, 8>;
  using Mat86 = Eigen::Matrix<double, 8, 6>;
  using Mat6 = Eigen::Matrix<double, 6, 6>;
  Mat8 schur = Mat8::Zero();
  double sse = 0.0;
  int n = 0;
  c.view_rms_px.clear();
  // Central differences; steps relative to each parameter's scale.
  const double steps[8] = {1e-4 * c.camera.fx, 1e-4 * c.camera.fy, 1e-3, 1e-3, 1e-6, 1e-6, 1e-6, 1e-6};
  std::vector<geometry::Camera> plus(8), minus(8);
  for (int k = 0; k < 8; ++k) {
    double p[8], m[8];
    std::copy(params, params + 8, p);
    std::copy(params, params + 8, m);
    p[k] += steps[k];
    m[k] -= steps[k];
    Result<geometry::Camera> cp = with_parameters(c.camera, p).lens();
    Result<geometry::Camera> cm = with_parameters(c.camera, m).lens();
    if (!cp.ok() || !cm.ok()) return invalid_argument("evaluate: the lens is at the edge of its valid range");
    plus[static_cast<std::size_t>(k)] = *cp;
    minus[static_cast<std::size_t>(k)] = *cm;
  }
  for (std::size_t v = 0; v < views.size(); ++v) {
    const Eigen::Matrix3d& R = c.poses[v].R_cb;
    const Vec3& t = c.poses[v].t_cb;
    Mat86 B = Mat86::Zero();
    Mat6 C = Mat6::Zero();
    Mat8 A = Mat8::Zero();
    double view_sse = 0.0;
    for (int k = 0; k < board.cols * board.rows; ++k) {
      const Vec3 X = board.corner(k % board.cols, k / board.cols);
      Vec2 uv;
      if (!project(*lens, R, t, X, uv)) return invalid_argument("evaluate: a corner projects behind the lens");
      const double e2 = (views[v][static_cast<std::size_t>(k)] - uv).squaredNorm();
      view_sse += e2;
      Eigen::Matrix<double, 2, 8> Ji;
      Eigen::Matrix<double, 2, 6> Je;
      for (int q = 0; q < 8; ++q) {
        Vec2 a, b;
        project(plus[static_cast<std::size_t>(q)], R, t, X, a);
        project(minus[static_cast<std::size_t>(q)], R, t, X, b);
        Ji.col(q) = (a - b) / (2.0 * steps[q]);
      }
      for (int q = 0; q < 6; ++q) {
        constexpr double kRot = 1e-6, kTrans = 1e-7;
        Vec2 a, b;
        if (q < 3) {
          const Eigen::Matrix3d dR = Eigen::AngleAxisd(kRot, Vec3::Unit(q)).toRotationMatrix();
          project(*lens, dR * R, t, X, a);
          project(*lens, dR.transpose() * R, t, X, b);
          Je.col(q) = (a - b) / (2.0 * kRot);
        } else {
          project(*lens, R, t + kTrans * Vec3::Unit(q - 3), X, a);
          project(*lens, R, t - kTrans * Vec3::Unit(q - 3), X, b);
          Je.col(q) = (a - b) / (2.0 * kTrans);
        }
      }
      A += Ji.transpose() * Ji;
      B += Ji.transpose() * Je;
      C += Je.transpose() * Je;
    }
    const int m = board.cols * board.rows;
    c.view_rms_px.push_back(std::sqrt(view_sse / m));
    sse += view_sse;
    n += m;
    // The view's pose marginalised out: A - B C^-1 B^T.
    schur += A - B * C.ldlt().solve(B.transpose());
  }
  c.corners = n;
  c.rms_px = std::sqrt(sse / n);
  const int dof = 2 * n - 8 - 6 * static_cast<int>(views.size());
  const double sigma2 = dof > 0 ? sse / dof : 0.0;
  const Mat8 cov = sigma2 * schur.inverse();
  for (int k = 0; k < 8; ++k) c.stddev[static_cast<std::size_t>(k)] = std::sqrt(std::max(0.0, cov(k, k)));
  return {};
}

}  // namespace ale::calib
