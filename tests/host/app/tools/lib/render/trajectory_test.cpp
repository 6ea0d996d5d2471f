// The sweeper's loops close and stay on the floor at camera height, clear of the furniture; a
// recorded flight gets a room around it, keeping its motion, and the room's furniture keeps clear
// of it.
#include <gtest/gtest.h>

#include <cmath>

#include "app/tools/lib/render/trajectory.h"
#include "render_fixture.h"
#include "tests/host/support/test_data.h"

namespace ale::render {
namespace {

using test::small_scene;

TEST(RenderTrajectory, LoopClosesAtConstantSpeedAndHeight) {
  DriveOptions d;
  const Trajectory t = make_loop(small_scene(), d, 60.0);
  // One lap of the 3 x 2 m ellipse is ~7.93 m: 26.4 s at 0.3 m/s.
  double length = 0.0;
  double lap_end = -1.0;
  const auto& s = t.samples();
  for (std::size_t i = 1; i < s.size(); ++i) {
    const double step = (s[i].pose.p_wb - s[i - 1].pose.p_wb).norm();
    EXPECT_NEAR(step / (s[i].t_s - s[i - 1].t_s), d.speed_mps, 0.01);
    length += step;
    if (lap_end < 0 && length >= 7.93) lap_end = s[i].t_s;
    EXPECT_DOUBLE_EQ(s[i].pose.p_wb.z(), 0.09);
    EXPECT_FALSE(small_scene().inside_box(s[i].pose.p_wb.cast<float>(), 0.3f)) << s[i].pose.p_wb.transpose();
  }
  ASSERT_GT(lap_end, 0.0);
  EXPECT_NEAR(lap_end, 26.4, 0.2);
  // After a lap the pose is the start pose again (a closed loop).
  const double lap = 7.9327 / d.speed_mps;
  EXPECT_LT((t.at(lap).p_wb - t.at(0.0).p_wb).norm(), 0.01);
  EXPECT_LT(t.at(lap).q_wb.angularDistance(t.at(0.0).q_wb), 0.01);
}

TEST(RenderTrajectory, SquareTurnsInPlaceAndCloses) {
  DriveOptions d;
  const Trajectory t = make_square(small_scene(), d, 40.0);
  // Legs: 8 s straight, 1.5 s turn, 5.33 s straight, 1.5 s turn, ... lap 32.67 s.
  const double lap = 2.0 * (2.4 + 1.6) / d.speed_mps + 4.0 * 1.5;
  // Within one 5 ms trajectory sample of motion (1.5 mm): the lap end falls between samples.
  EXPECT_LT((t.at(lap).p_wb - t.at(0.0).p_wb).norm(), 0.002);
  // Mid-turn at the first corner: heading 45 degrees, the camera 15 cm from the corner.
  const Pose mid = t.at(8.0 + 0.75);
  const Eigen::Vector3d heading = mid.q_wb * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(heading.y(), heading.x()), 0.25 * 3.14159265358979, 1e-3);
  EXPECT_NEAR((mid.p_wb.head<2>() - Eigen::Vector2d(4.2, 1.7)).norm(), 0.15, 1e-6);
  for (const TimedPose& s : t.samples())
    EXPECT_FALSE(small_scene().inside_box(s.pose.p_wb.cast<float>(), 0.3f)) << s.pose.p_wb.transpose();
}

TEST(RenderTrajectory, LanesTurnInPlaceMoveOverAndComeBack) {
  DriveOptions d;
  LaneOptions lanes;  // 6 lanes 0.3 m apart, 3 m long
  ASSERT_TRUE(validate(lanes).ok());
  // Out: 6 lanes of 10 s, 5 move-overs of 1 s, 10 quarter turns of 1.5 s; then a half turn of 3 s
  // and the same back: a cycle of 2 x (60 + 5 + 15) + 2 x 3 = 166 s.
  const double cycle = 2.0 * (6 * 10.0 + 5 * 1.0 + 10 * 1.5) + 2 * 3.0;
  const Trajectory t = make_lanes(small_scene(), d, lanes, cycle + 5.0);
  EXPECT_LT((t.at(cycle).p_wb - t.at(0.0).p_wb).norm(), 0.002);
  EXPECT_LT(t.at(cycle).q_wb.angularDistance(t.at(0.0).q_wb), 1e-3);
  // The first lane ends at 10 s; during the first turn (10-11.5 s) the turning axis stays put and
  // the heading goes from 0 to 90 degrees (the camera swings on its 15 cm arm).
  auto heading = [&](double ts) {
    const Eigen::Vector3d h = t.at(ts).q_wb * Eigen::Vector3d::UnitX();
    return std::atan2(h.y(), h.x());
  };
  auto axis = [&](double ts) {
    const Pose p = t.at(ts);
    return Eigen::Vector2d(p.p_wb.x() - d.camera_ahead_m * std::cos(heading(ts)),
                           p.p_wb.y() - d.camera_ahead_m * std::sin(heading(ts)));
  };
  EXPECT_NEAR(heading(10.75), 0.25 * 3.14159265358979, 1e-3);
  EXPECT_LT((axis(10.2) - axis(11.3)).norm(), 1e-6);
  // Then it moves over by one lane width and drives the second lane back (heading 180 degrees).
  EXPECT_NEAR((axis(12.5) - axis(11.5)).norm(), lanes.width_m, 1e-3);
  EXPECT_NEAR(std::abs(heading(20.0)), 3.14159265358979, 1e-3);
  for (const TimedPose& s : t.samples()) {
    EXPECT_DOUBLE_EQ(s.pose.p_wb.z(), 0.09);
    EXPECT_FALSE(small_scene().inside_box(s.pose.p_wb.cast<float>(), 0.3f)) << s.pose.p_wb.transpose();
  }
  LaneOptions wide = lanes;
  wide.width_m = 0.6;
  EXPECT_FALSE(validate(wide).ok());  // 3 m of lanes would reach the sofa
}

TEST(RenderTrajectory, TurnRateSetsTheTurnsInPlace) {
  DriveOptions d;
  d.turn_rate_dps = 90.0;
  const Trajectory square = make_square(small_scene(), d, 40.0);
  // The first corner at 8 s: a quarter turn now takes 1 s; half way at 8.5 s.
  const Eigen::Vector3d h = square.at(8.5).q_wb * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(h.y(), h.x()), 0.25 * 3.14159265358979, 1e-3);
  const Eigen::Vector3d after = square.at(9.0).q_wb * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(std::atan2(after.y(), after.x()), 0.5 * 3.14159265358979, 1e-3);
  // Lanes: the cycle of LanesTurnInPlaceMoveOverAndComeBack with turns of 1 s and 2 s.
  const double cycle = 2.0 * (6 * 10.0 + 5 * 1.0 + 10 * 1.0) + 2 * 2.0;
  const Trajectory lanes = make_lanes(small_scene(), d, LaneOptions{}, cycle + 1.0);
  EXPECT_LT((lanes.at(cycle).p_wb - lanes.at(0.0).p_wb).norm(), 0.002);
  // 4 s before the end it is driving the first lane back, 0.3 m from where it started.
  EXPECT_GT((lanes.at(cycle - 4.0).p_wb - lanes.at(0.0).p_wb).norm(), 0.25);
}

