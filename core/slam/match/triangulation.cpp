#include "core/slam/match/triangulation.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/geometry/chi_square.h"

namespace ale::slam {
namespace {

// The epipolar gate (1 dof, 95 %, as ORB-SLAM writes it) in both precisions the search uses.
constexpr double kGate = geometry::kChi2OneDof95TwoDigits;
constexpr float kGateF = static_cast<float>(kGate);
static_assert(kGateF == 3.84f, "the float gate rounds to 3.84f");

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

// The first index in [0, n) where `past` holds (n when none), `past` being false and then true
// along the index: the cells a line's band touches, found in a few tests where checking each of
// the 64 columns (48 rows) cost about a million ARM instructions a frame in the dark.
template <class Past>
int first_where(int n, Past past) {
  int lo = 0, hi = n;
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if (past(mid)) hi = mid; else lo = mid + 1;
  }
  return lo;
}
}  // namespace

int search_for_triangulation(const MatchContext& ctx, const PosedKeyframe& keyframe1, const PosedKeyframe& keyframe2,
                             double max_depth, std::vector<std::pair<int, int>>& pairs) {
  const FrameFeatures& kf1 = keyframe1.frame;
  const FrameFeatures& kf2 = keyframe2.frame;
  const map::LandmarkId* kf1_landmarks = keyframe1.landmarks;
  const map::LandmarkId* kf2_landmarks = keyframe2.landmarks;
  const geometry::Camera& pinhole = ctx.pinhole;
  const ScalePyramid& pyramid = ctx.pyramid;
  const MatcherParams& params = ctx.params;
  MatcherScratch& scratch = ctx.scratch;
  pairs.clear();
  if (!kf2.grid || kf1.count <= 0 || kf2.count <= 0) return 0;
  const geometry::CameraIntrinsics& k = pinhole.intrinsics();
  geometry::Mat3 K;
  K << k.fx, 0.0, k.cx, 0.0, k.fy, k.cy, 0.0, 0.0, 1.0;
  const geometry::Mat3 K_inv = K.inverse();
  const geometry::SE3 T21 = keyframe2.T_cw * keyframe1.T_cw.inverse();
  const geometry::Mat3 F21 = K_inv.transpose() * geometry::hat(T21.translation()) * T21.rotation() * K_inv;
  // the epipole: camera 1's centre seen from camera 2
  float eu = 0.0f, ev = 0.0f;
  const bool has_epipole = project_pinhole(pinhole, T21.translation(), &eu, &ev);

  const FeatureGrid& grid = *kf2.grid;
  const ImageBounds& bb = grid.bounds();
  const float cw = grid.cell_width(), ch = grid.cell_height();
  const float band = std::sqrt(kGateF * pyramid.sigma2[pyramid.levels - 1]);
  scratch.best_dist.assign(static_cast<std::size_t>(kf2.count), std::numeric_limits<int>::max());
  scratch.owner.assign(static_cast<std::size_t>(kf2.count), kNoMatch);
  scratch.matched.assign(static_cast<std::size_t>(kf1.count), kNoMatch);

  const bool use_ratio = params.ratio_triangulation < 1.0f;
  const features::HammingKernel hamming = features::hamming_kernel();
  // per level: the epipolar gate (squared pixels), its square root (the tolerance along the
  // line) and the distance from the epipole below which a candidate is skipped (squared pixels)
  double gate[ScalePyramid::kMaxLevels], tol[ScalePyramid::kMaxLevels];
  float near_epipole[ScalePyramid::kMaxLevels];
  for (int l = 0; l < pyramid.levels; ++l) {
    gate[l] = kGate * pyramid.sigma2[l];
    tol[l] = std::sqrt(gate[l]);
    near_epipole[l] = 100.0f * pyramid.scale[l];
  }
  scratch.epipolar.resize(static_cast<std::size_t>(kf2.count));
  for (int i2 = 0; i2 < kf2.count; ++i2) {
    const map::KeyframeFeature& c = kf2.features[i2];
    EpipolarKeypoint& e = scratch.epipolar[static_cast<std::size_t>(i2)];
    e.level = std::clamp<int>(c.level, 0, pyramid.levels - 1);
    e.u = c.u;
    e.v = c.v;
    e.gate = gate[e.level];
    e.tol = tol[e.level];
    e.mapped = kf2_landmarks && kf2_landmarks[i2].valid();
  }
  const EpipolarKeypoint* keypoints2 = scratch.epipolar.data();
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
      const EpipolarKeypoint& e = keypoints2[i2];
      if (e.mapped && !use_ratio) return;
      // the tests in the order they reject most (the band's cells hold mostly keypoints off the
      // line): near the line, on its searched part within the keypoint's own uncertainty, away
      // from the epipole
      const double num = la * e.u + lb * e.v + lc;
      if (num * num / den >= e.gate) return;
      const double w = along_u ? e.u : e.v;
      if (w < w_lo - e.tol || w > w_hi + e.tol) return;
      const map::KeyframeFeature& c = kf2.features[i2];
      if (has_epipole) {
        const float du = eu - c.u, dv = ev - c.v;
        if (du * du + dv * dv < near_epipole[e.level]) return;
      }
      const int d = hamming(a.descriptor, c.descriptor);
      if (use_ratio) scratch.scored.emplace_back(i2, d);
      if (e.mapped || d > params.th_low || d >= scratch.best_dist[static_cast<std::size_t>(i2)]) return;
      b.offer(d, i2, e.level);
    };
    // walk the grid cells along the line, +-band around it: the columns (rows) whose span
    // [u0, u1] meets [w_lo_cells, w_hi_cells], u0 and u1 growing with the index
    if (along_u) {
      auto u0_of = [&](int col) -> double { return bb.min_u + static_cast<float>(col) * cw; };
      const int col_begin = first_where(FeatureGrid::kCols, [&](int col) { return !(u0_of(col) + cw < w_lo_cells); });
      const int col_end = first_where(FeatureGrid::kCols, [&](int col) { return u0_of(col) > w_hi_cells; });
      for (int col = col_begin; col < col_end; ++col) {
        const double u0 = u0_of(col), u1 = u0 + cw;
        const double v0 = -(la * u0 + lc) / lb, v1 = -(la * u1 + lc) / lb;
        const int r0 = floor_clamped((std::min(v0, v1) - band - bb.min_v) / ch, 0, FeatureGrid::kRows);
        const int r1 = floor_clamped((std::max(v0, v1) + band - bb.min_v) / ch, -1, FeatureGrid::kRows - 1);
        for (int row = r0; row <= r1; ++row) {
          for (const int* p = grid.cell_begin(col, row); p != grid.cell_end(col, row); ++p) consider(*p);
        }
      }
    } else {
      auto v0_of = [&](int row) -> double { return bb.min_v + static_cast<float>(row) * ch; };
      const int row_begin = first_where(FeatureGrid::kRows, [&](int row) { return !(v0_of(row) + ch < w_lo_cells); });
      const int row_end = first_where(FeatureGrid::kRows, [&](int row) { return v0_of(row) > w_hi_cells; });
      for (int row = row_begin; row < row_end; ++row) {
        const double v0 = v0_of(row), v1 = v0 + ch;
        const double u0 = -(lb * v0 + lc) / la, u1 = -(lb * v1 + lc) / la;
        const int c0 = floor_clamped((std::min(u0, u1) - band - bb.min_u) / cw, 0, FeatureGrid::kCols);
        const int c1 = floor_clamped((std::max(u0, u1) + band - bb.min_u) / cw, -1, FeatureGrid::kCols - 1);
        if (c0 > c1) continue;
        // cells c0..c1 of the row in one pass (FeatureGrid::cell_begin)
        for (const int* p = grid.cell_begin(c0, row), *end = grid.cell_end(c1, row); p != end; ++p) consider(*p);
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
  return list_matched_pairs(kf1, kf2, params.rotation, scratch, pairs);
}
}  // namespace ale::slam
