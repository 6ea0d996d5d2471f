// Feature-matching figures under an identity ground truth (fixed cameras, or a frame and a
// relit copy of it), shared by the real-data feature tests: repeatability and matching score as
// the ORB front-end issue defines them.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <utility>
#include <vector>

#include "core/features/orb.h"
#include "core/frontend/frame_path.h"

namespace ale::test {

using features::Descriptor;
using features::ExtractorConfig;
using features::Keypoint;
using frontend::FramePath;

struct Extraction {
  std::vector<Keypoint> kps;
  std::vector<Descriptor> desc;
};

inline Extraction extract(const ExtractorConfig& cfg, const GrayImage& img) {
  FramePath ex;
  Extraction e;
  EXPECT_TRUE(ex.configure(cfg).ok());
  const Status st = ex.extract(img.view(), e.kps, e.desc);
  EXPECT_TRUE(st.ok()) << st.to_string();
  return e;
}

inline double mean_grey(const GrayImage& img) {
  double s = 0.0;
  for (std::uint8_t v : img.pixels) s += v;
  return s / static_cast<double>(img.pixels.size());
}

// Index of the descriptor of `to` nearest to d (Hamming), or -1 when `to` is empty.
inline int nearest(const Descriptor& d, const std::vector<Descriptor>& to) {
  int best = -1;
  int best_d = 1 << 30;
  for (std::size_t j = 0; j < to.size(); ++j) {
    const int h = features::hamming_distance(d, to[j]);
    if (h < best_d) {
      best_d = h;
      best = static_cast<int>(j);
    }
  }
  return best;
}

// Mutual nearest-neighbour matches (i in a, j in b).
inline std::vector<std::pair<int, int>> mutual_matches(const Extraction& a, const Extraction& b) {
  std::vector<int> b_to_a(b.desc.size());
  for (std::size_t j = 0; j < b.desc.size(); ++j) b_to_a[j] = nearest(b.desc[j], a.desc);
  std::vector<std::pair<int, int>> out;
  for (std::size_t i = 0; i < a.desc.size(); ++i) {
    const int j = nearest(a.desc[i], b.desc);
    if (j >= 0 && b_to_a[static_cast<std::size_t>(j)] == static_cast<int>(i)) out.push_back({static_cast<int>(i), j});
  }
  return out;
}

// Share of keypoints with a partner within `tol` px (identity ground truth), over the smaller count.
inline double repeatability(const Extraction& a, const Extraction& b, double tol) {
  const auto covered = [tol](const Extraction& from, const Extraction& to) {
    int n = 0;
    for (const Keypoint& p : from.kps) {
      for (const Keypoint& q : to.kps) {
        if (std::hypot(p.x - q.x, p.y - q.y) <= tol) {
          ++n;
          break;
        }
      }
    }
    return n;
  };
  const std::size_t smaller = std::min(a.kps.size(), b.kps.size());
  if (smaller == 0) return 0.0;
  return static_cast<double>(std::min(covered(a, b), covered(b, a))) / static_cast<double>(smaller);
}

// Mutual nearest-neighbour matches landing within `tol` px, over the smaller count.
inline double matching_score(const Extraction& a, const Extraction& b, double tol) {
  const std::size_t smaller = std::min(a.kps.size(), b.kps.size());
  if (smaller == 0) return 0.0;
  int good = 0;
  for (const auto& [i, j] : mutual_matches(a, b)) {
    const Keypoint& p = a.kps[static_cast<std::size_t>(i)];
    const Keypoint& q = b.kps[static_cast<std::size_t>(j)];
    if (std::hypot(p.x - q.x, p.y - q.y) <= tol) ++good;
  }
  return static_cast<double>(good) / static_cast<double>(smaller);
}

}  // namespace ale::test
