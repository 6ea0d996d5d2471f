#include "core/slam/matcher.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace ale::slam {
namespace {

constexpr int kNoMatch = -1;

int hamming(const features::Descriptor& a, const features::Descriptor& b) { return features::hamming_distance(a, b); }

// Rotation-consistency check: bins orientation differences of the kept matches and returns, in
// `keep`, which of them lie in the three strongest bins (a bin counts when it holds at least a
// tenth of the strongest; ORB-SLAM's ComputeThreeMaxima).
class RotationHistogram {
 public:
  RotationHistogram(int bins, std::vector<std::vector<int>>& storage) : storage_(storage), bins_(std::max(bins, 1)) {
    storage_.resize(static_cast<std::size_t>(bins_));
    for (auto& b : storage_) b.clear();
  }
  void add(float angle1_deg, float angle2_deg, int item) {
    float rot = angle1_deg - angle2_deg;
    if (rot < 0.0f) rot += 360.0f;
    int bin = static_cast<int>(std::lround(rot * static_cast<float>(bins_) / 360.0f));
    if (bin >= bins_) bin = 0;
    if (bin < 0) bin = 0;
    storage_[static_cast<std::size_t>(bin)].push_back(item);
  }
  // Calls drop(item) for every item outside the three strongest bins.
  template <class F>
  void filter(F&& drop) const {
    int m[3] = {-1, -1, -1};
    std::size_t c[3] = {0, 0, 0};
    for (int i = 0; i < bins_; ++i) {
      const std::size_t s = storage_[static_cast<std::size_t>(i)].size();
      if (s > c[0]) {
        c[2] = c[1]; m[2] = m[1];
        c[1] = c[0]; m[1] = m[0];
        c[0] = s; m[0] = i;
      } else if (s > c[1]) {
        c[2] = c[1]; m[2] = m[1];
        c[1] = s; m[1] = i;
      } else if (s > c[2]) {
        c[2] = s; m[2] = i;
      }
    }
    if (c[1] * 10 < c[0]) m[1] = m[2] = -1;
    else if (c[2] * 10 < c[0]) m[2] = -1;
    for (int i = 0; i < bins_; ++i) {
      if (i == m[0] || i == m[1] || i == m[2]) continue;
      for (int item : storage_[static_cast<std::size_t>(i)]) drop(item);
    }
  }

 private:
  std::vector<std::vector<int>>& storage_;
  int bins_;
};

// The two best Hamming distances among candidates and the index of the best.
struct Best2 {
  int dist = std::numeric_limits<int>::max();
  int dist2 = std::numeric_limits<int>::max();
  int index = kNoMatch;
  int level = -1;
  int level2 = -1;
  void offer(int d, int idx, int lvl) {
    if (d < dist) {
      dist2 = dist;
      level2 = level;
      dist = d;
      index = idx;
      level = lvl;
    } else if (d < dist2) {
      dist2 = d;
      level2 = lvl;
    }
  }
};

bool project_pinhole(const geometry::Camera& pinhole, const geometry::Vec3& p_c, float* u, float* v) {
  geometry::Vec2 uv;
  if (!pinhole.project(p_c, &uv)) return false;
  *u = static_cast<float>(uv.x());
  *v = static_cast<float>(uv.y());
  return true;
}

// The part of kf1's ray (kf2's frame: d * ray + t21 at depth d in kf1) a point in front of kf2,
// at most max_depth deep (0 or less: unbounded), projects to, as an interval of the walked
// coordinate (u when along_u, else v). An end where the point reaches kf2's image plane projects
// to infinity and leaves that side open. False when no depth puts the point in front of both.
bool searched_part(const geometry::CameraIntrinsics& k, const geometry::Vec3& ray, const geometry::Vec3& t21,
                   double max_depth, bool along_u, double* w_lo, double* w_hi) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double d_lo = 0.0, d_hi = max_depth > 0.0 ? max_depth : kInf;
  bool open_lo = !(t21.z() > 0.0), open_hi = !(max_depth > 0.0);
  if (ray.z() > 0.0) {
    const double dz = -t21.z() / ray.z();
    if (dz > d_lo) d_lo = dz, open_lo = true;
  } else {
    const double dz = ray.z() < 0.0 ? -t21.z() / ray.z() : (t21.z() > 0.0 ? kInf : 0.0);
    if (dz < d_hi) d_hi = dz, open_hi = true;
  }
  if (!(d_lo < d_hi)) return false;
  auto walk_coord = [&](double d) {
    const geometry::Vec3 p = d * ray + t21;
    return along_u ? k.fx * p.x() / p.z() + k.cx : k.fy * p.y() / p.z() + k.cy;
  };
  *w_lo = -kInf;
  *w_hi = kInf;
  if (!open_lo && !open_hi) {
    const double w0 = walk_coord(d_lo), w1 = walk_coord(d_hi);
    *w_lo = std::min(w0, w1);
    *w_hi = std::max(w0, w1);
  } else if (!open_lo || !open_hi) {
    // one end finite: the open one lies beyond it in the direction the line moves with depth
    // (the projection is monotonic in d on the interval, so any depth between shows it)
    const double w_end = walk_coord(open_lo ? d_hi : d_lo);
    const double w_in = walk_coord(std::isinf(d_hi) ? d_lo + 1.0 : 0.5 * (d_lo + d_hi));
    if (w_in >= w_end) *w_lo = w_end; else *w_hi = w_end;
  }
  return true;
}

