#include "app/tools/lib/render/checkerboard.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "app/tools/lib/render/rng.h"

namespace ale::render {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kGridCols = 5;  // aim points: a 5 x 4 grid from edge to edge of the image
constexpr int kGridRows = 4;
constexpr double kMarginPx = 3.0;
constexpr float kBlack = 0.06f;
constexpr float kWhite = 0.9f;
constexpr float kBackground = 0.42f;
constexpr int kEdgeSamples = 16;  // per side of a pixel an edge crosses

bool parse_count(const std::string& text, int& out) {
  if (text.empty() || text.size() > 3) return false;
  for (char c : text)
    if (c < '0' || c > '9') return false;
  out = std::atoi(text.c_str());
  return out >= 2 && out <= 64;
}

// The board's white plate, outer edge: one square of border around the squares.
void plate_extent(const CheckerboardSpec& b, double& x0, double& x1, double& y0, double& y1) {
  x0 = -2.0 * b.square_m;
  y0 = -2.0 * b.square_m;
  x1 = (b.cols + 1) * b.square_m;
  y1 = (b.rows + 1) * b.square_m;
}

// Albedo of board point (x, y) (board frame, metres); the background beyond the plate.
float albedo(const CheckerboardSpec& b, double x, double y) {
  double x0, x1, y0, y1;
  plate_extent(b, x0, x1, y0, y1);
  if (x < x0 || x > x1 || y < y0 || y > y1) return kBackground;
  const double s = b.square_m;
  if (x < -s || x >= b.cols * s || y < -s || y >= b.rows * s) return kWhite;
  const long ix = static_cast<long>(std::floor(x / s)) + 1;
  const long iy = static_cast<long>(std::floor(y / s)) + 1;
  return (ix + iy) % 2 == 0 ? kBlack : kWhite;
}

// Whether the squares and half of the white border around them project inside the image,
// kMarginPx from its edges (a detector needs some white around the squares, not all of it).
bool plate_inside(const PinholeCamera& cam, const CheckerboardSpec& b, const BoardPose& pose) {
  const double x0 = -1.5 * b.square_m, y0 = -1.5 * b.square_m;
  const double x1 = (b.cols + 0.5) * b.square_m, y1 = (b.rows + 0.5) * b.square_m;
  constexpr int kSteps = 12;
  for (int k = 0; k <= kSteps; ++k) {
    const double f = static_cast<double>(k) / kSteps;
    for (const Eigen::Vector3d& p_b : {Eigen::Vector3d(x0 + f * (x1 - x0), y0, 0.0), Eigen::Vector3d(x0 + f * (x1 - x0), y1, 0.0),
                                       Eigen::Vector3d(x0, y0 + f * (y1 - y0), 0.0), Eigen::Vector3d(x1, y0 + f * (y1 - y0), 0.0)}) {
      const Eigen::Vector3d p_c = pose.R_cb * p_b + pose.t_cb;
      // Beyond 80 degrees off axis a board is too foreshortened to be found.
      if (p_c.z() <= p_c.norm() * std::cos(80.0 * kPi / 180.0)) return false;
      const Eigen::Vector2d uv = cam.project(p_c);
      if (!(uv.x() >= kMarginPx && uv.y() >= kMarginPx && uv.x() <= cam.width - 1 - kMarginPx &&
            uv.y() <= cam.height - 1 - kMarginPx))
        return false;
    }
  }
  return true;
}

}  // namespace

Result<CheckerboardSpec> parse_board(const std::string& text) {
  const std::size_t x = text.find('x');
  CheckerboardSpec b;
  if (x == std::string::npos || !parse_count(text.substr(0, x), b.cols) || !parse_count(text.substr(x + 1), b.rows))
    return invalid_argument("board '" + text + "' is not COLSxROWS: inner corners along a row and a column, "
                            "whole numbers in 2..64 (e.g. 9x6)");
  return b;
}

