// False relocalisation on a route with repeated texture (issue 31): `ale-render --scene twin`
// renders two living rooms alike, side by side (the right one is the left one moved 6 m along x;
// a partition at x = 6 m with an opening). The twin route drives the square in the left room
// (one lap and its first side again, 0-41 s), goes through the opening and drives the same
// square in the right room from 70.3 s. The lights go off from 76 to 78 s while the camera drives
// along the right room's first side, which looks like the left room's first side, mapped twice
// before (0-8 s and 33-41 s); the right room's own first side was mapped from 70.3 s until the
// lights went off. Replayed through the daemon's loop with the built-in vocabulary. As a control,
// a kidnap inside the left room, while only it is mapped.
//
// A relocalised frame is judged without aligning the run (a monocular map drifts in scale over
// the route): the map's earlier posed frame whose camera centre is nearest the relocalised one
// is where the relocaliser put the camera, and its ground truth says which place that is. The
// relocalisation is right when that place is within 1 m of where the camera really was, and
// false otherwise: in the twin room (the same place 6 m away) or anywhere else.
//
// False loops (issue 32) on the same run: the first room is driven round once, the second never,
// so a loop closed after the camera left the first room joins the second room's look-alike view to
// the first room's, and is false (counted from the frame log's `loops` column).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "app/daemon/frame_loop.h"
#include "app/tools/lib/eval/frame_log.h"
#include "tests/host/app/rendered_sequence.h"
#include "tests/host/support/test_data.h"