// The last step of the pair searches: the matches in scratch.matched (f1 index -> f2 index, or
// kNoMatch) outside the rotation histogram's strongest bins are dropped when check_orientation,
// and the rest are appended to pairs in f1 order. Returns pairs.size().
int list_pairs(const FrameFeatures& f1, const FrameFeatures& f2, bool check_orientation, int orientation_bins,
               MatcherScratch& scratch, std::vector<std::pair<int, int>>& pairs) {
  if (check_orientation) {
    RotationHistogram h(orientation_bins, scratch.bins);
    for (int i = 0; i < f1.count; ++i) {
      const int j = scratch.matched[static_cast<std::size_t>(i)];
      if (j != kNoMatch) h.add(f1.features[i].angle_deg, f2.features[j].angle_deg, i);
    }
    h.filter([&](int i) { scratch.matched[static_cast<std::size_t>(i)] = kNoMatch; });
  }
  for (int i = 0; i < f1.count; ++i) {
    const int j = scratch.matched[static_cast<std::size_t>(i)];
    if (j != kNoMatch) pairs.emplace_back(i, j);
  }
  return static_cast<int>(pairs.size());
}

// The triangulation search's ratio test: b (the best candidate on an epipolar line) beats by
// ratio_triangulation every scored candidate farther than ratio_separation x its level's scale
// from it.
bool clearly_best(const FrameFeatures& kf2, const Best2& b, const ScalePyramid& pyramid, const MatcherParams& params,
                  const std::vector<std::pair<int, int>>& scored) {
  const map::KeyframeFeature& best = kf2.features[b.index];
  const float r = params.ratio_separation * pyramid.scale[std::clamp<int>(best.level, 0, pyramid.levels - 1)];
  int other = std::numeric_limits<int>::max();
  for (const auto& [i2, d] : scored) {
    const float du = kf2.features[i2].u - best.u, dv = kf2.features[i2].v - best.v;
    if (du * du + dv * dv > r * r) other = std::min(other, d);
  }
  return static_cast<float>(b.dist) < params.ratio_triangulation * static_cast<float>(other);
}

}  // namespace

int search_for_initialization(const FrameFeatures& f1, const FrameFeatures& f2,
                              const std::vector<std::pair<float, float>>& predicted, float window_px,
                              const MatcherParams& params, std::vector<int>& matches12, MatcherScratch& scratch) {
  matches12.assign(static_cast<std::size_t>(std::max(f1.count, 0)), kNoMatch);
  if (!f2.grid || f1.count <= 0 || f2.count <= 0 || static_cast<int>(predicted.size()) != f1.count) return 0;
  scratch.best_dist.assign(static_cast<std::size_t>(f2.count), std::numeric_limits<int>::max());
  scratch.owner.assign(static_cast<std::size_t>(f2.count), kNoMatch);
  int n = 0;
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
  if (params.check_orientation) {
    RotationHistogram h(params.orientation_bins, scratch.bins);
    for (int i1 = 0; i1 < f1.count; ++i1) {
      const int i2 = matches12[static_cast<std::size_t>(i1)];
      if (i2 != kNoMatch) h.add(f1.features[i1].angle_deg, f2.features[i2].angle_deg, i1);
    }
    h.filter([&](int i1) {
      matches12[static_cast<std::size_t>(i1)] = kNoMatch;
      --n;
    });
  }
  return n;
}

