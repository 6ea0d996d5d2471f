#include "app/tools/lib/render/trajectory.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "app/tools/lib/render/camera.h"

namespace ale::render {

namespace {
constexpr double kPi = 3.14159265358979323846;
constexpr double kSampleRate = 200.0;  // Hz, like EuRoC's ground truth

Pose planar_pose(double x, double y, double heading, const DriveOptions& d) {
  Pose p;
  p.q_wb = Eigen::Quaterniond(Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()));
  p.p_wb = Eigen::Vector3d(x + d.camera_ahead_m * std::cos(heading), y + d.camera_ahead_m * std::sin(heading),
                           d.camera_height_m);
  return p;
}

// One leg of a route of straight drives and turns in place: the turning axis goes from `from` to
// `to` while the heading goes from heading0 by turn (radians; 0 on a drive).
struct Leg {
  double duration_s;
  Eigen::Vector2d from, to;
  double heading0, turn;
};

// The legs driven one after the other, over and over, sampled at kSampleRate for duration_s.
Trajectory drive_legs(const std::vector<Leg>& legs, const DriveOptions& drive, double duration_s) {
  double cycle = 0.0;
  for (const Leg& l : legs) cycle += l.duration_s;
  std::vector<TimedPose> out;
  const int n = static_cast<int>(std::ceil(duration_s * kSampleRate)) + 1;
  for (int k = 0; k < n; ++k) {
    const double t = k / kSampleRate;
    double r = std::fmod(t, cycle);
    std::size_t li = 0;
    while (li + 1 < legs.size() && r >= legs[li].duration_s) r -= legs[li++].duration_s;
    const Leg& leg = legs[li];
    const double w = std::clamp(r / leg.duration_s, 0.0, 1.0);
    const Eigen::Vector2d pos = leg.from + w * (leg.to - leg.from);
    out.push_back({t, planar_pose(pos.x(), pos.y(), leg.heading0 + w * leg.turn, drive)});
  }
  return Trajectory(std::move(out), cycle);
}

// The legs of a closed route through `points` (the turning axis's waypoints): at each, a turn in
// place to face the next (the shorter way; a half turn goes left), then the drive to it.
std::vector<Leg> legs_through(const std::vector<Eigen::Vector2d>& points, const DriveOptions& drive) {
  std::vector<Leg> legs;
  auto heading_of = [&](std::size_t i) {
    const Eigen::Vector2d d = points[(i + 1) % points.size()] - points[i];
    return std::atan2(d.y(), d.x());
  };
  double heading = heading_of(0);
  auto turn_to = [&](const Eigen::Vector2d& at, double next) {
    double turn = std::remainder(next - heading, 2.0 * kPi);
    // A half turn goes left (anticlockwise), whichever way the remainder rounded.
    if (std::abs(std::abs(turn) - kPi) < 1e-9) turn = kPi;
    if (std::abs(turn) > 1e-9)
      legs.push_back({std::abs(turn) * 180.0 / kPi / drive.turn_rate_dps, at, at, heading, (heading + turn) - heading});
    heading += turn;
  };
  for (std::size_t i = 0; i < points.size(); ++i) {
    turn_to(points[i], heading_of(i));
    const Eigen::Vector2d& to = points[(i + 1) % points.size()];
    legs.push_back({(to - points[i]).norm() / drive.speed_mps, points[i], to, heading, 0.0});
  }
  turn_to(points[0], heading_of(0));  // the turn that closes the cycle
  return legs;
}
}  // namespace

Rig sweeper_rig(double tilt_up_deg) {
  Rig r;
  r.R_bc = sweeper_R_bc(tilt_up_deg);
  return r;
}

Rig euroc_cam0_rig() {
  Rig r;
  r.R_bc << 0.0148655429818, -0.999880929698, 0.00414029679422,  //
      0.999557249008, 0.0149672133247, 0.025715529948,           //
      -0.0257744366974, 0.00375618835797, 0.999660727178;
  r.t_bc = Eigen::Vector3d(-0.0216401454975, -0.064676986768, 0.00981073058949);
  return r;
}

Pose Trajectory::at(double t_s) const {
  if (samples_.empty()) return {};
  if (t_s <= samples_.front().t_s) return samples_.front().pose;
  if (t_s >= samples_.back().t_s) return samples_.back().pose;
  const auto it = std::upper_bound(samples_.begin(), samples_.end(), t_s,
                                   [](double t, const TimedPose& s) { return t < s.t_s; });
  const TimedPose& b = *it;
  const TimedPose& a = *(it - 1);
  const double w = (t_s - a.t_s) / (b.t_s - a.t_s);
  Pose p;
  p.p_wb = a.pose.p_wb + w * (b.pose.p_wb - a.pose.p_wb);
  p.q_wb = a.pose.q_wb.slerp(w, b.pose.q_wb);
  return p;
}

