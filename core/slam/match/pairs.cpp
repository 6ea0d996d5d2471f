#include "core/slam/match/pairs.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ale::slam {

int search_for_initialization(const MatchContext& ctx, const FrameFeatures& f1, const FrameFeatures& f2,
                              const std::vector<std::pair<float, float>>& predicted, float window_px,
                              std::vector<int>& matches12) {
  const MatcherParams& params = ctx.params;
  MatcherScratch& scratch = ctx.scratch;
  matches12.assign(static_cast<std::size_t>(std::max(f1.count, 0)), kNoMatch);
  if (!f2.grid || f1.count <= 0 || f2.count <= 0 || static_cast<int>(predicted.size()) != f1.count) return 0;
  scratch.best_dist.assign(static_cast<std::size_t>(f2.count), std::numeric_limits<int>::max());
  scratch.owner.assign(static_cast<std::size_t>(f2.count), kNoMatch);
  int n = 0;
  const features::HammingKernel hamming = features::hamming_kernel();
  for (int i1 = 0; i1 < f1.count; ++i1) {
    const map::KeyframeFeature& a = f1.features[i1];
    if (a.level > params.initialization_max_level) continue;
    scratch.candidates.clear();
    const auto& p = predicted[static_cast<std::size_t>(i1)];
    // the same octave, or one either side when all levels take part
    const int lo = params.initialization_max_level > 0 ? a.level - 1 : 0;
    const int hi = params.initialization_max_level > 0 ? a.level + 1 : 0;
    f2.grid->query(p.first, p.second, window_px, lo, hi, scratch.candidates);
    Best2 b;
    for (int i2 : scratch.candidates) {
      const int d = hamming(a.descriptor, f2.features[i2].descriptor);
      // a keypoint of f2 already taken by an equal or better match is not offered
      if (scratch.best_dist[static_cast<std::size_t>(i2)] <= d) continue;
      b.offer(d, i2, f2.features[i2].level);
    }
    if (b.index == kNoMatch || b.dist > params.th_low) continue;
    if (static_cast<float>(b.dist) >= static_cast<float>(b.dist2) * params.ratio_initialization) continue;
    const int prev = scratch.owner[static_cast<std::size_t>(b.index)];
    if (prev != kNoMatch) {
      matches12[static_cast<std::size_t>(prev)] = kNoMatch;
      --n;
    }
    matches12[static_cast<std::size_t>(i1)] = b.index;
    scratch.owner[static_cast<std::size_t>(b.index)] = i1;
    scratch.best_dist[static_cast<std::size_t>(b.index)] = b.dist;
    ++n;
  }
  if (params.rotation.enabled) n -= drop_inconsistent_rotations(f1, f2, params.rotation.bins, matches12, scratch.bins);
  return n;
}

namespace {

bool finite_position(const map::KeyframeFeature& f) { return std::isfinite(f.u) && std::isfinite(f.v); }

void offer(Nearest2& n, int d, int index) {
  if (d < n.best) {
    n.second = n.best;
    n.best = d;
    n.index = index;
  } else if (d < n.second) {
    n.second = d;
  }
}

// The common part of match_all_pairs and match_along_epipolar_lines (pairs.h) over the listed
// pairs; candidate(i1, i2) is the search's rule.
template <class Candidate>
int match_pairs(const FrameFeatures& f1, const FrameFeatures& f2, const std::vector<DescriptorPair>& near_pairs,
                const PairSearchParams& params, Candidate candidate, std::vector<std::pair<int, int>>& pairs,
                MatcherScratch& scratch) {
  pairs.clear();
  if (f1.count <= 0 || f2.count <= 0) return 0;
  scratch.nearest12.assign(static_cast<std::size_t>(f1.count), Nearest2{});
  scratch.nearest21.assign(static_cast<std::size_t>(f2.count), Nearest2{});
  for (const DescriptorPair& p : near_pairs) {
    if (!candidate(p.i1, p.i2)) continue;
    offer(scratch.nearest12[static_cast<std::size_t>(p.i1)], p.distance, p.i2);
    offer(scratch.nearest21[static_cast<std::size_t>(p.i2)], p.distance, p.i1);
  }
  scratch.matched.assign(static_cast<std::size_t>(f1.count), kNoMatch);
  for (int i = 0; i < f1.count; ++i) {
    const Nearest2& n = scratch.nearest12[static_cast<std::size_t>(i)];
    if (n.index < 0 || n.best > params.max_distance) continue;
    if (!(static_cast<double>(n.best) < params.ratio * static_cast<double>(n.second))) continue;
    if (params.mutual && scratch.nearest21[static_cast<std::size_t>(n.index)].index != i) continue;
    scratch.matched[static_cast<std::size_t>(i)] = n.index;
  }
  return list_matched_pairs(f1, f2, params.rotation, scratch, pairs);
}

}  // namespace