int search_by_projection(const FrameFeatures& frame, const geometry::SE3& T_cw, const geometry::Camera& pinhole,
                         const map::MapStore& map, const std::vector<map::LandmarkId>& candidates,
                         const ScalePyramid& pyramid, float radius_factor, const MatcherParams& params,
                         std::vector<map::LandmarkId>& frame_landmarks, MatcherScratch& scratch,
                         std::vector<map::LandmarkId>* in_view) {
  if (in_view) in_view->clear();
  if (!frame.grid || static_cast<int>(frame_landmarks.size()) != frame.count) return 0;
  const geometry::Vec3 centre = T_cw.inverse().translation();
  // landmarks the frame has already, sorted for lookup
  scratch.seen.clear();
  for (map::LandmarkId id : frame_landmarks) {
    if (id.valid()) scratch.seen.push_back(id.value);
  }
  std::sort(scratch.seen.begin(), scratch.seen.end());
  int n = 0;
  for (map::LandmarkId id : candidates) {
    const map::Landmark* lm = map.landmark(id);
    if (!lm) continue;
    if (std::binary_search(scratch.seen.begin(), scratch.seen.end(), id.value)) continue;
    const geometry::Vec3 p_c = T_cw * lm->p_w;
    float u = 0.0f, v = 0.0f;
    if (!project_pinhole(pinhole, p_c, &u, &v) || !frame.grid->bounds().contains(u, v)) continue;
    const geometry::Vec3 ray = lm->p_w - centre;
    const float dist = static_cast<float>(ray.norm());
    if (dist < 0.8f * lm->min_distance || dist > 1.2f * lm->max_distance) continue;
    const double view_cos = ray.dot(lm->normal) / std::max(static_cast<double>(dist), 1e-12);
    if (view_cos < 0.5) continue;
    if (in_view) in_view->push_back(id);
    const int level = pyramid.predict_level(dist, lm->max_distance);
    const float r = radius_factor * (view_cos > 0.998 ? 2.5f : 4.0f) * pyramid.scale[level];
    scratch.candidates.clear();
    frame.grid->query(u, v, r, level - 1, level, scratch.candidates);
    Best2 b;
    for (int i : scratch.candidates) {
      if (frame_landmarks[static_cast<std::size_t>(i)].valid()) continue;
      b.offer(hamming(lm->descriptor, frame.features[i].descriptor), i, frame.features[i].level);
    }
    if (b.index == kNoMatch || b.dist > params.th_high) continue;
    if (b.level == b.level2 && static_cast<float>(b.dist) > params.ratio_projection * static_cast<float>(b.dist2)) {
      continue;
    }
    frame_landmarks[static_cast<std::size_t>(b.index)] = id;
    ++n;
  }
  return n;
}

int search_by_projection(const FrameFeatures& current, const geometry::SE3& T_cw, const FrameFeatures& last,
                         const std::vector<map::LandmarkId>& last_landmarks, const map::MapStore& map,
                         const geometry::Camera& pinhole, const ScalePyramid& pyramid, float radius_px,
                         const MatcherParams& params, std::vector<map::LandmarkId>& current_landmarks,
                         MatcherScratch& scratch) {
  if (!current.grid || static_cast<int>(current_landmarks.size()) != current.count ||
      static_cast<int>(last_landmarks.size()) != last.count) {
    return 0;
  }
  scratch.matched.assign(static_cast<std::size_t>(current.count), kNoMatch);  // last index per current keypoint
  int n = 0;
  for (int il = 0; il < last.count; ++il) {
    const map::LandmarkId id = last_landmarks[static_cast<std::size_t>(il)];
    const map::Landmark* lm = map.landmark(id);
    if (!lm) continue;
    float u = 0.0f, v = 0.0f;
    if (!project_pinhole(pinhole, T_cw * lm->p_w, &u, &v) || !current.grid->bounds().contains(u, v)) continue;
    const int level = last.features[il].level;
    const float r = radius_px * pyramid.scale[std::clamp(level, 0, pyramid.levels - 1)];
    scratch.candidates.clear();
    current.grid->query(u, v, r, level - 1, level + 1, scratch.candidates);
    Best2 b;
    for (int i : scratch.candidates) {
      if (current_landmarks[static_cast<std::size_t>(i)].valid()) continue;
      b.offer(hamming(lm->descriptor, current.features[i].descriptor), i, current.features[i].level);
    }
    if (b.index == kNoMatch || b.dist > params.th_high) continue;
    current_landmarks[static_cast<std::size_t>(b.index)] = id;
    scratch.matched[static_cast<std::size_t>(b.index)] = il;
    ++n;
  }
  if (params.check_orientation) {
    RotationHistogram h(params.orientation_bins, scratch.bins);
    for (int i = 0; i < current.count; ++i) {
      const int il = scratch.matched[static_cast<std::size_t>(i)];
      if (il != kNoMatch) h.add(last.features[il].angle_deg, current.features[i].angle_deg, i);
    }
    h.filter([&](int i) {
      current_landmarks[static_cast<std::size_t>(i)] = map::LandmarkId{};
      --n;
    });
  }
  return n;
}