Trajectory make_loop(const Scene& scene, const DriveOptions& drive, double duration_s) {
  const double cx = 0.5 * scene.size.x();
  const double cy = 0.5 * scene.size.y();
  const double a = 1.5;
  const double b = 1.0;
  // Arc length as a function of the ellipse angle, tabulated, to drive at constant speed.
  constexpr int kSteps = 4096;
  std::vector<double> arc(kSteps + 1, 0.0);
  for (int i = 1; i <= kSteps; ++i) {
    const double th = 2.0 * kPi * (i - 0.5) / kSteps;
    arc[static_cast<std::size_t>(i)] =
        arc[static_cast<std::size_t>(i - 1)] + std::hypot(a * std::sin(th), b * std::cos(th)) * 2.0 * kPi / kSteps;
  }
  const double lap = arc.back();
  std::vector<TimedPose> out;
  const int n = static_cast<int>(std::ceil(duration_s * kSampleRate)) + 1;
  for (int k = 0; k < n; ++k) {
    const double t = k / kSampleRate;
    const double s = std::fmod(drive.speed_mps * t, lap);
    const auto i = static_cast<std::size_t>(std::upper_bound(arc.begin(), arc.end(), s) - arc.begin());
    const std::size_t j = std::clamp<std::size_t>(i, 1, kSteps);
    const double frac = (s - arc[j - 1]) / std::max(1e-12, arc[j] - arc[j - 1]);
    const double th = 2.0 * kPi * (static_cast<double>(j - 1) + frac) / kSteps;
    // The heading is the ellipse's tangent; the camera (not the turning axis) is on the ellipse.
    const double heading = std::atan2(b * std::cos(th), -a * std::sin(th));
    Pose p = planar_pose(cx + a * std::cos(th) - drive.camera_ahead_m * std::cos(heading),
                         cy + b * std::sin(th) - drive.camera_ahead_m * std::sin(heading), heading, drive);
    out.push_back({t, p});
  }
  return Trajectory(std::move(out), lap / drive.speed_mps);
}

Trajectory make_square(const Scene& scene, const DriveOptions& drive, double duration_s) {
  const double cx = 0.5 * scene.size.x();
  const double cy = 0.5 * scene.size.y();
  const double hx = 1.2;
  const double hy = 0.8;
  const Eigen::Vector2d corners[4] = {{cx - hx, cy - hy}, {cx + hx, cy - hy}, {cx + hx, cy + hy}, {cx - hx, cy + hy}};
  std::vector<Leg> legs;
  for (int c = 0; c < 4; ++c) {
    const int next = (c + 1) % 4;
    const double heading = 0.5 * kPi * c;
    legs.push_back({(corners[next] - corners[c]).norm() / drive.speed_mps, corners[c], corners[next], heading, 0.0});
    legs.push_back({90.0 / drive.turn_rate_dps, corners[next], corners[next], 0.5 * kPi * next - 0.5 * kPi, 0.5 * kPi});
  }
  return drive_legs(legs, drive, duration_s);
}

Status validate(const LaneOptions& lanes, bool living_room) {
  if (lanes.lanes < 2 || lanes.lanes > 12) return invalid_argument("lanes must be 2..12, not " + std::to_string(lanes.lanes));
  if (!(lanes.width_m >= 0.1 && lanes.width_m <= 1.0))
    return invalid_argument("lane width must be 0.1..1.0 m, not " + std::to_string(lanes.width_m));
  const double longest = living_room ? 4.0 : 20.0;
  if (!(lanes.length_m >= 0.5 && lanes.length_m <= longest))
    return invalid_argument("lane length must be 0.5.." + std::to_string(longest).substr(0, 4) + " m, not " +
                            std::to_string(lanes.length_m));
  if (living_room && (lanes.lanes - 1) * lanes.width_m > 2.4)
    return invalid_argument("lanes x width span more than 2.4 m: the lanes would reach the furniture");
  return {};
}

