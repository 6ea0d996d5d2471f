#include "app/daemon/trajectory_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "tests/host/support/test_data.h"

namespace ale::app {
namespace {

FrameRecord tracked(std::uint64_t seq, double x, std::uint32_t map_id = 0) {
  FrameRecord r;
  r.pose.state = TrackingState::kTracking;
  r.pose.frame_sequence = seq;
  r.pose.timestamp_ns = 1000000000LL + static_cast<std::int64_t>(seq) * 50000000LL;
  r.pose.p_wc = {x, 0.0, 0.0};
  r.pose.map_id = static_cast<int>(map_id);
  return r;
}

struct Fixture {
  // A folder of its own: ctest runs these cases in parallel processes.
  std::string path = test::make_temp_dir("trajectory-file") + "/trajectory.tum";
  map::MapStore map{map::MapCapacity{4, 10, 8}};
  map::KeyframeId kf;
  slam::RefinedTrajectory refined;
  Fixture() {
    std::remove(path.c_str());
    kf = *map.add_keyframe(1.0, 0, geometry::SE3(), nullptr, 0);
  }
  // The frame's pose as tracking gave it (camera at x), relative to the keyframe at the origin.
  void add(const FrameRecord& r, bool with_keyframe = true) {
    const geometry::SE3 T_cw(geometry::SO3(), geometry::Vec3(-r.pose.p_wc[0], 0.0, 0.0));
    refined.add(static_cast<double>(r.pose.timestamp_ns) * 1e-9, r.pose.frame_sequence,
                with_keyframe ? kf : map::KeyframeId{}, T_cw, map);
  }
};

TEST(TrajectoryFile, FinalPosesReplaceTheOnlineOnesWhereTheKeyframeIsKnown) {
  Fixture f;
  TrajectoryFile file;
  ASSERT_TRUE(file.open(f.path, true).ok());
  const FrameRecord a = tracked(1, 0.1), b = tracked(2, 0.2), c = tracked(3, 0.3);
  FrameRecord lost = tracked(4, 9.0);
  lost.pose.state = TrackingState::kLost;
  for (const FrameRecord* r : std::vector<const FrameRecord*>{&a, &b, &c, &lost}) ASSERT_TRUE(file.append(*r).ok());
  f.add(a);
  f.add(b, false);  // no keyframe: keeps its online pose
  f.add(c);
  // a later BA moves the keyframe 1 m along x: the frames that hang on it follow
  f.map.keyframe(f.kf)->T_cw = geometry::SE3(geometry::SO3(), geometry::Vec3(-1.0, 0.0, 0.0));
  f.refined.resolve(f.map);
  ASSERT_TRUE(file.finish(&f.refined).ok());
  const std::string text = test::read_file(f.path);
  EXPECT_NE(text.find("1.050000000 1.100000 "), std::string::npos) << text;
  EXPECT_NE(text.find("1.100000000 0.200000 "), std::string::npos) << text;
  EXPECT_NE(text.find("1.150000000 1.300000 "), std::string::npos) << text;
  EXPECT_EQ(text.find("1.200000000"), std::string::npos) << "a lost frame has no line";
  EXPECT_EQ(text.find("# map 0\n"), text.find('\n') + 1) << text;
  struct stat st;
  EXPECT_NE(stat((f.path + ".tmp").c_str(), &st), 0) << "the temporary file is gone";
}

TEST(TrajectoryFile, OnlinePosesAreLeftAsWritten) {
  Fixture f;
  TrajectoryFile file;
  ASSERT_TRUE(file.open(f.path, false).ok());
  const FrameRecord a = tracked(1, 0.1), b = tracked(2, 0.2, 1);
  ASSERT_TRUE(file.append(a).ok());
  ASSERT_TRUE(file.append(b).ok());
  f.add(a);
  f.map.keyframe(f.kf)->T_cw = geometry::SE3(geometry::SO3(), geometry::Vec3(-1.0, 0.0, 0.0));
  f.refined.resolve(f.map);
  ASSERT_TRUE(file.finish(&f.refined).ok());
  const std::string text = test::read_file(f.path);
  EXPECT_NE(text.find("1.050000000 0.100000 "), std::string::npos) << text;
  EXPECT_NE(text.find("# map 1\n1.100000000 0.200000 "), std::string::npos) << text;
}

// A map file loaded while running may hold the id of a map this run made before (a run that
// started map 0, then LOAD_MAP of a home map saved as map 0): its poses are in another frame, so
// they start a segment of their own, online and in the final rewrite.
TEST(TrajectoryFile, ASegmentStartedByALoadIsKeptApartFromAnEarlierMapOfTheSameId) {
  for (const bool final_poses : {false, true}) {
    Fixture f;
    TrajectoryFile file;
    ASSERT_TRUE(file.open(f.path, final_poses).ok());
    const FrameRecord a = tracked(1, 0.1), b = tracked(2, 0.2), c = tracked(3, 5.0), d = tracked(4, 5.1);
    ASSERT_TRUE(file.append(a).ok());
    ASSERT_TRUE(file.append(b).ok());
    file.start_segment();
    ASSERT_TRUE(file.append(c).ok());
    ASSERT_TRUE(file.append(d).ok());
    for (const FrameRecord* r : {&a, &b, &c, &d}) f.add(*r, false);
    f.refined.resolve(f.map);
    ASSERT_TRUE(file.finish(&f.refined).ok());
    const std::string text = test::read_file(f.path);
    EXPECT_NE(text.find("# map 0\n1.050000000 0.100000 0.000000 0.000000 0.0000000 0.0000000 0.0000000 1.0000000\n"
                        "1.100000000 0.200000 0.000000 0.000000 0.0000000 0.0000000 0.0000000 1.0000000\n"
                        "# map 0\n1.150000000 5.000000 "),
              std::string::npos)
        << (final_poses ? "final: " : "online: ") << text;
    EXPECT_EQ(text.find("# map 0\n1.200000000"), std::string::npos) << "one break only: " << text;
  }
}

TEST(TrajectoryFile, AFailedRewriteKeepsTheOnlineFileAndSaysSo) {
  Fixture f;
  TrajectoryFile file;
  ASSERT_TRUE(file.open(f.path, true).ok());
  const FrameRecord a = tracked(1, 0.1);
  ASSERT_TRUE(file.append(a).ok());
  f.add(a);
  f.refined.resolve(f.map);
  const std::string tmp = f.path + ".tmp";
  ASSERT_EQ(mkdir(tmp.c_str(), 0700), 0);  // the temporary cannot be created
  const Status s = file.finish(&f.refined);
  rmdir(tmp.c_str());
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.code(), StatusCode::kIoError);
  EXPECT_NE(s.message().find("online poses are kept"), std::string::npos) << s.to_string();
  EXPECT_NE(test::read_file(f.path).find("1.050000000 0.100000 "), std::string::npos);
}

}  // namespace
}  // namespace ale::app