std::vector<BoardPose> checkerboard_poses(const PinholeCamera& cam, const CheckerboardSpec& b, int n,
                                          std::uint64_t seed, bool into_corners) {
  std::vector<BoardPose> poses;
  const Eigen::Vector3d left = cam.ray(0.0, cam.cy);
  const Eigen::Vector3d right = cam.ray(cam.width - 1.0, cam.cy);
  const double fov = (left.isZero() || right.isZero()) ? 1.5 : std::acos(std::clamp(left.dot(right), -1.0, 1.0));
  double x0, x1, y0, y1;
  plate_extent(b, x0, x1, y0, y1);
  const Eigen::Vector3d centre_b(0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.0);
  const Eigen::Vector2d image_centre(cam.cx, cam.cy);
  SplitMix64 rng(mix_seed(seed, 0xB0A7D));
  for (int k = 0; k < n; ++k) {
    const int cell = k % (kGridCols * kGridRows);
    const double cell_w = (cam.width - 1.0) / (kGridCols - 1);
    const double cell_h = (cam.height - 1.0) / (kGridRows - 1);
    const bool on_edge = cell % kGridCols == 0 || cell % kGridCols == kGridCols - 1 || cell / kGridCols == 0 ||
                         cell / kGridCols == kGridRows - 1;
    bool placed = false;
    for (int draw = 0; draw < 50 && !placed; ++draw) {
      // Aims on the image's edges and corners end up as close to them as the board fits.
      Eigen::Vector2d aim((cell % kGridCols + 0.3 * (rng.uniform_double() - 0.5)) * cell_w,
                          (cell / kGridCols + 0.3 * (rng.uniform_double() - 0.5)) * cell_h);
      double width_share = 0.25 + 0.3 * rng.uniform_double();  // of the field of view
      const double tilt = (10.0 + 30.0 * rng.uniform_double()) * kPi / 180.0;
      const double tilt_axis = 2.0 * kPi * rng.uniform_double();
      // Into the corners a board is held square to the image (a rolled one cannot reach them).
      const double roll_range_deg = into_corners && on_edge ? 10.0 : 60.0;
      const double roll = (rng.uniform_double() - 0.5) * roll_range_deg * kPi / 180.0;
      const auto pose_at = [&](const Eigen::Vector3d& ray, double share) {
        BoardPose p;
        const Eigen::Matrix3d R_align = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), ray).toRotationMatrix();
        p.R_cb = R_align * Eigen::AngleAxisd(tilt, Eigen::Vector3d(std::cos(tilt_axis), std::sin(tilt_axis), 0.0)).toRotationMatrix() *
                 Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        const double distance = (x1 - x0) / (2.0 * std::tan(0.5 * std::min(share * fov, 2.5)));
        p.t_cb = distance * ray - p.R_cb * centre_b;
        return p;
      };
      if (into_corners) {
        // The board farther away (down to 15 % of the field of view) before the aim moves
        // towards the centre, in steps of 1 %.
        for (int step = 0; step < 100 && !placed; ++step) {
          const Eigen::Vector3d ray = cam.ray(aim.x(), aim.y());
          for (double share = width_share; share >= 0.15 && !placed && !ray.isZero(); share *= 0.95) {
            const BoardPose p = pose_at(ray, share);
            if (plate_inside(cam, b, p)) {
              poses.push_back(p);
              placed = true;
            }
          }
          aim = image_centre + 0.99 * (aim - image_centre);
        }
        continue;
      }
      // Pull the aim towards the centre and shrink the board until the whole plate is seen.
      for (int shrink = 0; shrink < 60 && !placed; ++shrink) {
        const Eigen::Vector3d ray = cam.ray(aim.x(), aim.y());
        if (!ray.isZero()) {
          const BoardPose p = pose_at(ray, width_share);
          if (plate_inside(cam, b, p)) {
            poses.push_back(p);
            placed = true;
          }
        }
        aim = image_centre + 0.96 * (aim - image_centre);
        width_share *= 0.985;
      }
    }
  }
  return poses;
}

CheckerboardRenderer::CheckerboardRenderer(const PinholeCamera& camera, const CheckerboardSpec& board, int supersample)
    : camera_(camera), board_(board), supersample_(std::clamp(supersample, 1, 8)) {
  const int ss = supersample_;
  rays_c_.reserve(static_cast<std::size_t>(camera.width) * static_cast<std::size_t>(camera.height) *
                  static_cast<std::size_t>(ss * ss));
  for (int y = 0; y < camera.height; ++y)
    for (int x = 0; x < camera.width; ++x)
      for (int j = 0; j < ss; ++j)
        for (int i = 0; i < ss; ++i)
          rays_c_.push_back(camera.ray(x + (i + 0.5) / ss - 0.5, y + (j + 0.5) / ss - 0.5).cast<float>());
  corner_rays_.reserve(static_cast<std::size_t>(camera.width + 1) * static_cast<std::size_t>(camera.height + 1));
  for (int y = 0; y <= camera.height; ++y)
    for (int x = 0; x <= camera.width; ++x) corner_rays_.push_back(camera.ray(x - 0.5, y - 0.5));
}