TEST(RenderTrajectory, LanesOutsideTheLivingRoomMayBeLonger) {
  LaneOptions long_lanes;
  long_lanes.length_m = 6.0;
  long_lanes.width_m = 0.6;
  EXPECT_FALSE(validate(long_lanes).ok());
  EXPECT_TRUE(validate(long_lanes, false).ok());
  long_lanes.length_m = 25.0;
  EXPECT_FALSE(validate(long_lanes, false).ok());
}

TEST(RenderTrajectory, TwinRouteDrivesTheSameSquareInBothRooms) {
  SceneOptions o;
  o.texel_scale = 4.0f;
  Result<Scene> twin = build_twin_scene(o);
  ASSERT_TRUE(twin.ok()) << twin.status().to_string();
  DriveOptions d;
  const Trajectory t = make_twin_route(*twin, d, 200.0);
  // It starts at the left square's first corner heading +x, and later passes the same corner of
  // the right square, 6 m along, with the same heading.
  const Pose start = t.at(0.0);
  double best = 1e9;
  double when = 0.0;
  for (const TimedPose& s : t.samples()) {
    const double gap = (s.pose.p_wb - start.p_wb - Eigen::Vector3d(6.0, 0.0, 0.0)).norm() +
                       s.pose.q_wb.angularDistance(start.q_wb);
    if (gap < best) {
      best = gap;
      when = s.t_s;
    }
  }
  EXPECT_LT(best, 0.01) << "at " << when << " s";
  bool left = false, right = false;
  for (const TimedPose& s : t.samples()) {
    const Eigen::Vector3f p = s.pose.p_wb.cast<float>();
    // Clear of the furniture and the partition: through the partition only in its opening.
    EXPECT_FALSE(twin->inside_box(p, 0.2f)) << p.transpose() << " at " << s.t_s;
    left |= p.x() < 5.5f;
    right |= p.x() > 6.5f;
  }
  EXPECT_TRUE(left && right);
}

