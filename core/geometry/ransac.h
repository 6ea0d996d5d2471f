// One RANSAC for every solver: seeded sampling that gives the same result on every machine, an
// iteration count that adapts to the best inlier ratio seen (for a confidence) under a hard
// cap, and a score chosen by the problem (ORB-SLAM's truncated chi-square score, or the inlier
// count).
//
// A Problem provides:
//   static constexpr int kSampleSize;    // points in a minimal sample
//   static constexpr int kMaxModels;     // models one minimal sample can give (P3P: 4)
//   using Model = ...;
//   int size() const;                    // correspondences
//   // Models from the sample's indices (kSampleSize of them) into models[0..kMaxModels);
//   // returns how many (0 when the sample is degenerate).
//   int fit(const int* sample, Model* models) const;
//   // Score of a model (higher is better) and its inlier mask (1 for an inlier, size()
//   // entries); returns the number of inliers through *inliers.
//   double score(const Model& model, std::uint8_t* mask, int* inliers) const;
//   // Optional: the same with an early exit. It may stop once the model cannot score above
//   // `beat` and then returns a value not above beat (mask and count unspecified); a value above
//   // beat must be the exact score. RANSAC passes the best score so far, so the result is the
//   // same as without it.
//   double score(const Model& model, std::uint8_t* mask, int* inliers, double beat) const;
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "core/base/rng.h"
#include "core/base/status.h"

namespace ale::geometry {

struct RansacParams {
  std::uint64_t seed = 0;
  double confidence = 0.99;   // probability of drawing at least one all-inlier sample
  int max_iterations = 200;   // hard cap (ORB-SLAM's initialiser uses 200)
  int min_iterations = 1;
};

struct RansacStats {
  int iterations = 0;  // samples drawn
  int inliers = 0;     // inliers of the returned model
  double score = 0.0;
};

// Iterations needed to draw one all-inlier sample of size k with probability `confidence`
// when a share `inlier_ratio` of the data are inliers; `cap` when that cannot be reached.
inline int ransac_iterations_needed(double inlier_ratio, int k, double confidence, int cap) {
  if (inlier_ratio >= 1.0) return 1;
  if (inlier_ratio <= 0.0) return cap;
  const double p_good = std::pow(inlier_ratio, k);
  if (p_good <= 0.0) return cap;
  const double denom = std::log1p(-p_good);
  if (denom >= 0.0) return cap;
  const double n = std::ceil(std::log1p(-confidence) / denom);
  return n >= static_cast<double>(cap) ? cap : std::max(1, static_cast<int>(n));
}

// Draws k distinct indices in [0, n) (k <= n) with partial Fisher-Yates over `pool` (resized to
// n, kept between calls so that sampling does not allocate).
inline void ransac_draw(SplitMix64& rng, int n, int k, std::vector<int>& pool, int* out) {
  if (static_cast<int>(pool.size()) != n) {
    pool.resize(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) pool[static_cast<std::size_t>(i)] = i;
  }
  for (int i = 0; i < k; ++i) {
    const int j = i + static_cast<int>(rng.below(static_cast<std::uint32_t>(n - i)));
    std::swap(pool[static_cast<std::size_t>(i)], pool[static_cast<std::size_t>(j)]);
    out[i] = pool[static_cast<std::size_t>(i)];
  }
}

namespace detail {
template <class P, class = void>
struct HasBoundedScore : std::false_type {};
template <class P>
struct HasBoundedScore<P, std::void_t<decltype(std::declval<const P&>().score(
                              std::declval<const typename P::Model&>(), static_cast<std::uint8_t*>(nullptr),
                              static_cast<int*>(nullptr), 0.0))>> : std::true_type {};

template <class P>
double score_to_beat(const P& problem, const typename P::Model& model, std::uint8_t* mask, int* inliers, double beat) {
  if constexpr (HasBoundedScore<P>::value) {
    return problem.score(model, mask, inliers, beat);
  } else {
    return problem.score(model, mask, inliers);
  }
}
}  // namespace detail

// Scratch that a caller keeps to make repeated runs allocation-free.
struct RansacScratch {
  std::vector<int> pool;
  std::vector<std::uint8_t> mask;
};

// Runs RANSAC; on success *best holds the best model and best_mask its inliers (size()
// entries). kInvalidArgument when there are fewer correspondences than a minimal sample;
// kNotFound when no sample gave a model with at least `min_inliers` inliers.
template <class Problem>
Status ransac(const Problem& problem, const RansacParams& params, int min_inliers, typename Problem::Model* best,
              std::vector<std::uint8_t>& best_mask, RansacStats* stats, RansacScratch& scratch) {
  constexpr int k = Problem::kSampleSize;
  const int n = problem.size();
  RansacStats st;
  if (n < k) {
    if (stats) *stats = st;
    return invalid_argument("ransac: " + std::to_string(n) + " correspondences, a minimal sample needs " +
                            std::to_string(k));
  }
  // The pool's order is part of the random stream: start it fresh so that a run depends only
  // on the seed, not on earlier runs with the same scratch.
  scratch.pool.resize(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) scratch.pool[static_cast<std::size_t>(i)] = i;
  scratch.mask.resize(static_cast<std::size_t>(n));
  best_mask.assign(static_cast<std::size_t>(n), 0);

  SplitMix64 rng(params.seed);
  int sample[k];
  typename Problem::Model models[Problem::kMaxModels];
  double best_score = -1.0;
  int best_inliers = -1;
  const int cap = std::max(params.max_iterations, 1);
  int needed = cap;  // until a model says how good the data are
  int it = 0;
  while (it < cap && (it < needed || it < params.min_iterations)) {
    ++it;
    ransac_draw(rng, n, k, scratch.pool, sample);
    const int m = problem.fit(sample, models);
    for (int j = 0; j < m; ++j) {
      int inl = 0;
      const double s = detail::score_to_beat(problem, models[j], scratch.mask.data(), &inl, best_score);
      if (s > best_score) {
        best_score = s;
        best_inliers = inl;
        *best = models[j];
        best_mask.swap(scratch.mask);
        scratch.mask.resize(static_cast<std::size_t>(n));
        needed = ransac_iterations_needed(static_cast<double>(inl) / n, k, params.confidence, cap);
      }
    }
  }
  st.iterations = it;
  st.inliers = std::max(best_inliers, 0);
  st.score = std::max(best_score, 0.0);
  if (stats) *stats = st;
  if (best_inliers < std::max(min_inliers, 0) || best_inliers < 0) {
    std::fill(best_mask.begin(), best_mask.end(), std::uint8_t{0});
    return not_found("ransac: best model has " + std::to_string(std::max(best_inliers, 0)) + " inliers, " +
                     std::to_string(min_inliers) + " needed");
  }
  return Status::ok_status();
}

}  // namespace ale::geometry