Status CheckerboardRenderer::render(const BoardPose& pose, double noise_grey, std::uint64_t noise_seed,
                                    MutableGrayView out) const {
  if (out.data == nullptr || out.width != camera_.width || out.height != camera_.height)
    return invalid_argument("checkerboard view: output image is not the camera's size");
  const Eigen::Vector3d n_c = pose.R_cb.col(2);  // the board's normal in the camera frame
  const double n_dot_t = n_c.dot(pose.t_cb);
  double x0, x1, y0, y1;
  plate_extent(board_, x0, x1, y0, y1);
  const int per_pixel = supersample_ * supersample_;
  SplitMix64 rng(noise_seed);
  // Grey level (before the noise) of the board point a camera ray meets; `hit` false where the
  // ray has no lens or the board is behind.
  const auto shade = [&](const Eigen::Vector3d& ray, bool& hit) {
    const double denom = n_c.dot(ray);
    const double lambda = std::abs(denom) > 1e-12 ? n_dot_t / denom : -1.0;
    hit = !ray.isZero() && lambda > 0.0;
    if (!hit) return 0.0;
    const Eigen::Vector3d p_b = pose.R_cb.transpose() * (lambda * ray - pose.t_cb);
    // Light falls off a little across the board (a lamp to one side).
    const double light = 0.8 + 0.2 * std::clamp((p_b.x() - x0) / (x1 - x0), 0.0, 1.0);
    return static_cast<double>(albedo(board_, p_b.x(), p_b.y())) * light;
  };
  const int fine = kEdgeSamples;
  std::size_t r = 0;
  for (int y = 0; y < camera_.height; ++y) {
    std::uint8_t* row = out.row(y);
    for (int x = 0; x < camera_.width; ++x) {
      double sum = 0.0, lo = INFINITY, hi = -INFINITY;
      for (int k = 0; k < per_pixel; ++k, ++r) {
        bool hit = false;
        const double g = shade(rays_c_[r].cast<double>(), hit);  // black where nothing is hit
        sum += g;
        lo = std::min(lo, g);
        hi = std::max(hi, g);
      }
      double mean = sum / per_pixel;
      // A pixel an edge crosses: its share of each side from fine x fine rays, interpolated
      // between the rays through the pixel's corners (a regular ss x ss grid leaves the edge's
      // position quantised, errors of up to 1 / (2 ss^2) of the contrast that repeat along it).
      const std::size_t c00 = static_cast<std::size_t>(y) * static_cast<std::size_t>(camera_.width + 1) + static_cast<std::size_t>(x);
      const std::size_t c10 = c00 + 1, c01 = c00 + static_cast<std::size_t>(camera_.width + 1), c11 = c01 + 1;
      if (hi - lo > 0.01 && !corner_rays_[c00].isZero() && !corner_rays_[c10].isZero() && !corner_rays_[c01].isZero() &&
          !corner_rays_[c11].isZero()) {
        double fine_sum = 0.0;
        for (int j = 0; j < fine; ++j) {
          const double v = (j + 0.5) / fine;
          for (int i = 0; i < fine; ++i) {
            const double u = (i + 0.5) / fine;
            const Eigen::Vector3d ray = (1 - v) * ((1 - u) * corner_rays_[c00] + u * corner_rays_[c10]) +
                                        v * ((1 - u) * corner_rays_[c01] + u * corner_rays_[c11]);
            bool hit = false;
            fine_sum += shade(ray, hit);
          }
        }
        mean = fine_sum / (fine * fine);
      }
      const double grey = 255.0 * mean + noise_grey * rng.gaussian();
      row[x] = static_cast<std::uint8_t>(std::clamp(std::lround(grey), 0L, 255L));
    }
  }
  return {};
}

}  // namespace ale::render