// A synthetic 8 x 3 x 2 m flight at absolute times, rolling and pitching.
std::vector<TimedPose> synthetic_flight() {
  std::vector<TimedPose> rec;
  for (int i = 0; i <= 100; ++i) {
    TimedPose p;
    p.t_s = 100.0 + i * 0.1;
    p.pose.p_wb = Eigen::Vector3d(-4.0 + 0.08 * i, 1.5 * std::sin(i * 0.1), 1.0 + std::cos(i * 0.2));
    p.pose.q_wb = Eigen::Quaterniond(Eigen::AngleAxisd(0.3 * std::sin(i * 0.05), Eigen::Vector3d::UnitX()) *
                                     Eigen::AngleAxisd(0.02 * i, Eigen::Vector3d::UnitZ()));
    rec.push_back(p);
  }
  return rec;
}

TEST(RenderTrajectory, PlacesAFlightInARoomAroundIt) {
  const std::vector<TimedPose> rec = synthetic_flight();
  const Rig rig = euroc_cam0_rig();
  RoomMargins m;
  RoomPlacement room;
  Result<Trajectory> t = place_in_room(rec, rig, 0.0, 10.0, m, &room);
  ASSERT_TRUE(t.ok()) << t.status().to_string();
  EXPECT_DOUBLE_EQ(t->samples().front().t_s, 0.0);
  EXPECT_NEAR(t->duration_s(), 10.0, 1e-9);
  // The body's box is 8 x 3 x 2 m; the camera sits a few cm off it, so the room is a little more
  // than that plus the margins.
  EXPECT_GT(room.size.x(), 8.0 + 2.0 * m.walls_m);
  EXPECT_LT(room.size.x(), 8.0 + 2.0 * m.walls_m + 0.2);
  EXPECT_GT(room.size.z(), 2.0 + m.floor_m + m.ceiling_m);
  EXPECT_LT(room.size.z(), 2.0 + m.floor_m + m.ceiling_m + 0.2);
  // Moved, not turned or scaled: every pose is the recorded one plus the offset.
  for (std::size_t i = 0; i < rec.size(); ++i) {
    const TimedPose& s = t->samples()[i];
    EXPECT_NEAR(s.t_s, rec[i].t_s - 100.0, 1e-9);
    EXPECT_LT((s.pose.p_wb - (rec[i].pose.p_wb + room.offset)).norm(), 1e-12);
    EXPECT_LT(s.pose.q_wb.angularDistance(rec[i].pose.q_wb), 1e-12);
  }
  // Body and camera stay the margins away from the walls, the floor and the ceiling.
  for (const Eigen::Vector3f& p : path_points(*t, rig, 0.0, 10.0)) {
    for (int a = 0; a < 2; ++a) {
      EXPECT_GE(p[a], m.walls_m - 1e-4);
      EXPECT_LE(p[a], room.size[a] - m.walls_m + 1e-4);
    }
    EXPECT_GE(p.z(), m.floor_m - 1e-4);
    EXPECT_LE(p.z(), room.size.z() - m.ceiling_m + 1e-4);
  }
  // A window: the room is sized around that part only.
  RoomPlacement part;
  ASSERT_TRUE(place_in_room(rec, rig, 0.0, 2.0, m, &part).ok());
  EXPECT_LT(part.size.x(), 1.6 + 2.0 * m.walls_m + 0.2);

  EXPECT_FALSE(place_in_room(rec, rig, 5.0, 10.5, m, nullptr).ok());  // past the end
  EXPECT_FALSE(place_in_room(rec, rig, 3.0, 2.0, m, nullptr).ok());   // backwards
  EXPECT_FALSE(place_in_room({rec.front()}, rig, 0.0, 0.0, m, nullptr).ok());
  std::vector<TimedPose> bad = rec;
  bad[5].t_s = bad[4].t_s;  // not increasing
  EXPECT_FALSE(place_in_room(bad, rig, 0.0, 1.0, m, nullptr).ok());
}

