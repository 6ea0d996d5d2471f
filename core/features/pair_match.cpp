#include "core/features/pair_match.h"

#include <cmath>
#include <limits>
#include <string>

#include "core/geometry/two_view.h"

namespace ale::features {
namespace {

constexpr int kNone = -1;
constexpr int kFar = std::numeric_limits<int>::max();

// For each of `from`, the index of its nearest neighbour in `to` and the two smallest distances.
void nearest_two(const std::vector<Descriptor>& from, const std::vector<Descriptor>& to, std::vector<int>& best_index,
                 std::vector<int>& best, std::vector<int>& second) {
  best_index.assign(from.size(), kNone);
  best.assign(from.size(), kFar);
  second.assign(from.size(), kFar);
  for (std::size_t i = 0; i < from.size(); ++i) {
    int b = kFar, s = kFar, bi = kNone;
    for (std::size_t j = 0; j < to.size(); ++j) {
      const int d = hamming_distance(from[i], to[j]);
      if (d < b) {
        s = b;
        b = d;
        bi = static_cast<int>(j);
      } else if (d < s) {
        s = d;
      }
    }
    best_index[i] = bi;
    best[i] = b;
    second[i] = s;
  }
}

// Passes the ratio test: a second neighbour that is missing counts as infinitely far.
bool distinct(int best, int second, double ratio) {
  return second == kFar || static_cast<double>(best) < ratio * static_cast<double>(second);
}

// The distance of x to the line l (homogeneous), pixels.
double line_distance(const geometry::Vec3& l, const geometry::Vec2& x) {
  const double n = std::hypot(l.x(), l.y());
  if (!(n > 0.0)) return std::numeric_limits<double>::infinity();
  return std::abs(l.x() * x.x() + l.y() * x.y() + l.z()) / n;
}

// The RANSAC problem (ransac.h): 8-point F, scored by the inlier count at the epipolar gate.
struct FundamentalProblem {
  static constexpr int kSampleSize = geometry::kTwoViewSampleSize;
  static constexpr int kMaxModels = 1;
  using Model = geometry::Mat3;

  const std::vector<geometry::Vec2>& x1;
  const std::vector<geometry::Vec2>& x2;
  double gate_px;

