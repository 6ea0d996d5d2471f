// The renderer's EuRoC output is read back unchanged by the replay backend: frames, calibration
// and ground truth (the state CSV is the body, groundtruth.txt the camera); and a real EuRoC
// ground truth renders in a hall around it, its poses kept.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "app/tools/ale_render/euroc_writer.h"
#include "app/tools/lib/eval/trajectory.h"
#include "app/tools/lib/render/noise_model.h"
#include "hal/replay/dataset.h"
#include "core/io/image_io.h"
#include "render_fixture.h"
#include "tests/host/support/test_data.h"

namespace ale::render {
namespace {

using test::small_scene;

// Renders `frames` frames of `traj` into `dir` the way ale-render does; with `odometry` also the
// sweeper's wheel odometry (DriveOptions' rig).
void write_sequence(const std::string& dir, const Trajectory& traj, const Rig& rig, int frames,
                    std::int64_t start_ns, const OdometrySettings* odometry = nullptr) {
  SequenceConfig c;
  c.camera = PinholeCamera::wide(96, 72);
  c.frames = frames;
  c.supersample = 1;
  c.light = LightProfile::kDimming;
  Result<SequenceRenderer> seq = SequenceRenderer::create(small_scene(), traj, rig, c);
  ASSERT_TRUE(seq.ok()) << seq.status().to_string();
  Result<EurocWriter> w = EurocWriter::create(dir, false);
  ASSERT_TRUE(w.ok()) << w.status().to_string();
  // With the noise model's notes, as ale-render writes them.
  ASSERT_TRUE(w->write_sensor_yaml(c.camera, c.fps, rig, "test", describe_noise("standard", c.sensor)).ok());
  GrayImage img(c.camera.width, c.camera.height);
  std::vector<FrameTime> times;
  for (int k = 0; k < frames; ++k) {
    FrameRecord rec;
    ASSERT_TRUE(seq->render_next(img.view(), rec).ok());
    const std::int64_t ts = start_ns + std::llround(k * 1e9 / c.fps);
    ASSERT_TRUE(w->add_frame(ts, img.view(), rec, Eigen::Vector3d::Zero(), "dimming").ok());
    times.push_back({ts, rec.t_s});
  }
  ASSERT_TRUE(w->finish().ok());
  if (odometry != nullptr) {
    Result<std::string> note =
        write_sweeper_odometry(*w, traj, rig, sweeper_T_BC(rig, DriveOptions{}), times, *odometry, "test");
    ASSERT_TRUE(note.ok()) << note.status().to_string();
    EXPECT_EQ(note->rfind("odometry: ", 0), 0u) << *note;
  }
}

// The rows of odometry0/data.csv: timestamp and the six numbers.
std::vector<std::pair<std::int64_t, std::vector<double>>> read_odometry_csv(const std::string& path) {
  std::ifstream f(path);
  std::string line;
  std::getline(f, line);
  EXPECT_EQ(line, "#timestamp [ns],x [m],y [m],theta [rad],gyro_z [rad/s],v_left [m/s],v_right [m/s]");
  std::vector<std::pair<std::int64_t, std::vector<double>>> rows;
  while (std::getline(f, line)) {
    std::stringstream ss(line);
    std::string cell;
    std::getline(ss, cell, ',');
    rows.push_back({std::stoll(cell), {}});
    while (std::getline(ss, cell, ',')) rows.back().second.push_back(std::stod(cell));
    EXPECT_EQ(rows.back().second.size(), 6u) << line;
  }
  return rows;
}

TEST(RenderWriter, OdometryWithoutNoiseIsTheBaseUnderTheCameraTruth) {
  const std::string dir = ale::test::make_temp_dir("render_writer_odometry");
  const DriveOptions drive;
  const Trajectory traj = make_loop(small_scene(), drive, 2.0);
  const Rig rig = sweeper_rig(12.0);
  OdometrySettings none;
  none.noise = OdometryNoise::kNone;
  write_sequence(dir, traj, rig, 31, 1700000000000000000LL, &none);

  // T_BC from sensor.yaml.
  const std::string yaml = ale::test::read_file(dir + "/mav0/odometry0/sensor.yaml");
  EXPECT_EQ(yaml.rfind("sensor_type: odometry\ncomment: ", 0), 0u) << yaml;
  EXPECT_NE(yaml.find("\nrate_hz: 50\n"), std::string::npos);
  EXPECT_NE(yaml.find("\nnoise: none\n"), std::string::npos);
  const std::size_t data = yaml.find("data: [");
  ASSERT_NE(data, std::string::npos);
  std::stringstream numbers(yaml.substr(data + 7));
  Eigen::Matrix4d T_BC;
  for (int i = 0; i < 16; ++i) {
    std::string cell;
    std::getline(numbers, cell, i < 15 ? ',' : ']');
    T_BC(i / 4, i % 4) = std::stod(cell);
  }
  EXPECT_LT((T_BC.block<3, 1>(0, 3) - Eigen::Vector3d(0.15, 0.0, 0.09)).norm(), 1e-12);
  EXPECT_LT((T_BC.block<3, 3>(0, 0) - rig.R_bc).norm(), 1e-11);

  // 50 Hz over the frames' 1 s.
  const auto rows = read_odometry_csv(dir + "/mav0/odometry0/data.csv");
  ASSERT_EQ(rows.size(), 51u);
  // Each row is the base's truth from the start, computed here from the body: the turning axis
  // is camera_ahead_m behind the optical centre.
  auto base_at = [&](double t) {
    const Pose p = traj.at(t);
    const Eigen::Vector3d fwd = p.q_wb * Eigen::Vector3d::UnitX();
    return Eigen::Vector3d(p.p_wb.x() - drive.camera_ahead_m * fwd.x(), p.p_wb.y() - drive.camera_ahead_m * fwd.y(),
                           std::atan2(fwd.y(), fwd.x()));
  };
  const Eigen::Vector3d b0 = base_at(0.0);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(rows[i].first, 1700000000000000000LL + static_cast<std::int64_t>(i) * 20000000LL);
    const Eigen::Vector3d b = base_at(static_cast<double>(i) / 50.0);
    const Eigen::Vector2d d = Eigen::Rotation2Dd(-b0.z()) * Eigen::Vector2d(b.x() - b0.x(), b.y() - b0.y());
    EXPECT_NEAR(rows[i].second[0], d.x(), 1e-9) << i;
    EXPECT_NEAR(rows[i].second[1], d.y(), 1e-9) << i;
    EXPECT_NEAR(std::remainder(rows[i].second[2] - (b.z() - b0.z()), 2.0 * 3.14159265358979323846), 0.0, 1e-9) << i;
  }

