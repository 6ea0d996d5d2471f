#include "app/tools/lib/ba/libmv_problem.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <unordered_map>

#include "core/base/rng.h"

namespace ale::optim {
namespace {

using geometry::Mat3;
using geometry::SE3;
using geometry::SO3;
using geometry::Vec3;

// Reads 4-byte values in the file's byte order.
class Reader {
 public:
  Reader(const std::vector<unsigned char>& bytes, bool big_endian) : b_(bytes), big_(big_endian) {}
  bool u32(std::uint32_t* v) {
    if (pos_ + 4 > b_.size()) return false;
    const unsigned char* p = b_.data() + pos_;
    *v = big_ ? (std::uint32_t{p[0]} << 24 | std::uint32_t{p[1]} << 16 | std::uint32_t{p[2]} << 8 | p[3])
              : (std::uint32_t{p[3]} << 24 | std::uint32_t{p[2]} << 16 | std::uint32_t{p[1]} << 8 | p[0]);
    pos_ += 4;
    return true;
  }
  bool i32(int* v) {
    std::uint32_t u = 0;
    if (!u32(&u)) return false;
    std::int32_t s = 0;
    std::memcpy(&s, &u, 4);
    *v = s;
    return true;
  }
  bool f32(double* v) {
    std::uint32_t u = 0;
    if (!u32(&u)) return false;
    float f = 0.0f;
    std::memcpy(&f, &u, 4);
    *v = f;
    return std::isfinite(*v);
  }
  void skip(std::size_t n) { pos_ += n; }
  std::size_t left() const { return b_.size() - std::min(pos_, b_.size()); }

 private:
  const std::vector<unsigned char>& b_;
  bool big_;
  std::size_t pos_ = 0;
};

double median_of(std::vector<double>* v) {
  if (v->empty()) return 0.0;
  auto mid = v->begin() + static_cast<std::ptrdiff_t>(v->size() / 2);
  std::nth_element(v->begin(), mid, v->end());
  return *mid;
}

Vec3 random_unit(SplitMix64* rng) {
  // Uniform on the sphere from two uniforms (z uniform in [-1, 1], azimuth uniform).
  const double z = 2.0 * rng->uniform_double() - 1.0;
  const double a = 2.0 * M_PI * rng->uniform_double();
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return Vec3(r * std::cos(a), r * std::sin(a), z);
}

}  // namespace

Result<LibmvProblem> load_libmv_problem(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return not_found("cannot open libmv problem " + path);
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto corrupt = [&](const std::string& what) { return corrupt_data(path + ": " + what); };
  if (bytes.size() < 2) return corrupt("shorter than its 2-byte header");
  if (bytes[0] != 'v' && bytes[0] != 'V') return corrupt("first byte is not the byte-order tag v or V");
  if (bytes[1] != 'P' && bytes[1] != 'N') return corrupt("second byte is not the observation-space tag P or N");
  Reader r(bytes, bytes[0] == 'V');
  r.skip(2);

  LibmvProblem p;
  p.normalised_observations = bytes[1] == 'N';
  double f = 0, cx = 0, cy = 0, k1 = 0, k2 = 0, k3 = 0, p1 = 0, p2 = 0;
  for (double* v : {&f, &cx, &cy, &k1, &k2, &k3, &p1, &p2}) {
    if (!r.f32(v)) return corrupt("truncated or non-finite intrinsics");
  }
  p.intrinsics.model = geometry::CameraModel::kPinholeRadTan;
  p.intrinsics.fx = p.intrinsics.fy = f;
  p.intrinsics.cx = cx;
  p.intrinsics.cy = cy;
  p.intrinsics.distortion = {k1, k2, p1, p2, k3};

  int n = 0;
  if (!r.i32(&n) || n < 0 || static_cast<std::size_t>(n) > r.left() / 52) return corrupt("bad camera count");
  std::unordered_map<int, int> camera_of_id, point_of_id;
  for (int i = 0; i < n; ++i) {
    int id = 0;
    double v[12];
    if (!r.i32(&id)) return corrupt("truncated camera");
    for (double& x : v) {
      if (!r.f32(&x)) return corrupt("truncated or non-finite camera");
    }
    Mat3 rot;
    for (int c = 0; c < 3; ++c) {
      for (int row = 0; row < 3; ++row) rot(row, c) = v[3 * c + row];  // column-major in the file
    }
    const SE3 T(SO3::from_matrix(rot), Vec3(v[9], v[10], v[11]));
    // A repeated id replaces the earlier camera, as libmv's reader does.
    const auto [it, fresh] = camera_of_id.emplace(id, static_cast<int>(p.T_cw.size()));
    if (fresh) {
      p.image_ids.push_back(id);
      p.T_cw.push_back(T);
    } else {
      p.T_cw[it->second] = T;
    }
  }
  if (!r.i32(&n) || n < 0 || static_cast<std::size_t>(n) > r.left() / 16) return corrupt("bad point count");
  for (int i = 0; i < n; ++i) {
    int id = 0;
    Vec3 x;
    if (!r.i32(&id) || !r.f32(&x.x()) || !r.f32(&x.y()) || !r.f32(&x.z())) return corrupt("truncated or non-finite point");
    const auto [it, fresh] = point_of_id.emplace(id, static_cast<int>(p.points_w.size()));
    if (fresh) {
      p.track_ids.push_back(id);
      p.points_w.push_back(x);
    } else {
      p.points_w[it->second] = x;
    }
  }
  if (!r.i32(&n) || n < 0 || static_cast<std::size_t>(n) > r.left() / 16) return corrupt("bad observation count");
  p.observations.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    int image = 0, track = 0;
    LibmvObservation o;
    if (!r.i32(&image) || !r.i32(&track) || !r.f32(&o.uv_px.x()) || !r.f32(&o.uv_px.y())) {
      return corrupt("truncated or non-finite observation");
    }
    const auto c = camera_of_id.find(image);
    const auto t = point_of_id.find(track);
    if (c == camera_of_id.end() || t == point_of_id.end()) {
      ++p.skipped_observations;  // libmv's adjuster skips markers without a camera or a point too
      continue;
    }
    o.camera = c->second;
    o.point = t->second;
    p.observations.push_back(o);
  }
  if (r.left() != 0) return corrupt(std::to_string(r.left()) + " bytes after the last observation");
  return p;
}