int search_for_triangulation(const FrameFeatures& kf1, const geometry::SE3& T1w, const map::LandmarkId* kf1_landmarks,
                             const FrameFeatures& kf2, const geometry::SE3& T2w, const map::LandmarkId* kf2_landmarks,
                             const geometry::Camera& pinhole, const ScalePyramid& pyramid, const MatcherParams& params,
                             std::vector<std::pair<int, int>>& pairs, MatcherScratch& scratch, double max_depth) {
  pairs.clear();
  if (!kf2.grid || kf1.count <= 0 || kf2.count <= 0) return 0;
  const geometry::CameraIntrinsics& k = pinhole.intrinsics();
  geometry::Mat3 K;
  K << k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0;
  const geometry::Mat3 K_inv = K.inverse();
  const geometry::SE3 T21 = T2w * T1w.inverse();
  const geometry::Mat3 F21 = K_inv.transpose() * geometry::hat(T21.translation()) * T21.rotation() * K_inv;
  // the epipole: camera 1's centre seen from camera 2
  float eu = 0.0f, ev = 0.0f;
  const bool has_epipole = project_pinhole(pinhole, T21.translation(), &eu, &ev);

  const FeatureGrid& grid = *kf2.grid;
  const ImageBounds& bb = grid.bounds();
  const float cw = grid.cell_width(), ch = grid.cell_height();
  const float band = std::sqrt(3.84f * pyramid.sigma2[pyramid.levels - 1]);
  scratch.best_dist.assign(static_cast<std::size_t>(kf2.count), std::numeric_limits<int>::max());
  scratch.owner.assign(static_cast<std::size_t>(kf2.count), kNoMatch);
  scratch.matched.assign(static_cast<std::size_t>(kf1.count), kNoMatch);

  const bool use_ratio = params.ratio_triangulation < 1.0f;
  const geometry::Mat3 R21 = T21.rotation();
  const geometry::Vec3 t21 = T21.translation();
  for (int i1 = 0; i1 < kf1.count; ++i1) {
    if (kf1_landmarks && kf1_landmarks[i1].valid()) continue;
    const map::KeyframeFeature& a = kf1.features[i1];
    const geometry::Vec3 line = F21 * geometry::Vec3(a.u, a.v, 1.0);
    const double la = line.x(), lb = line.y(), lc = line.z();
    const double den = la * la + lb * lb;
    if (!(den > 0.0)) continue;
    const bool along_u = std::fabs(lb) >= std::fabs(la);
    const geometry::Vec3 ray = R21 * (K_inv * geometry::Vec3(a.u, a.v, 1.0));
    double w_lo = 0.0, w_hi = 0.0;
    if (!searched_part(k, ray, t21, max_depth, along_u, &w_lo, &w_hi)) continue;  // never in front of both
    // the cells walked below cover the part with the widest level's band; each candidate is
    // then held to its own level's
    const double w_lo_cells = w_lo - band, w_hi_cells = w_hi + band;
    Best2 b;
    scratch.scored.clear();
    auto consider = [&](int i2) {
      const bool mapped = kf2_landmarks && kf2_landmarks[i2].valid();
      if (mapped && !use_ratio) return;
      const map::KeyframeFeature& c = kf2.features[i2];
      const int lvl = std::clamp<int>(c.level, 0, pyramid.levels - 1);
      if (has_epipole) {
        const float du = eu - c.u, dv = ev - c.v;
        if (du * du + dv * dv < 100.0f * pyramid.scale[lvl]) return;
      }
      const double num = la * c.u + lb * c.v + lc;
      if (num * num / den >= 3.84 * pyramid.sigma2[lvl]) return;
      // on the searched part of the line, within the keypoint's own uncertainty
      const double w = along_u ? c.u : c.v, tol = std::sqrt(3.84 * pyramid.sigma2[lvl]);
      if (w < w_lo - tol || w > w_hi + tol) return;
      const int d = hamming(a.descriptor, c.descriptor);
      if (use_ratio) scratch.scored.emplace_back(i2, d);
      if (mapped || d > params.th_low || d >= scratch.best_dist[static_cast<std::size_t>(i2)]) return;
      b.offer(d, i2, lvl);
    };
    // walk the grid cells along the line, +-band around it
    if (along_u) {
      for (int col = 0; col < FeatureGrid::kCols; ++col) {
        const double u0 = bb.min_u + static_cast<float>(col) * cw, u1 = u0 + cw;
        if (u1 < w_lo_cells || u0 > w_hi_cells) continue;
        const double v0 = -(la * u0 + lc) / lb, v1 = -(la * u1 + lc) / lb;
        const int r0 = floor_clamped((std::min(v0, v1) - band - bb.min_v) / ch, 0, FeatureGrid::kRows);
        const int r1 = floor_clamped((std::max(v0, v1) + band - bb.min_v) / ch, -1, FeatureGrid::kRows - 1);
        for (int row = r0; row <= r1; ++row) {
          for (const int* p = grid.cell_begin(col, row); p != grid.cell_end(col, row); ++p) consider(*p);
        }
      }
    } else {
      for (int row = 0; row < FeatureGrid::kRows; ++row) {
        const double v0 = bb.min_v + static_cast<float>(row) * ch, v1 = v0 + ch;
        if (v1 < w_lo_cells || v0 > w_hi_cells) continue;
        const double u0 = -(lb * v0 + lc) / la, u1 = -(lb * v1 + lc) / la;
        const int c0 = floor_clamped((std::min(u0, u1) - band - bb.min_u) / cw, 0, FeatureGrid::kCols);
        const int c1 = floor_clamped((std::max(u0, u1) + band - bb.min_u) / cw, -1, FeatureGrid::kCols - 1);
        for (int col = c0; col <= c1; ++col) {
          for (const int* p = grid.cell_begin(col, row); p != grid.cell_end(col, row); ++p) consider(*p);
        }
      }
    }
    if (b.index == kNoMatch) continue;
    if (use_ratio && !clearly_best(kf2, b, pyramid, params, scratch.scored)) continue;
    const int prev = scratch.owner[static_cast<std::size_t>(b.index)];
    if (prev != kNoMatch) scratch.matched[static_cast<std::size_t>(prev)] = kNoMatch;
    scratch.owner[static_cast<std::size_t>(b.index)] = i1;
    scratch.best_dist[static_cast<std::size_t>(b.index)] = b.dist;
    scratch.matched[static_cast<std::size_t>(i1)] = b.index;
  }
  return list_pairs(kf1, kf2, params.check_orientation, params.orientation_bins, scratch, pairs);
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

// The common part of match_all_pairs and match_along_epipolar_lines (matcher.h) over the listed
// pairs; candidate(i1, i2) is the search's rule.
template <class Candidate>
int match_pairs(const FrameFeatures& f1, const FrameFeatures& f2, const std::vector<DescriptorPair>& near_pairs,
                const PairMatchParams& params, Candidate candidate, std::vector<std::pair<int, int>>& pairs,
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
  return list_pairs(f1, f2, params.check_orientation, params.orientation_bins, scratch, pairs);
}

}  // namespace

void near_descriptor_pairs(const FrameFeatures& f1, const FrameFeatures& f2, const PairMatchParams& params,
                           std::vector<DescriptorPair>& near_pairs) {
  near_pairs.clear();
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
                    const PairMatchParams& params, std::vector<std::pair<int, int>>& pairs, MatcherScratch& scratch) {
  return match_pairs(f1, f2, near_pairs, params, [](int, int) { return true; }, pairs, scratch);
}

int match_all_pairs(const FrameFeatures& f1, const FrameFeatures& f2, const PairMatchParams& params,
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