  // groundtruth.txt back from the odometry: camera = base x T_BC, with the base of the first
  // camera pose as the odometry's origin. The files keep 9 decimals: 1e-8 m and rad.
  Result<eval::Trajectory> tum = eval::read_trajectory(dir + "/groundtruth.txt");
  ASSERT_TRUE(tum.ok()) << tum.status().to_string();
  ASSERT_EQ(tum->poses.size(), 31u);
  auto camera = [&](std::size_t k) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = tum->poses[k].R_wb;
    T.translation() = tum->poses[k].p_wb;
    return T;
  };
  const Eigen::Isometry3d T_w_odom = camera(0) * Eigen::Isometry3d(T_BC).inverse();
  int compared = 0;
  for (std::size_t k = 0; k < 31; k += 3) {  // frames at 30 fps meet rows at 50 Hz every 0.1 s
    const auto& row = rows[k / 3 * 5];
    ASSERT_EQ(row.first, 1700000000000000000LL + std::llround(static_cast<double>(k) * 1e9 / 30.0));
    Eigen::Isometry3d T_odom_base = Eigen::Isometry3d::Identity();
    T_odom_base.linear() = Eigen::AngleAxisd(row.second[2], Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T_odom_base.translation() = Eigen::Vector3d(row.second[0], row.second[1], 0.0);
    const Eigen::Isometry3d T_wc = T_w_odom * T_odom_base * Eigen::Isometry3d(T_BC);
    EXPECT_LT((T_wc.translation() - camera(k).translation()).norm(), 1e-8) << k;
    EXPECT_LT(Eigen::Quaterniond(T_wc.linear()).angularDistance(Eigen::Quaterniond(camera(k).linear())), 1e-8) << k;
    ++compared;
  }
  EXPECT_EQ(compared, 11);
}

TEST(RenderWriter, OdometryFilesAreTheSameForTheSameSeed) {
  const Trajectory traj = make_square(small_scene(), DriveOptions{}, 1.0);
  const Rig rig = sweeper_rig(12.0);
  OdometrySettings harsh;
  harsh.noise = OdometryNoise::kHarsh;
  harsh.seed = 3;
  const std::string a = ale::test::make_temp_dir("render_writer_odometry_a");
  const std::string b = ale::test::make_temp_dir("render_writer_odometry_b");
  write_sequence(a, traj, rig, 10, 1700000000000000000LL, &harsh);
  write_sequence(b, traj, rig, 10, 1700000000000000000LL, &harsh);
  for (const char* f : {"/mav0/odometry0/data.csv", "/mav0/odometry0/sensor.yaml"}) {
    EXPECT_FALSE(ale::test::read_file(a + f).empty());
    EXPECT_EQ(ale::test::read_file(a + f), ale::test::read_file(b + f)) << f;
  }
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
  // The sensor noise model is recorded in sensor.yaml's comment lines, which the reader skips.
  const std::string yaml = ale::test::read_file(dir + "/mav0/cam0/sensor.yaml");
  EXPECT_NE(yaml.find("\n# noise model: standard\n# full well: 8000 e-\n"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("\n# read noise: 2.5 e- rms\n"), std::string::npos) << yaml;
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
  // groundtruth.txt, read by the evaluator, is the same trajectory ...
  Result<eval::Trajectory> tum = eval::read_trajectory(dir + "/groundtruth.txt");
  ASSERT_TRUE(tum.ok()) << tum.status().to_string();
  ASSERT_EQ(tum->poses.size(), 5u);
  EXPECT_NEAR(tum->poses[3].p_wb.y(), p3.p_wb.y(), 1e-8);
  // ... of the camera: the sweeper's sits at the body origin, turned by the mount.
  const Eigen::Quaterniond q_c3(p3.q_wb.toRotationMatrix() * rig.R_bc);
  EXPECT_LT(Eigen::Quaterniond(tum->poses[3].R_wb).angularDistance(q_c3), 1e-7);
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
  // 0.4 s from 20 s in (the vehicle is flying then), like `ale-render --trajectory FILE --start 20`.
  const Rig rig = euroc_cam0_rig();
  const double start_s = 20.0;
  const int frames = 13;  // at 30 fps
  RoomPlacement room;
  Result<Trajectory> placed = place_in_room(rec, rig, start_s, start_s + (frames - 1) / 30.0, RoomMargins{}, &room);
  ASSERT_TRUE(placed.ok()) << placed.status().to_string();
  EXPECT_NEAR(placed->duration_s(), t->poses.back().t_s - t->poses.front().t_s, 1e-6);
  SceneOptions o;
  o.texel_scale = 4.0f;
  Result<Scene> hall = build_hall_scene(o, room.size.cast<float>(),
                                        path_points(*placed, rig, start_s, start_s + (frames - 1) / 30.0), 0.8f);
  ASSERT_TRUE(hall.ok()) << hall.status().to_string();

  const std::string dir = ale::test::make_temp_dir("render_writer_euroc");
  const auto start_ns = static_cast<std::int64_t>(std::llround(t->poses.front().t_s * 1e9));
  SequenceConfig c;
  c.camera = PinholeCamera::wide(96, 72);
  c.frames = frames;
  c.supersample = 1;
  c.start_s = start_s;
  Result<SequenceRenderer> seq = SequenceRenderer::create(*hall, *placed, rig, c);
  ASSERT_TRUE(seq.ok()) << seq.status().to_string();
  Result<EurocWriter> w = EurocWriter::create(dir, false);
  ASSERT_TRUE(w.ok());
  ASSERT_TRUE(w->write_sensor_yaml(c.camera, c.fps, rig, "test").ok());
  GrayImage img(c.camera.width, c.camera.height);
  double contrast = 0.0;
  for (int k = 0; k < frames; ++k) {
    FrameRecord fr;
    ASSERT_TRUE(seq->render_next(img.view(), fr).ok());
    const auto [lo, hi] = std::minmax_element(img.pixels.begin(), img.pixels.end());
    contrast += *hi - *lo;
    ASSERT_TRUE(w->add_frame(start_ns + std::llround((start_s + k / c.fps) * 1e9), img.view(), fr,
                             Eigen::Vector3d::Zero(), "normal").ok());
  }
  ASSERT_TRUE(w->finish().ok());
  EXPECT_GT(contrast / frames, 60.0);  // the camera sees the hall, not a blank wall

  Result<replay::Dataset> ds = replay::open_dataset(dir);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  ASSERT_EQ(ds->frames.size(), static_cast<std::size_t>(frames));
  EXPECT_NEAR(ds->calibration->T_BS[3], -0.0216401454975, 1e-12);
  Eigen::Matrix4d T_bc = Eigen::Matrix4d::Identity();
  for (int r = 0; r < 4; ++r)
    for (int k = 0; k < 4; ++k) T_bc(r, k) = ds->calibration->T_BS[static_cast<std::size_t>(4 * r + k)];
  // The state CSV is the recorded body moved into the hall, at the frame times (interpolated
  // between the 200 Hz samples); groundtruth.txt is the camera: body x T_BS.
  Result<std::vector<replay::GroundTruthState>> state = replay::read_euroc_groundtruth(ds->groundtruth_file);
  Result<eval::Trajectory> tum = eval::read_trajectory(dir + "/groundtruth.txt");
  ASSERT_TRUE(state.ok() && tum.ok());
  ASSERT_EQ(state->size(), static_cast<std::size_t>(frames));
  ASSERT_EQ(tum->poses.size(), static_cast<std::size_t>(frames));
  for (int k = 0; k < frames; ++k) {
    const double t_abs = t->poses.front().t_s + start_s + k / c.fps;
    // The recorded pose at t_abs, interpolated here from the file's own samples.
    std::size_t i = 1;
    while (t->poses[i].t_s < t_abs) ++i;
    const eval::StampedPose& a = t->poses[i - 1];
    const eval::StampedPose& b = t->poses[i];
    const double wgt = (t_abs - a.t_s) / (b.t_s - a.t_s);
    const Eigen::Vector3d p_body = a.p_wb + wgt * (b.p_wb - a.p_wb) + room.offset;
    const Eigen::Quaterniond q_body = Eigen::Quaterniond(a.R_wb).slerp(wgt, Eigen::Quaterniond(b.R_wb));
    const replay::GroundTruthState& st = (*state)[static_cast<std::size_t>(k)];
    EXPECT_EQ(st.timestamp_ns, ds->frames[static_cast<std::size_t>(k)].timestamp_ns);
    EXPECT_LT((Eigen::Vector3d(st.p_wb[0], st.p_wb[1], st.p_wb[2]) - p_body).norm(), 1e-6) << k;
    const Eigen::Quaterniond q_state(st.q_wb_wxyz[0], st.q_wb_wxyz[1], st.q_wb_wxyz[2], st.q_wb_wxyz[3]);
    EXPECT_LT(q_state.angularDistance(q_body), 1e-6) << k;
    const Eigen::Vector3d p_cam = p_body + q_body * T_bc.block<3, 1>(0, 3);
    const Eigen::Matrix3d R_cam = q_body.toRotationMatrix() * T_bc.block<3, 3>(0, 0);
    const eval::StampedPose& g = tum->poses[static_cast<std::size_t>(k)];
    EXPECT_NEAR(g.t_s, t_abs, 1e-6);
    EXPECT_LT((g.p_wb - p_cam).norm(), 1e-6) << k;
    EXPECT_LT(Eigen::Quaterniond(g.R_wb).angularDistance(Eigen::Quaterniond(R_cam)), 1e-6) << k;
    EXPECT_GT((g.p_wb - p_body).norm(), 0.06);  // cam0 is 6.9 cm from the body origin
  }
}

TEST(RenderWriter, SecondsTextIsExact) {
  EXPECT_EQ(ns_to_seconds_text(1403715274302140000LL), "1403715274.302140000");
  EXPECT_EQ(ns_to_seconds_text(5), "0.000000005");
}

}  // namespace
}  // namespace ale::render
