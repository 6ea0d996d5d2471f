// Chi-square gates of the SLAM core's residuals, in one place. A keypoint's position error has
// variance sigma^2 = scale(level)^2 px^2 per axis; a squared error over sigma^2 beyond the gate
// of its degrees of freedom is an outlier at the 95 % level:
//   1 dof: a distance to a line (epipolar searches, the fundamental matrix's score);
//   2 dof: a distance to a point (reprojection in BA, PnP, triangulation, fusion).
// The Huber kernels of the reprojection terms take the 2-dof gate's square root as their
// threshold (ORB-SLAM's monocular kernel).
#pragma once

namespace ale::geometry {

constexpr double kChi2OneDof95 = 3.841;  // 95 % gate of a chi-square with 1 degree of freedom
constexpr double kChi2TwoDof95 = 5.991;  // ... with 2
constexpr double kChi2ThreeDof95 = 7.815;  // ... with 3
// The 1-dof gate to two decimals, as ORB-SLAM's search for triangulation writes it; that search
// (core/slam/match/triangulation.cpp) keeps it so that its matches stay byte for byte the same.
constexpr double kChi2OneDof95TwoDigits = 3.84;
// sqrt(kChi2TwoDof95) to ten digits: the motion-only optimisation's Huber threshold. The bundle
// adjustments take std::sqrt(kChi2TwoDof95), which differs from it in the last bits; each keeps
// its own so that trajectories stay byte for byte what they are.
constexpr double kHuberDeltaTwoDof95 = 2.447648871;

}  // namespace ale::geometry