void perturb_libmv_problem(std::uint64_t seed, double rotation_deg, double relative, LibmvProblem* problem) {
  LibmvProblem& p = *problem;
  std::vector<std::vector<double>> camera_depths(p.T_cw.size()), point_depths(p.points_w.size());
  for (const LibmvObservation& o : p.observations) {
    const double z = (p.T_cw[o.camera] * p.points_w[o.point]).z();
    camera_depths[o.camera].push_back(std::abs(z));
    point_depths[o.point].push_back(std::abs(z));
  }
  SplitMix64 rng(seed);
  const double angle_rad = rotation_deg * M_PI / 180.0;
  for (std::size_t i = 0; i < p.T_cw.size(); ++i) {
    const double move = relative * median_of(&camera_depths[i]);
    const SO3 dr = SO3::exp(angle_rad * random_unit(&rng));
    const SE3& t = p.T_cw[i];
    // Centre c = -R^T t moves by `move`; the rotation turns on the left (camera frame).
    const Vec3 centre = -(t.so3().inverse() * t.translation()) + move * random_unit(&rng);
    const SO3 r_new = dr * t.so3();
    p.T_cw[i] = SE3(r_new, -(r_new * centre));
  }
  for (std::size_t j = 0; j < p.points_w.size(); ++j) {
    p.points_w[j] += relative * median_of(&point_depths[j]) * random_unit(&rng);
  }
}

double libmv_cost(const LibmvProblem& problem, const geometry::Camera& camera) {
  double cost = 0.0;
  for (const LibmvObservation& o : problem.observations) {
    geometry::Vec2 uv;
    if (!camera.project(problem.T_cw[o.camera] * problem.points_w[o.point], &uv)) {
      return std::numeric_limits<double>::infinity();
    }
    cost += 0.5 * (uv - o.uv_px).squaredNorm();
  }
  return cost;
}

}  // namespace ale::optim