  int size() const { return static_cast<int>(x1.size()); }
  int fit(const int* sample, Model* models) const {
    geometry::Vec2 a[kSampleSize], b[kSampleSize];
    for (int k = 0; k < kSampleSize; ++k) {
      a[k] = x1[static_cast<std::size_t>(sample[k])];
      b[k] = x2[static_cast<std::size_t>(sample[k])];
    }
    return geometry::fundamental_8point(a, b, kSampleSize, &models[0]) ? 1 : 0;
  }
  double score(const Model& F_21, std::uint8_t* mask, int* inliers) const {
    int n = 0;
    for (std::size_t i = 0; i < x1.size(); ++i) {
      const geometry::Vec3 p1(x1[i].x(), x1[i].y(), 1.0), p2(x2[i].x(), x2[i].y(), 1.0);
      const bool in = line_distance(F_21 * p1, x2[i]) <= gate_px && line_distance(F_21.transpose() * p2, x1[i]) <= gate_px;
      mask[i] = in ? 1 : 0;
      n += in ? 1 : 0;
    }
    *inliers = n;
    return n;
  }
};

}  // namespace

void match_descriptors(const std::vector<Descriptor>& a, const std::vector<Descriptor>& b,
                       const PairMatchParams& params, PairMatchScratch& scratch) {
  scratch.matches.clear();
  if (a.empty() || b.empty()) return;
  nearest_two(a, b, scratch.nearest_in_b, scratch.best_a, scratch.second_a);
  nearest_two(b, a, scratch.nearest_in_a, scratch.best_b, scratch.second_b);
  for (std::size_t i = 0; i < a.size(); ++i) {
    const int j = scratch.nearest_in_b[i];
    if (j == kNone || scratch.nearest_in_a[static_cast<std::size_t>(j)] != static_cast<int>(i)) continue;
    const std::size_t jj = static_cast<std::size_t>(j);
    if (scratch.best_a[i] > params.max_hamming) continue;
    if (!distinct(scratch.best_a[i], scratch.second_a[i], params.ratio) ||
        !distinct(scratch.best_b[jj], scratch.second_b[jj], params.ratio))
      continue;
    scratch.matches.emplace_back(static_cast<int>(i), j);
  }
}

Result<PairMatchFigures> match_pair(const std::vector<Keypoint>& kps_a, const std::vector<Descriptor>& desc_a,
                                    const std::vector<Keypoint>& kps_b, const std::vector<Descriptor>& desc_b,
                                    const PairMatchParams& params, PairMatchScratch& scratch) {
  if (kps_a.size() != desc_a.size() || kps_b.size() != desc_b.size())
    return invalid_argument("match_pair: " + std::to_string(kps_a.size()) + "/" + std::to_string(kps_b.size()) +
                            " keypoints but " + std::to_string(desc_a.size()) + "/" + std::to_string(desc_b.size()) +
                            " descriptors");
  if (params.max_hamming < 0 || !(params.ratio > 0.0 && params.ratio <= 1.0) || !(params.epipolar_px > 0.0) ||
      params.max_iterations < 1)
    return invalid_argument("match_pair: max_hamming >= 0, ratio in (0, 1], epipolar_px > 0, max_iterations >= 1");
  PairMatchFigures f;
  f.keypoints_a = static_cast<int>(kps_a.size());
  f.keypoints_b = static_cast<int>(kps_b.size());
  match_descriptors(desc_a, desc_b, params, scratch);
  f.matches = static_cast<int>(scratch.matches.size());
  if (f.matches < geometry::kTwoViewSampleSize) return f;
  scratch.x1.clear();
  scratch.x2.clear();
  for (const auto& [i, j] : scratch.matches) {
    const Keypoint& p = kps_a[static_cast<std::size_t>(i)];
    const Keypoint& q = kps_b[static_cast<std::size_t>(j)];
    scratch.x1.emplace_back(p.x, p.y);
    scratch.x2.emplace_back(q.x, q.y);
  }
  const FundamentalProblem problem{scratch.x1, scratch.x2, params.epipolar_px};
  geometry::RansacParams rp;
  rp.seed = params.seed;
  rp.max_iterations = params.max_iterations;
  rp.confidence = params.confidence;
  geometry::Mat3 F_21;
  geometry::RansacStats stats;
  if (!geometry::ransac(problem, rp, geometry::kTwoViewSampleSize, &F_21, scratch.mask, &stats, scratch.ransac).ok())
    return f;
  int inliers = stats.inliers;
  // Refit on all inliers while that admits more (the minimal sample's F is noisy).
  std::vector<geometry::Vec2>& in1 = scratch.in1;
  std::vector<geometry::Vec2>& in2 = scratch.in2;
  std::vector<std::uint8_t>& mask = scratch.refit_mask;
  mask.resize(scratch.x1.size());
  for (int round = 0; round < 5; ++round) {
    in1.clear();
    in2.clear();
    for (std::size_t k = 0; k < scratch.x1.size(); ++k)
      if (scratch.mask[k]) {
        in1.push_back(scratch.x1[k]);
        in2.push_back(scratch.x2[k]);
      }
    geometry::Mat3 refit;
    if (!geometry::fundamental_8point(in1.data(), in2.data(), static_cast<int>(in1.size()), &refit)) break;
    int n = 0;
    problem.score(refit, mask.data(), &n);
    if (n <= inliers) break;
    inliers = n;
    scratch.mask.swap(mask);
  }
  f.inliers = inliers;
  return f;
}

}  // namespace ale::features
