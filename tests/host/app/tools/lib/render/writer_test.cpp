// The renderer's EuRoC output is read back unchanged by the replay backend: frames, calibration
// and ground truth; and a real EuRoC ground truth renders through the same path.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "app/tools/ale_render/euroc_writer.h"
#include "app/tools/lib/eval/trajectory.h"
#include "hal/replay/dataset.h"
#include "core/io/image_io.h"
#include "render_fixture.h"
#include "tests/host/support/test_data.h"

namespace ale::render {
namespace {

using test::small_scene;

// Renders `frames` frames of `traj` into `dir` the way ale-render does.
void write_sequence(const std::string& dir, const Trajectory& traj, const Rig& rig, int frames,
                    std::int64_t start_ns) {
  SequenceConfig c;
  c.camera = PinholeCamera::wide(96, 72);
  c.frames = frames;
  c.supersample = 1;
  c.light = LightProfile::kDimming;
  Result<SequenceRenderer> seq = SequenceRenderer::create(small_scene(), traj, rig, c);
  ASSERT_TRUE(seq.ok()) << seq.status().to_string();
  Result<EurocWriter> w = EurocWriter::create(dir, false);
  ASSERT_TRUE(w.ok()) << w.status().to_string();
  ASSERT_TRUE(w->write_sensor_yaml(c.camera, c.fps, rig, "test").ok());
  GrayImage img(c.camera.width, c.camera.height);
  for (int k = 0; k < frames; ++k) {
    FrameRecord rec;
    ASSERT_TRUE(seq->render_next(img.view(), rec).ok());
    const std::int64_t ts = start_ns + std::llround(k * 1e9 / c.fps);
    ASSERT_TRUE(w->add_frame(ts, img.view(), rec, Eigen::Vector3d::Zero(), "dimming").ok());
  }
  ASSERT_TRUE(w->finish().ok());
}

TEST(RenderWriter, ReplayBackendReadsTheOutput) {
  const std::string dir = ale::test::make_temp_dir("render_writer");
  const Trajectory traj = make_loop(small_scene(), DriveOptions{}, 1.0);
  const Rig rig = sweeper_rig(12.0);
  write_sequence(dir, traj, rig, 5, 1700000000000000000LL);

  Result<replay::Dataset> ds = replay::open_dataset(dir);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  EXPECT_EQ(ds->format, replay::DatasetFormat::kEuroc);
  ASSERT_EQ(ds->frames.size(), 5u);
  EXPECT_EQ(ds->frames[0].timestamp_ns, 1700000000000000000LL);
  EXPECT_EQ(ds->frames[1].timestamp_ns, 1700000000033333333LL);
  EXPECT_EQ(ds->width, 96);
  EXPECT_EQ(ds->height, 72);
  ASSERT_TRUE(ds->calibration.has_value());
  EXPECT_DOUBLE_EQ(ds->calibration->fx, 48.0);
  EXPECT_DOUBLE_EQ(ds->calibration->cx, 47.5);
  EXPECT_DOUBLE_EQ(ds->calibration->rate_hz, 30.0);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(ds->calibration->T_BS[static_cast<std::size_t>(4 * r + c)], rig.R_bc(r, c), 1e-11);
  GrayImage frame;
  ASSERT_TRUE(io::read_gray(ds->frames[2].path, frame).ok());
  EXPECT_EQ(frame.width, 96);

  Result<std::vector<replay::GroundTruthState>> gt = replay::read_euroc_groundtruth(ds->groundtruth_file);
  ASSERT_TRUE(gt.ok()) << gt.status().to_string();
  ASSERT_EQ(gt->size(), 5u);
  EXPECT_EQ((*gt)[3].timestamp_ns, ds->frames[3].timestamp_ns);
  const Pose p3 = traj.at(3.0 / 30.0);
  EXPECT_NEAR((*gt)[3].p_wb[0], p3.p_wb.x(), 1e-8);
  EXPECT_NEAR((*gt)[3].q_wb_wxyz[0], p3.q_wb.w(), 1e-8);
  // The TUM copy is the same trajectory, read by the evaluator.
  Result<eval::Trajectory> tum = eval::read_trajectory(dir + "/groundtruth.txt");
  ASSERT_TRUE(tum.ok()) << tum.status().to_string();
  ASSERT_EQ(tum->poses.size(), 5u);
  EXPECT_NEAR(tum->poses[3].p_wb.y(), p3.p_wb.y(), 1e-8);
  // One lighting row per frame.
  std::ifstream lighting(dir + "/lighting.csv");
  std::string line;
  int rows = 0;
  while (std::getline(lighting, line)) rows += (!line.empty() && line[0] != '#');
  EXPECT_EQ(rows, 5);
  // A second run into the same folder is refused unless asked to overwrite.
  EXPECT_FALSE(EurocWriter::create(dir, false).ok());
  EXPECT_TRUE(EurocWriter::create(dir, true).ok());
}

TEST(RenderWriter, RendersARealEurocTrajectory) {
  ALE_REQUIRE_DATA(path, "euroc_groundtruth/V1_01_easy.txt");
  Result<eval::Trajectory> t = eval::read_trajectory(path);
  ASSERT_TRUE(t.ok()) << t.status().to_string();
  std::vector<TimedPose> rec;
  for (const eval::StampedPose& s : t->poses) rec.push_back({s.t_s, {Eigen::Quaterniond(s.R_wb), s.p_wb}});
  FitReport rep;
  Result<Trajectory> fitted = fit_into_room(rec, small_scene(), euroc_cam0_rig(), 0.5, &rep);
  ASSERT_TRUE(fitted.ok()) << fitted.status().to_string();
  EXPECT_GT(rep.scale, 0.2);
  EXPECT_LE(rep.scale, 1.0);
  EXPECT_NEAR(fitted->duration_s(), t->poses.back().t_s - t->poses.front().t_s, 1e-6);
  const std::string dir = ale::test::make_temp_dir("render_writer_euroc");
  const auto start_ns = static_cast<std::int64_t>(std::llround(t->poses.front().t_s * 1e9));
  write_sequence(dir, *fitted, euroc_cam0_rig(), 3, start_ns);
  Result<replay::Dataset> ds = replay::open_dataset(dir);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  EXPECT_EQ(ds->frames.size(), 3u);
  EXPECT_NEAR(ds->calibration->T_BS[3], -0.0216401454975, 1e-12);
}

TEST(RenderWriter, SecondsTextIsExact) {
  EXPECT_EQ(ns_to_seconds_text(1403715274302140000LL), "1403715274.302140000");
  EXPECT_EQ(ns_to_seconds_text(5), "0.000000005");
}

}  // namespace
}  // namespace ale::render