namespace ale::app {
namespace {

constexpr double kPartitionX = 6.0;  // build_twin_scene: the rooms' boundary, and their offset
constexpr double kRightPlaceM = 1.0;

// groundtruth.txt (TUM: the camera's position) by timestamp in ns.
std::map<std::int64_t, Eigen::Vector3d> read_camera_truth(const std::string& path) {
  std::map<std::int64_t, Eigen::Vector3d> truth;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string stamp;
    Eigen::Vector3d p;
    fields >> stamp >> p.x() >> p.y() >> p.z();
    const std::size_t dot = stamp.find('.');
    std::string fraction = dot == std::string::npos ? "" : stamp.substr(dot + 1);
    fraction.resize(9, '0');
    truth[std::stoll(stamp.substr(0, dot)) * 1000000000LL + std::stoll(fraction)] = p;
  }
  return truth;
}

struct Judged {
  int relocalisations = 0;  // frames in state relocalized
  int right = 0;
  int twin = 0;       // put at the same place in the other room
  int elsewhere = 0;  // put anywhere else
  int resets = 0;
  int loops_first_room = 0;  // loops closed while the camera drove the first room's square
  int loops_after = 0;       // ... after it left it: false (the second room is not driven round)
};

// The twin route leaves the first room after its lap and a side (41 s).
constexpr double kFirstRoomEndS = 42.0;

// Renders `args` (the twin scene), replays it through the daemon's loop and judges each
// relocalised frame (the file's comment); prints one line per relocalisation and the counts.
Judged replay_and_judge(const std::string& tag, const std::string& args) {
  Judged judged;
  const std::string work = test::make_temp_dir(tag);
  EXPECT_TRUE(test::render_sequence(work + "/seq", "--scene twin --fps 15 --width 320 --height 240 --supersample 1 " + args));
  const std::map<std::int64_t, Eigen::Vector3d> truth = read_camera_truth(work + "/seq/groundtruth.txt");
  hal::FakePoseSink sink;
  hal::NullGpio gpio;
  test::RenderedReplay replay;
  EXPECT_TRUE(replay.open(work + "/seq", sink, gpio));
  if (!replay.deps) return judged;
  DaemonConfig config;
  config.daemon.frame_log = work + "/frames.csv";
  RunSummary summary;
  const Status s = run_frame_loop(config, *replay.deps, summary);
  EXPECT_TRUE(s.ok()) << s.to_string();
  EXPECT_EQ(sink.poses.size(), truth.size());
  judged.resets = summary.resets;
  const std::int64_t t0 = truth.empty() ? 0 : truth.begin()->first;
  // Loops closed, by when: the first room is driven round once, the second never.
  const Result<eval::FrameLog> log = eval::read_frame_log(config.daemon.frame_log);
  EXPECT_TRUE(log.ok()) << log.status().to_string();
  if (log.ok()) {
    for (std::size_t i = 0; i < log->frames.size(); ++i) {
      const int loops = eval::loops_closed_at(*log, i);
      if (loops == 0) continue;
      const double at_s = static_cast<double>(static_cast<std::int64_t>(log->frames[i].timestamp_ns) - t0) * 1e-9;
      (at_s < kFirstRoomEndS ? judged.loops_first_room : judged.loops_after) += loops;
      std::printf("loop closed at %.2f s: %s\n", at_s, at_s < kFirstRoomEndS ? "the first room's lap" : "FALSE");
    }
  }
  for (std::size_t i = 0; i < sink.poses.size(); ++i) {
    const hal::PoseEstimate& p = sink.poses[i];
    if (p.state != TrackingState::kRelocalized) continue;
    ++judged.relocalisations;
    const Eigen::Vector3d at(p.p_wc[0], p.p_wc[1], p.p_wc[2]);
    const hal::PoseEstimate* nearest = nullptr;
    double nearest_m = INFINITY;
    for (std::size_t j = 0; j < i; ++j) {
      const hal::PoseEstimate& q = sink.poses[j];
      if (!has_pose(q.state) || q.map_id != p.map_id) continue;
      const double d = (Eigen::Vector3d(q.p_wc[0], q.p_wc[1], q.p_wc[2]) - at).norm();
      if (d < nearest_m) {
        nearest_m = d;
        nearest = &q;
      }
    }
    const auto really = truth.find(p.timestamp_ns);
    if (nearest == nullptr || really == truth.end() || truth.count(nearest->timestamp_ns) == 0) {
      ADD_FAILURE() << "relocalised frame at " << p.timestamp_ns << " ns: no earlier pose in its map or no ground truth";
      continue;
    }
    const Eigen::Vector3d& placed = truth.at(nearest->timestamp_ns);
    const double off_m = (placed - really->second).norm();
    const Eigen::Vector3d twin_shift(really->second.x() < kPartitionX ? kPartitionX : -kPartitionX, 0.0, 0.0);
    const double twin_off_m = (placed - (really->second + twin_shift)).norm();
    const bool right = off_m < kRightPlaceM;
    const bool twin = !right && twin_off_m < kRightPlaceM;
    ++(right ? judged.right : twin ? judged.twin : judged.elsewhere);
    std::printf("relocalised at %.2f s at (%.2f, %.2f): placed where the camera was at %.2f s, (%.2f, %.2f), "
                "%.2f m away: %s\n",
                static_cast<double>(p.timestamp_ns - t0) * 1e-9, really->second.x(), really->second.y(),
                static_cast<double>(nearest->timestamp_ns - t0) * 1e-9, placed.x(), placed.y(), off_m,
                right ? "right" : twin ? "in the twin room" : "elsewhere");
  }
  std::printf("relocalisations %d: right %d, in the twin room %d, elsewhere %d; resets %d\n", judged.relocalisations,
              judged.right, judged.twin, judged.elsewhere, judged.resets);
  return judged;
}

// The control: a kidnap inside the first room (at 10 s back to the pose at 3 s, 1 s without
// frames; 12 s, 165 frames) is relocalised in place. The judge can say "right", and the twin
// scene's repetition along the long walls does not mislead it while only one room is mapped.
TEST(TwinRoomsTest, AKidnapInTheFirstRoomIsRelocalisedInPlace) {
  const Judged j = replay_and_judge("twin-kidnap", "--duration 12 --kidnap 10,3,1");
  EXPECT_GE(j.relocalisations, 1);
  EXPECT_EQ(j.right, j.relocalisations);
  EXPECT_EQ(j.resets, 0);
}

// Issue 31's criterion: the loss in the second room (the lights off 76-78 s while the camera
// drives along its first side; 0-79 s, 1185 frames: about 25 s of rendering and 5 s of replay on
// one core of the shared host) is relocalised in the second room or not at all. The first room's
// look-alike place (6 m away, mapped twice) matches the frames after the light best; the
// relocaliser's continuity rule holds it back (beyond the reach of the last tracked pose, and the
// second room's keyframes give poses within the reach) until a second-room pose has 50 inliers,
// 0.53 s after the light; see docs/slam.md.
TEST(TwinRoomsTest, ALossInTheSecondRoomIsNotRelocalisedIntoTheFirst) {
  const Judged j = replay_and_judge("twin-rooms", "--duration 79 --blackout 76,2");
  EXPECT_GE(j.relocalisations, 1) << "the run must come back from the blackout by relocalisation";
  EXPECT_EQ(j.twin, 0) << "false relocalisations into the other room";
  EXPECT_EQ(j.elsewhere, 0) << "false relocalisations elsewhere";
  // Issue 32's criterion on the same run: no false loop (loop closing is on by default). A loop
  // closed after the camera left the first room joins the second room to the first.
  EXPECT_EQ(j.loops_after, 0) << "false loops";
}

}  // namespace
}  // namespace ale::app