Trajectory make_lanes(const Scene& scene, const DriveOptions& drive, const LaneOptions& lanes, double duration_s) {
  const double cx = 0.5 * scene.size.x();
  const double cy = 0.5 * scene.size.y();
  const double x0 = cx - 0.5 * lanes.length_m;
  const double x1 = cx + 0.5 * lanes.length_m;
  const double y0 = cy - 0.5 * (lanes.lanes - 1) * lanes.width_m;
  // The turning axis's waypoints: both ends of every lane, then back through them in reverse (or,
  // with return_to_start, straight back to the first: the cycle closes there).
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < lanes.lanes; ++i) {
    const double y = y0 + i * lanes.width_m;
    const bool outward = i % 2 == 0;
    points.emplace_back(outward ? x0 : x1, y);
    points.emplace_back(outward ? x1 : x0, y);
  }
  if (!lanes.return_to_start) {
    for (std::size_t i = points.size(); i-- > 1;) points.push_back(points[i - 1]);
    points.pop_back();  // the cycle closes on the first point
  }
  return drive_legs(legs_through(points, drive), drive, duration_s);
}

Trajectory make_twin_route(const Scene& scene, const DriveOptions& drive, double duration_s) {
  // The square of make_square in the left half (x < size/2), the same shifted by half the
  // room's length in the right half; between them along y = cy + 0.95 (through the opening).
  const double half = 0.5 * scene.size.x();
  const double cx = 0.5 * half;
  const double cy = 0.5 * scene.size.y();
  const double hx = 1.2;
  const double hy = 0.8;
  const double pass_y = cy + 0.95;
  std::vector<Eigen::Vector2d> points;
  for (int room = 0; room < 2; ++room) {
    const double x = cx + room * half;
    const Eigen::Vector2d square[4] = {{x - hx, cy - hy}, {x + hx, cy - hy}, {x + hx, cy + hy}, {x - hx, cy + hy}};
    // A lap of the square, then along its first side again and up to the passage.
    for (const Eigen::Vector2d& c : square) points.push_back(c);
    points.push_back(square[0]);
    points.push_back(square[1]);
    points.emplace_back(x + hx, pass_y);
    // Through the opening (or back through it from the right half) to the other square's corner.
    if (room == 0) points.emplace_back(x + half - hx, pass_y);
    else points.emplace_back(cx - hx, pass_y);
  }
  return drive_legs(legs_through(points, drive), drive, duration_s);
}


Result<Trajectory> place_in_room(const std::vector<TimedPose>& recorded, const Rig& rig, double start_s, double end_s,
                                 const RoomMargins& margins, RoomPlacement* placement) {
  if (recorded.size() < 2) return invalid_argument("trajectory has fewer than 2 poses");
  for (std::size_t i = 1; i < recorded.size(); ++i)
    if (!(recorded[i].t_s > recorded[i - 1].t_s))
      return invalid_argument("trajectory times do not increase at pose " + std::to_string(i + 1));
  if (!(margins.walls_m > 0.0 && margins.floor_m > 0.0 && margins.ceiling_m > 0.0))
    return invalid_argument("room margins must be positive");
  std::vector<TimedPose> from_start = recorded;
  for (TimedPose& s : from_start) s.t_s -= recorded.front().t_s;
  Trajectory moved(std::move(from_start));
  if (!(start_s >= 0.0) || !(end_s >= start_s) || end_s > moved.duration_s() + 1e-9)
    return invalid_argument("the window " + std::to_string(start_s) + " .. " + std::to_string(end_s) +
                            " s is outside the trajectory's " + std::to_string(moved.duration_s()) + " s");
  const std::vector<Eigen::Vector3f> points = path_points(moved, rig, start_s, end_s);
  Eigen::Vector3d lo = points.front().cast<double>();
  Eigen::Vector3d hi = lo;
  for (const Eigen::Vector3f& p : points) {
    lo = lo.cwiseMin(p.cast<double>());
    hi = hi.cwiseMax(p.cast<double>());
  }
  RoomPlacement out;
  out.path_lo = lo;
  out.path_hi = hi;
  const Eigen::Vector3d below(margins.walls_m, margins.walls_m, margins.floor_m);
  const Eigen::Vector3d above(margins.walls_m, margins.walls_m, margins.ceiling_m);
  out.offset = below - lo;
  out.size = hi - lo + below + above;
  std::vector<TimedPose> samples = moved.samples();
  for (TimedPose& s : samples) s.pose.p_wb += out.offset;
  if (placement != nullptr) *placement = out;
  return Trajectory(std::move(samples));
}

std::vector<Eigen::Vector3f> path_points(const Trajectory& trajectory, const Rig& rig, double start_s, double end_s) {
  std::vector<Eigen::Vector3f> out;
  auto add = [&](const Pose& p) {
    out.push_back(p.p_wb.cast<float>());
    out.push_back((p.p_wb + p.q_wb * rig.t_bc).cast<float>());
  };
  add(trajectory.at(start_s));
  for (const TimedPose& s : trajectory.samples())
    if (s.t_s > start_s && s.t_s < end_s) add(s.pose);
  add(trajectory.at(end_s));
  return out;
}

}  // namespace ale::render