TEST(RenderTrajectory, HallFurnitureKeepsClearOfThePath) {
  const std::vector<TimedPose> rec = synthetic_flight();
  const Rig rig = euroc_cam0_rig();
  RoomPlacement room;
  Result<Trajectory> t = place_in_room(rec, rig, 0.0, 10.0, RoomMargins{}, &room);
  ASSERT_TRUE(t.ok());
  const std::vector<Eigen::Vector3f> path = path_points(*t, rig, 0.0, 10.0);
  SceneOptions o;
  o.texel_scale = 4.0f;
  const float clearance = 0.8f;
  Result<Scene> scene = build_hall_scene(o, room.size.cast<float>(), path, clearance);
  ASSERT_TRUE(scene.ok()) << scene.status().to_string();
  EXPECT_TRUE(scene->size.isApprox(room.size.cast<float>()));
  for (const Eigen::Vector3f& p : path) EXPECT_FALSE(scene->inside_box(p, clearance - 1e-3f)) << p.transpose();
  int furniture = 0;
  for (const Box& b : scene->boxes) furniture += b.emission[kMinZ] > 0.0f ? 0 : 1;  // not the lamps
  // 12 x 7 m of floor: room for wall furniture and crates away from the path.
  EXPECT_GE(furniture, 4);
  // From anywhere on the path a ray meets a surface within the room.
  for (std::size_t i = 0; i < path.size(); i += 97) {
    Hit hit;
    ASSERT_TRUE(cast_ray(*scene, path[i], Eigen::Vector3f(1.0f, 0.2f, -0.1f).normalized(), hit));
    EXPECT_LT(hit.t, scene->size.norm());
  }
  // A path through the whole room leaves no place for crates, but the room is still built.
  std::vector<Eigen::Vector3f> everywhere;
  for (float x = 0.0f; x < room.size.x(); x += 0.5f)
    for (float y = 0.0f; y < room.size.y(); y += 0.5f) everywhere.emplace_back(x, y, 1.0f);
  Result<Scene> packed = build_hall_scene(o, room.size.cast<float>(), everywhere, clearance);
  ASSERT_TRUE(packed.ok());
  for (const Box& b : packed->boxes) EXPECT_GT(b.emission[kMinZ], 0.0f);
  EXPECT_FALSE(build_hall_scene(o, Eigen::Vector3f(1.0f, 5.0f, 3.0f), path, clearance).ok());
}