void near_descriptor_pairs(const FrameFeatures& f1, const FrameFeatures& f2, const PairSearchParams& params,
                           std::vector<DescriptorPair>& near_pairs) {
  near_pairs.clear();
  const features::HammingKernel hamming = features::hamming_kernel();
  for (int i = 0; i < f1.count; ++i) {
    if (!finite_position(f1.features[i])) continue;
    for (int j = 0; j < f2.count; ++j) {
      if (!finite_position(f2.features[j])) continue;
      const int d = hamming(f1.features[i].descriptor, f2.features[j].descriptor);
      if (static_cast<double>(d) * params.ratio <= static_cast<double>(params.max_distance) || d <= params.max_distance)
        near_pairs.push_back({i, j, d});
    }
  }
}

int match_all_pairs(const FrameFeatures& f1, const FrameFeatures& f2, const std::vector<DescriptorPair>& near_pairs,
                    const PairSearchParams& params, std::vector<std::pair<int, int>>& pairs, MatcherScratch& scratch) {
  return match_pairs(f1, f2, near_pairs, params, [](int, int) { return true; }, pairs, scratch);
}

int match_all_pairs(const FrameFeatures& f1, const FrameFeatures& f2, const PairSearchParams& params,
                    std::vector<std::pair<int, int>>& pairs, MatcherScratch& scratch) {
  near_descriptor_pairs(f1, f2, params, scratch.near_pairs);
  return match_all_pairs(f1, f2, scratch.near_pairs, params, pairs, scratch);
}

int match_along_epipolar_lines(const FrameFeatures& f1, const FrameFeatures& f2, const geometry::Mat3& F_21,
                               const EpipolarBandParams& params, std::vector<std::pair<int, int>>& pairs,
                               MatcherScratch& scratch) {
  near_descriptor_pairs(f1, f2, params.match, scratch.near_pairs);
  return match_along_epipolar_lines(f1, f2, scratch.near_pairs, F_21, params, pairs, scratch);
}

int match_along_epipolar_lines(const FrameFeatures& f1, const FrameFeatures& f2,
                               const std::vector<DescriptorPair>& near_pairs, const geometry::Mat3& F_21,
                               const EpipolarBandParams& params, std::vector<std::pair<int, int>>& pairs,
                               MatcherScratch& scratch) {
  // f1's epipolar lines in f2, scaled to unit normal (distance = l . (u, v, 1)); a zero line
  // (the keypoint at the epipole of a degenerate F) has no band.
  scratch.line_sigma.resize(static_cast<std::size_t>(ScalePyramid::kMaxLevels));
  for (int l = 0; l < ScalePyramid::kMaxLevels; ++l)
    scratch.line_sigma[static_cast<std::size_t>(l)] =
        static_cast<float>(params.sigma_px * std::pow(static_cast<double>(params.scale_factor), l));
  std::vector<geometry::Vec3>& lines = scratch.lines;
  lines.assign(static_cast<std::size_t>(std::max(f1.count, 0)), geometry::Vec3::Zero());
  for (int i = 0; i < f1.count; ++i) {
    const map::KeyframeFeature& a = f1.features[i];
    if (!finite_position(a)) continue;
    const geometry::Vec3 l = F_21 * geometry::Vec3(a.u, a.v, 1.0);
    const double norm = l.head<2>().norm();
    if (norm > 0.0 && l.allFinite()) lines[static_cast<std::size_t>(i)] = l / norm;
  }
  const auto level_sigma = [&](int level) {
    return scratch.line_sigma[static_cast<std::size_t>(std::clamp(level, 0, ScalePyramid::kMaxLevels - 1))];
  };
  const auto candidate = [&](int i, int j) {
    const geometry::Vec3& l = lines[static_cast<std::size_t>(i)];
    if (l.isZero()) return false;
    const int la = f1.features[i].level;
    const int lb = f2.features[j].level;
    if (std::abs(la - lb) > params.max_level_diff) return false;
    const double sigma = level_sigma(std::max(la, lb));
    const double d = l.x() * f2.features[j].u + l.y() * f2.features[j].v + l.z();
    return d * d <= params.chi2 * sigma * sigma;
  };
  return match_pairs(f1, f2, near_pairs, params.match, candidate, pairs, scratch);
}

}  // namespace ale::slam
