// Synthetic pose graphs for the pose-graph tests and benchmark: a trajectory over several laps
// of a wavy circle, odometry edges between consecutive poses with seeded noise, loop edges
// between the same places on different laps, and the odometry chain as the initial estimate.
#pragma once

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/base/rng.h"
#include "core/geometry/lie.h"
#include "core/optim/pose_graph.h"

namespace ale::optim::test {

// Tolerances tight enough that our solver and Ceres (same values) both stop at the minimum.
inline LmOptions tight_lm_options() {
  LmOptions o;
  o.max_iterations = 200;
  o.function_tolerance = 1e-12;
  o.parameter_tolerance = 1e-12;
  o.gradient_tolerance = 1e-14;
  return o;
}

template <class Group>
struct PoseGraphScene {
  std::vector<Group> truth;    // T_iw
  std::vector<Group> initial;  // the odometry chain from truth[0]
  std::vector<PoseGraphEdge<Group>> edges;
};

struct CircleSceneSpec {
  int poses = 100;
  int laps = 2;
  int loop_every = 5;              // a loop edge from every loop_every-th pose of lap >= 1
  double radius_m = 5.0;
  double rotation_sigma_rad = 0.01;
  double translation_sigma_m = 0.02;
  double loop_sigma_factor = 1.0;  // loop edges' noise relative to the odometry's
  double scale_drift_per_step = 0.0;  // Sim3: local scale c_k = (1 + drift)^k (see make_drift_scene)
  std::uint64_t seed = 1;
};

inline CircleSceneSpec circle_spec(int poses, int laps, int loop_every, std::uint64_t seed) {
  CircleSceneSpec spec;
  spec.poses = poses;
  spec.laps = laps;
  spec.loop_every = loop_every;
  spec.seed = seed;
  return spec;
}

inline geometry::SE3 circle_pose(const CircleSceneSpec& spec, int k) {
  const int per_lap = spec.poses / spec.laps;
  const double angle = 2.0 * M_PI * static_cast<double>(k) / static_cast<double>(per_lap);
  const geometry::Vec3 centre_w(spec.radius_m * std::cos(angle), spec.radius_m * std::sin(angle),
                                0.3 * std::sin(3.0 * angle));
  // Looking along the tangent, pitched a little with the height's slope.
  const geometry::SO3 R_wc = geometry::SO3::exp(geometry::Vec3(0.0, 0.0, angle + M_PI_2)) *
                             geometry::SO3::exp(geometry::Vec3(0.0, 0.1 * std::cos(3.0 * angle), 0.0));
  return geometry::SE3(R_wc, centre_w).inverse();
}

template <int kDim>
Eigen::Matrix<double, kDim, 1> gaussian_tangent(SplitMix64& rng, double translation_sigma, double rotation_sigma,
                                                double scale_sigma) {
  Eigen::Matrix<double, kDim, 1> x;
  for (int r = 0; r < 3; ++r) x[r] = translation_sigma * static_cast<double>(rng.gaussian());
  for (int r = 3; r < 6; ++r) x[r] = rotation_sigma * static_cast<double>(rng.gaussian());
  for (int r = 6; r < kDim; ++r) x[r] = scale_sigma * static_cast<double>(rng.gaussian());
  return x;
}

template <int kDim>
Eigen::Matrix<double, kDim, kDim> diagonal_information(double translation_sigma, double rotation_sigma,
                                                       double scale_sigma) {
  Eigen::Matrix<double, kDim, 1> d;
  for (int r = 0; r < 3; ++r) d[r] = 1.0 / (translation_sigma * translation_sigma);
  for (int r = 3; r < 6; ++r) d[r] = 1.0 / (rotation_sigma * rotation_sigma);
  for (int r = 6; r < kDim; ++r) d[r] = 1.0 / (scale_sigma * scale_sigma);
  return d.asDiagonal();
}

// Circle scene as SE3 or as Sim3 with scale 1 everywhere (the same problem for the Sim3 code;
// the scale's measurement sigma is the translation's).
template <class Group>
PoseGraphScene<Group> make_circle_scene(const CircleSceneSpec& spec) {
  constexpr int kDim = PoseGraphGroup<Group>::kDim;
  SplitMix64 rng(spec.seed);
  PoseGraphScene<Group> scene;
  for (int k = 0; k < spec.poses; ++k) scene.truth.push_back(Group(circle_pose(spec, k)));
  const double ts = spec.translation_sigma_m;
  const double rs = spec.rotation_sigma_rad;
  auto add_edge = [&](int i, int j, double sigma_factor) {
    PoseGraphEdge<Group> edge;
    edge.i = i;
    edge.j = j;
    const Group T_ij = scene.truth[i] * scene.truth[j].inverse();
    edge.T_ij = Group::exp(gaussian_tangent<kDim>(rng, ts * sigma_factor, rs * sigma_factor, ts * sigma_factor)) * T_ij;
    edge.information = diagonal_information<kDim>(ts * sigma_factor, rs * sigma_factor, ts * sigma_factor);
    scene.edges.push_back(edge);
  };
  for (int k = 0; k + 1 < spec.poses; ++k) add_edge(k, k + 1, 1.0);
  const int per_lap = spec.poses / spec.laps;
  for (int k = per_lap; k < spec.poses; k += spec.loop_every) add_edge(k, k - per_lap, spec.loop_sigma_factor);
  // Odometry chain: T_jw = T_ij^-1 T_iw along j = i + 1.
  scene.initial.push_back(scene.truth[0]);
  for (int k = 0; k + 1 < spec.poses; ++k) scene.initial.push_back(scene.edges[k].T_ij.inverse() * scene.initial[k]);
  return scene;
}

// Monocular scale drift in Sim3 (ORB-SLAM's loop-closing situation). Frame k's coordinates are
// in a local scale c_k = (1 + drift)^k; odometry edges carry the true relative rotation and
// translation in frame i's local scale (c_i t_ij) with scale 1, as an essential graph built
// from the drifting keyframe poses does; one loop edge from the last pose to pose 0, measured
// by a 3-D to 3-D alignment of the two local maps, carries the relative scale c_last / c_0.
// The SE3 pose of a refined vertex S_iw = (R, t, s) is (R, t / s).
inline PoseGraphScene<geometry::Sim3> make_drift_scene(const CircleSceneSpec& spec) {
  using geometry::Sim3;
  SplitMix64 rng(spec.seed);
  PoseGraphScene<Sim3> scene;
  const int n = spec.poses;
  std::vector<double> local_scale(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k) {
    scene.truth.push_back(Sim3(circle_pose(spec, k)));
    local_scale[k] = std::pow(1.0 + spec.scale_drift_per_step, k);
  }
  const double ts = spec.translation_sigma_m;
  const double rs = spec.rotation_sigma_rad;
  auto add_edge = [&](int i, int j, double scale) {
    const Sim3 T_ij = scene.truth[i] * scene.truth[j].inverse();
    PoseGraphEdge<Sim3> edge;
    edge.i = i;
    edge.j = j;
    edge.T_ij = Sim3::exp(gaussian_tangent<7>(rng, ts, rs, ts)) *
                Sim3(T_ij.so3(), local_scale[i] * T_ij.translation(), scale);
    edge.information = diagonal_information<7>(ts, rs, ts);
    scene.edges.push_back(edge);
  };
  for (int k = 0; k + 1 < n; ++k) add_edge(k, k + 1, 1.0);
  add_edge(n - 1, 0, local_scale[n - 1] / local_scale[0]);
  scene.initial.push_back(scene.truth[0]);
  for (int k = 0; k + 1 < n; ++k) scene.initial.push_back(scene.edges[k].T_ij.inverse() * scene.initial[k]);
  return scene;
}

// Camera centre of a vertex in the world, metric: for S_iw = (R, t, s), -R^T t / s.
inline geometry::Vec3 centre_w(const geometry::SE3& T_iw) { return -(T_iw.rotation().transpose() * T_iw.translation()); }
inline geometry::Vec3 centre_w(const geometry::Sim3& S_iw) {
  return -(S_iw.rotation().transpose() * S_iw.translation()) / S_iw.scale();
}

// RMS distance between the estimated and true camera centres (no alignment: vertex 0 is fixed
// at the truth, which fixes the gauge).
template <class Group>
double position_rms_m(const std::vector<Group>& estimate, const std::vector<Group>& truth) {
  double sum = 0.0;
  for (std::size_t k = 0; k < truth.size(); ++k) sum += (centre_w(estimate[k]) - centre_w(truth[k])).squaredNorm();
  return std::sqrt(sum / static_cast<double>(truth.size()));
}

}  // namespace ale::optim::test