// Every pose of the first lap comes again one lap later (the ground truth of ale-render --laps
// at t and t + lap), within one 5 ms sample of motion where a lap's end falls between samples.
void expect_laps_repeat(const Trajectory& t, double lap_s) {
  ASSERT_GE(t.duration_s(), 2.0 * lap_s);
  double worst_m = 0.0, worst_rad = 0.0;
  for (double ts = 0.0; ts <= lap_s; ts += 0.01) {
    worst_m = std::max(worst_m, (t.at(ts + lap_s).p_wb - t.at(ts).p_wb).norm());
    worst_rad = std::max(worst_rad, t.at(ts + lap_s).q_wb.angularDistance(t.at(ts).q_wb));
  }
  EXPECT_LT(worst_m, 0.002);
  EXPECT_LT(worst_rad, 0.002);
  // Not trivially: half a lap on, the pose is elsewhere.
  EXPECT_GT((t.at(0.5 * lap_s).p_wb - t.at(0.0).p_wb).norm(), 0.5);
}

TEST(RenderTrajectory, RoutesTellTheirLap) {
  DriveOptions d;
  const Trajectory loop = make_loop(small_scene(), d, 60.0);
  EXPECT_NEAR(loop.lap_s(), 7.9327 / d.speed_mps, 0.01);
  expect_laps_repeat(loop, loop.lap_s());
  // The lap does not depend on how long the route is driven.
  EXPECT_DOUBLE_EQ(make_loop(small_scene(), d, 0.0).lap_s(), loop.lap_s());
  const Trajectory square = make_square(small_scene(), d, 70.0);
  EXPECT_NEAR(square.lap_s(), 2.0 * (2.4 + 1.6) / d.speed_mps + 4.0 * 1.5, 1e-9);
  expect_laps_repeat(square, square.lap_s());
  // The lanes out and back in reverse order: the cycle of LanesTurnInPlaceMoveOverAndComeBack.
  const Trajectory lanes = make_lanes(small_scene(), d, LaneOptions{}, 0.0);
  EXPECT_NEAR(lanes.lap_s(), 2.0 * (6 * 10.0 + 5 * 1.0 + 10 * 1.5) + 2 * 3.0, 1e-9);
  // A recorded flight does not repeat.
  Result<Trajectory> flight = place_in_room(synthetic_flight(), Rig{}, 0.0, 5.0, RoomMargins{}, nullptr);
  ASSERT_TRUE(flight.ok());
  EXPECT_EQ(flight->lap_s(), 0.0);
}

TEST(RenderTrajectory, LanesReturnToTheStartAndDriveThemTheSameWayAgain) {
  DriveOptions d;
  LaneOptions lanes;  // 6 lanes 0.3 m apart, 3 m long
  lanes.return_to_start = true;
  // 6 lanes of 10 s, 5 move-overs of 1 s, 10 quarter turns of 1.5 s; then after the last lane
  // (it ends at the first lane's end of the room, heading -x) a quarter turn, 1.5 m back across
  // the lanes (5 s) and a quarter turn to face along the first lane: 80 + 8 s.
  const double lap = 6 * 10.0 + 5 * 1.0 + 10 * 1.5 + 1.5 + 5.0 + 1.5;
  const Trajectory t = make_lanes(small_scene(), d, lanes, 2.0 * lap + 1.0);
  EXPECT_NEAR(t.lap_s(), lap, 1e-9);
  expect_laps_repeat(t, lap);
  // The first lane is driven the same way in both laps (heading +x): not back in reverse order.
  const Pose first = t.at(5.0), again = t.at(lap + 5.0);
  EXPECT_GT((first.q_wb * Eigen::Vector3d::UnitX()).x(), 0.99);
  EXPECT_GT((again.q_wb * Eigen::Vector3d::UnitX()).x(), 0.99);
  // On the way back it drives along -y at the lanes' start, from the last lane to the first.
  const Pose back = t.at(80.0 + 1.5 + 2.5);
  EXPECT_LT((back.q_wb * Eigen::Vector3d::UnitX()).y(), -0.99);
  EXPECT_NEAR(back.p_wb.x(), t.at(0.0).p_wb.x() - d.camera_ahead_m, 1e-6);
  for (const TimedPose& s : t.samples())
    EXPECT_FALSE(small_scene().inside_box(s.pose.p_wb.cast<float>(), 0.3f)) << s.pose.p_wb.transpose();
}

}  // namespace
}  // namespace ale::render
