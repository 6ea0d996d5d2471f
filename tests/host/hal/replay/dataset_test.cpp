#include "hal/replay/dataset.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/io/image_io.h"
#include "hal/replay/euroc_writer.h"
#include "tests/host/hal/replay/replay_fixtures.h"
#include "tests/host/support/test_data.h"

namespace ale::replay {
namespace {

using test::fails_naming;

// The numbers in a "key: [a, b, ...]" line of a YAML file, read with plain string code.
std::vector<double> yaml_list(const std::string& path, const std::string& key) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind(key + ":", 0) != 0) continue;
    std::vector<double> v;
    std::string inner = line.substr(line.find('[') + 1);
    inner = inner.substr(0, inner.find(']'));
    for (char& c : inner)
      if (c == ',') c = ' ';
    std::istringstream s(inner);
    for (double d; s >> d;) v.push_back(d);
    return v;
  }
  return {};
}

// ---- real data ------------------------------------------------------------------------------

TEST(ReplayDatasetTest, EurocMicroSensorYamlValues) {
  ALE_REQUIRE_DATA(yaml, "euroc_v101_micro/mav0/cam0/sensor.yaml");
  const Result<hal::CameraCalibration> c = read_euroc_sensor_yaml(yaml);
  ASSERT_TRUE(c.ok()) << c.status().to_string();
  const std::vector<double> k = yaml_list(yaml, "intrinsics");
  const std::vector<double> d = yaml_list(yaml, "distortion_coefficients");
  const std::vector<double> res = yaml_list(yaml, "resolution");
  ASSERT_EQ(k.size(), 4u);
  ASSERT_EQ(d.size(), 4u);
  ASSERT_EQ(res.size(), 2u);
  EXPECT_EQ(c->fx, k[0]);
  EXPECT_EQ(c->fy, k[1]);
  EXPECT_EQ(c->cx, k[2]);
  EXPECT_EQ(c->cy, k[3]);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(c->distortion[i], d[i]) << i;
  EXPECT_EQ(c->width, 752);
  EXPECT_EQ(c->height, 480);
  EXPECT_EQ(c->width, static_cast<int>(res[0]));
  EXPECT_EQ(c->distortion_model, hal::DistortionModel::kRadialTangential);
  EXPECT_EQ(c->rate_hz, 20.0);
  // T_BS spans four lines in the file; spot-check the ends of each row.
  EXPECT_EQ(c->T_BS[0], 0.0148655429818);
  EXPECT_EQ(c->T_BS[3], -0.0216401454975);
  EXPECT_EQ(c->T_BS[7], -0.064676986768);
  EXPECT_EQ(c->T_BS[8], -0.0257744366974);
  EXPECT_EQ(c->T_BS[11], 0.00981073058949);
  EXPECT_EQ(c->T_BS[15], 1.0);
}

TEST(ReplayDatasetTest, EurocAcceptsRootMav0AndCam0) {
  ALE_REQUIRE_DATA(root, "euroc_v101_micro");
  for (const std::string& path : {root, root + "/mav0", root + "/mav0/cam0"}) {
    const Result<Dataset> ds = open_dataset(path);
    ASSERT_TRUE(ds.ok()) << path << ": " << ds.status().to_string();
    EXPECT_EQ(ds->format, DatasetFormat::kEuroc);
    EXPECT_EQ(ds->frames.size(), 95u);
    EXPECT_EQ(ds->width, 752);
    EXPECT_EQ(ds->height, 480);
    ASSERT_TRUE(ds->calibration.has_value());
    EXPECT_FALSE(ds->groundtruth_file.empty()) << path;
  }
}

TEST(ReplayDatasetTest, EurocGroundTruthRows) {
  ALE_REQUIRE_DATA(root, "euroc_v101_micro");
  const Result<Dataset> ds = open_dataset(root);
  ASSERT_TRUE(ds.ok());
  const Result<std::vector<GroundTruthState>> gt = read_euroc_groundtruth(ds->groundtruth_file);
  ASSERT_TRUE(gt.ok()) << gt.status().to_string();
  ASSERT_EQ(gt->size(), 95u);  // the README: matched rows, one per frame
  EXPECT_EQ(gt->front().timestamp_ns, ds->frames.front().timestamp_ns);
  // First row of the file: 1403715273262142976,0.878895,2.1834,0.948427,0.069433,-0.824237,...
  EXPECT_EQ(gt->front().p_wb[0], 0.878895);
  EXPECT_EQ(gt->front().q_wb_wxyz[0], 0.069433);
  EXPECT_EQ(gt->front().q_wb_wxyz[1], -0.824237);
  EXPECT_EQ(gt->front().v_wb[0], 0.00157587);
}

TEST(ReplayDatasetTest, TumFolderOfTimestampNamedImages) {
  ALE_REQUIRE_DATA(root, "tum_fr2_desk_20");
  for (const std::string& path : {root, root + "/rgb"}) {
    const Result<Dataset> ds = open_dataset(path);
    ASSERT_TRUE(ds.ok()) << path << ": " << ds.status().to_string();
    EXPECT_EQ(ds->format, DatasetFormat::kTum);
    ASSERT_EQ(ds->frames.size(), 20u);
    EXPECT_EQ(ds->width, 640);
    EXPECT_EQ(ds->height, 480);
    EXPECT_FALSE(ds->calibration.has_value());
    EXPECT_EQ(ds->frames.front().timestamp_ns, 1311868169163498000);
    EXPECT_EQ(ds->frames.back().timestamp_ns, 1311868171063438000);
    for (std::size_t i = 1; i < ds->frames.size(); ++i)
      EXPECT_LT(ds->frames[i - 1].timestamp_ns, ds->frames[i].timestamp_ns);
  }
}

TEST(ReplayDatasetTest, SecondsParseExactly) {
  EXPECT_EQ(parse_seconds_ns("1311868169.163498"), 1311868169163498000);
  EXPECT_EQ(parse_seconds_ns("12"), 12000000000);
  EXPECT_EQ(parse_seconds_ns("0.000000001"), 1);
  EXPECT_FALSE(parse_seconds_ns("0.0000000001").has_value());  // finer than 1 ns
  EXPECT_FALSE(parse_seconds_ns("12.").has_value());
  EXPECT_FALSE(parse_seconds_ns("1e9").has_value());
  EXPECT_FALSE(parse_seconds_ns("-1.5").has_value());
  EXPECT_FALSE(parse_seconds_ns("abc").has_value());
  EXPECT_EQ(parse_integer_ns("1403715273262142976"), 1403715273262142976);
  EXPECT_FALSE(parse_integer_ns("99999999999999999999").has_value());
  EXPECT_FALSE(parse_integer_ns("14037x").has_value());
}

// ---- fixtures -------------------------------------------------------------------------------

TEST(ReplayDatasetTest, TumRgbTxtWithComments) {
  const std::string dir = ale::test::make_temp_dir("tum");
  std::string list = "# color images\n# file: 'fixture'\n# timestamp filename\n";
  for (int i = 0; i < 3; ++i) {
    const std::string name = "rgb/" + std::to_string(100 + i) + ".25.png";
    std::filesystem::create_directories(dir + "/rgb");
    ASSERT_TRUE(io::write_png(dir + "/" + name, test::pattern_frame(8, 6, i).view()).ok());
    list += std::to_string(100 + i) + ".250000 " + name + "\n";
  }
  ASSERT_TRUE(ale::test::write_file(dir + "/rgb.txt", list));
  const Result<Dataset> ds = open_dataset(dir);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  ASSERT_EQ(ds->frames.size(), 3u);
  EXPECT_EQ(ds->list_file, dir + "/rgb.txt");
  EXPECT_EQ(ds->frames[2].timestamp_ns, 102250000000);
  EXPECT_EQ(ds->width, 8);
}

TEST(ReplayDatasetTest, TumRgbTxtBadLines) {
  const std::string dir = ale::test::make_temp_dir("tum");
  std::filesystem::create_directories(dir + "/rgb");
  ASSERT_TRUE(io::write_png(dir + "/rgb/1.png", test::pattern_frame(8, 6, 0).view()).ok());
  ASSERT_TRUE(io::write_png(dir + "/rgb/2.png", test::pattern_frame(8, 6, 1).view()).ok());
  const std::string list = dir + "/rgb.txt";
  ASSERT_TRUE(ale::test::write_file(list, "# c\n1.0 rgb/1.png\n2.0 rgb/2.png extra\n"));
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kCorruptData, list + ":3:"));
  ASSERT_TRUE(ale::test::write_file(list, "# c\n1.0 rgb/1.png\nsoon rgb/2.png\n"));
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kCorruptData, list + ":3:"));
  ASSERT_TRUE(ale::test::write_file(list, "2.0 rgb/2.png\n1.0 rgb/1.png\n"));
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kCorruptData, list + ":2:"));
  ASSERT_TRUE(ale::test::write_file(list, "1.0 rgb/1.png\n2.0 rgb/3.png\n"));
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kNotFound, dir + "/rgb/3.png"));
}

TEST(ReplayDatasetTest, TumFolderWithBadImageName) {
  const std::string dir = ale::test::make_temp_dir("tum");
  ASSERT_TRUE(io::write_png(dir + "/1311868169.163498.png", test::pattern_frame(8, 6, 0).view()).ok());
  ASSERT_TRUE(io::write_png(dir + "/frame_two.png", test::pattern_frame(8, 6, 1).view()).ok());
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kCorruptData, dir + "/frame_two.png"));
}

TEST(ReplayDatasetTest, EurocFixtureReads) {
  const std::string dir = ale::test::make_temp_dir("euroc");
  const std::string cam0 = test::write_euroc(dir, 5, 32, 24);
  const Result<Dataset> ds = open_dataset(dir);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  ASSERT_EQ(ds->frames.size(), 5u);
  EXPECT_EQ(ds->folder, cam0);
  EXPECT_TRUE(ds->groundtruth_file.empty());
  for (int i = 0; i < 5; ++i) EXPECT_EQ(ds->frames[static_cast<std::size_t>(i)].timestamp_ns, test::fixture_timestamp_ns(i));
  const hal::CameraCalibration& c = *ds->calibration;
  EXPECT_EQ(c.fx, 400.5);
  EXPECT_EQ(c.fy, 401.25);
  EXPECT_EQ(c.cx, 160.125);
  EXPECT_EQ(c.cy, 120.5);
  EXPECT_EQ(c.distortion[2], 1e-3);
  EXPECT_EQ(c.distortion[3], -5.0e-4);
  EXPECT_EQ(c.T_BS[1], -1.0);
  EXPECT_EQ(c.T_BS[3], 0.5);
  EXPECT_EQ(c.T_BS[11], 0.125);
  EXPECT_EQ(c.width, 32);
}

TEST(ReplayDatasetTest, EurocFrameListedButMissing) {
  const std::string dir = ale::test::make_temp_dir("euroc");
  const std::string cam0 = test::write_euroc(dir, 4, 16, 8);
  const std::string gone = cam0 + "/data/" + std::to_string(test::fixture_timestamp_ns(2)) + ".png";
  ASSERT_EQ(std::remove(gone.c_str()), 0);
  // The header is line 1, so frame 2 is on line 4.
  const Status st = open_dataset(dir).status();
  EXPECT_TRUE(fails_naming(st, StatusCode::kNotFound, gone));
  EXPECT_TRUE(fails_naming(st, StatusCode::kNotFound, cam0 + "/data.csv:4:"));
}

TEST(ReplayDatasetTest, EurocMalformedCsvLines) {
  const std::string dir = ale::test::make_temp_dir("euroc");
  const std::string cam0 = test::write_euroc(dir, 3, 16, 8);
  const std::string csv = cam0 + "/data.csv";
  const std::string t0 = std::to_string(test::fixture_timestamp_ns(0));
  const std::string t1 = std::to_string(test::fixture_timestamp_ns(1));
  const std::string header = "#timestamp [ns],filename\n";
  const struct {
    std::string content;
    const char* where;
  } cases[] = {
      {header + t0 + "," + t0 + ".png\n" + t1 + "\n", ":3:"},                          // one column
      {header + t0 + "," + t0 + ".png,extra\n", ":2:"},                                 // three columns
      {header + t0 + "," + t0 + ".png\nabc," + t1 + ".png\n", ":3:"},                   // not a number
      {header + t0 + "," + t0 + ".png\n1.5e18," + t1 + ".png\n", ":3:"},                // not an integer
      {header + t1 + "," + t1 + ".png\n" + t0 + "," + t0 + ".png\n", ":3:"},            // backwards
      {header + t0 + "," + t0 + ".png\n" + t0 + "," + t1 + ".png\n", ":3:"},            // repeated
  };
  for (const auto& c : cases) {
    ASSERT_TRUE(ale::test::write_file(csv, c.content));
    EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kCorruptData, csv + c.where)) << c.content;
  }
  ASSERT_TRUE(ale::test::write_file(csv, header));
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kNotFound, csv));
}

TEST(ReplayDatasetTest, EurocBackwardsTimestampNamesBothLines) {
  const std::string dir = ale::test::make_temp_dir("euroc");
  const std::string cam0 = test::write_euroc(dir, 3, 16, 8);
  const std::string csv = cam0 + "/data.csv";
  std::string rows = "#timestamp [ns],filename\n";
  for (int i : {0, 2, 1}) {
    const std::string t = std::to_string(test::fixture_timestamp_ns(i));
    rows += t + "," + t + ".png\n";
  }
  ASSERT_TRUE(ale::test::write_file(csv, rows));
  const Status st = open_dataset(dir).status();
  EXPECT_TRUE(fails_naming(st, StatusCode::kCorruptData, csv + ":4:"));
  EXPECT_TRUE(fails_naming(st, StatusCode::kCorruptData, "on line 3"));
}

TEST(ReplayDatasetTest, EmptyAndMissingFolders) {
  const std::string dir = ale::test::make_temp_dir("empty");
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kNotFound, dir));
  EXPECT_TRUE(fails_naming(open_dataset(dir + "/nothing").status(), StatusCode::kNotFound, dir + "/nothing"));
  std::filesystem::create_directories(dir + "/rgb");
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kNotFound, dir + "/rgb"));
}

TEST(ReplayDatasetTest, SensorYamlProblems) {
  const std::string dir = ale::test::make_temp_dir("yaml");
  const std::string cam0 = test::write_euroc(dir, 2, 16, 8);
  const std::string yaml = cam0 + "/sensor.yaml";
  const std::string good = test::euroc_yaml(16, 8);
  const auto without = [&](const std::string& key) {
    std::string out, line;
    std::istringstream in(good);
    while (std::getline(in, line))
      if (line.rfind(key + ":", 0) != 0) out += line + "\n";
    return out;
  };

  ASSERT_TRUE(ale::test::write_file(yaml, without("intrinsics")));
  Status st = open_dataset(dir).status();
  EXPECT_TRUE(fails_naming(st, StatusCode::kNotFound, yaml));
  EXPECT_TRUE(fails_naming(st, StatusCode::kNotFound, "intrinsics"));

  ASSERT_TRUE(ale::test::write_file(yaml, without("intrinsics") + "intrinsics: [400, 400, 8]\n"));
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kCorruptData, yaml + ":17:"));

  ASSERT_TRUE(ale::test::write_file(yaml, without("intrinsics") + "intrinsics: [400, x, 8, 4]\n"));
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kCorruptData, yaml + ":17:"));

  ASSERT_TRUE(ale::test::write_file(yaml, without("distortion_model") + "distortion_model: fisheye624\n"));
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kUnsupported, yaml + ":17:"));

  // An unterminated list is reported at the line that opened it (T_BS data is on line 8).
  std::string broken = good;
  broken.replace(broken.find("0.0, 0.0, 0.0, 1.0]"), 19, "0.0, 0.0, 0.0, 1.0");
  broken = broken.substr(0, broken.find("rate_hz"));
  ASSERT_TRUE(ale::test::write_file(yaml, broken));
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kCorruptData, yaml + ":8:"));

  ASSERT_TRUE(ale::test::write_file(yaml, without("resolution")));
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kNotFound, "resolution"));

  std::remove(yaml.c_str());
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kNotFound, yaml));
}

TEST(ReplayDatasetTest, EquidistantModelIsRead) {
  const std::string dir = ale::test::make_temp_dir("yaml");
  const std::string yaml = dir + "/sensor.yaml";
  std::string text = test::euroc_yaml(16, 8);
  text.replace(text.find("radial-tangential"), 17, "equidistant");
  ASSERT_TRUE(ale::test::write_file(yaml, text));
  const Result<hal::CameraCalibration> c = read_euroc_sensor_yaml(yaml);
  ASSERT_TRUE(c.ok()) << c.status().to_string();
  EXPECT_EQ(c->distortion_model, hal::DistortionModel::kEquidistant);
  EXPECT_EQ(c->distortion[0], -0.25);
}

TEST(ReplayDatasetTest, FrameSizeDiffersFromSensorYaml) {
  const std::string dir = ale::test::make_temp_dir("euroc");
  const std::string cam0 = test::write_euroc(dir, 2, 16, 8);
  ASSERT_TRUE(ale::test::write_file(cam0 + "/sensor.yaml", test::euroc_yaml(752, 480)));
  const std::string first = cam0 + "/data/" + std::to_string(test::fixture_timestamp_ns(0)) + ".png";
  const Status st = open_dataset(dir).status();
  EXPECT_TRUE(fails_naming(st, StatusCode::kCorruptData, first));
  EXPECT_TRUE(fails_naming(st, StatusCode::kCorruptData, "752x480"));
}

TEST(ReplayDatasetTest, GroundTruthErrorsNameTheLine) {
  const std::string dir = ale::test::make_temp_dir("gt");
  const std::string csv = dir + "/data.csv";
  ASSERT_TRUE(ale::test::write_file(csv, "#time(ns),px,py,pz,qw,qx,qy,qz\n10,1,2,3,1,0,0,0\n20,1,2,3,1,0,zero,0\n"));
  EXPECT_TRUE(fails_naming(read_euroc_groundtruth(csv).status(), StatusCode::kCorruptData, csv + ":3:"));
  ASSERT_TRUE(ale::test::write_file(csv, "10,1,2,3,1,0,0,0\n20,1,2,3\n"));
  EXPECT_TRUE(fails_naming(read_euroc_groundtruth(csv).status(), StatusCode::kCorruptData, csv + ":2:"));
  ASSERT_TRUE(ale::test::write_file(csv, "10,1,2,3,1,0,0,0\n20,1,2,3,1,0,0,0\n"));
  const Result<std::vector<GroundTruthState>> gt = read_euroc_groundtruth(csv);
  ASSERT_TRUE(gt.ok());
  EXPECT_EQ(gt->back().timestamp_ns, 20);
  EXPECT_EQ(gt->back().v_wb[0], 0.0);
}

// ---- wheel odometry (mav0/odometry0/) -------------------------------------------------------

TEST(ReplayDatasetTest, OdometryFixtureReads) {
  const std::string dir = ale::test::make_temp_dir("odometry");
  test::write_euroc(dir, 4, 16, 8);
  const std::string folder = test::write_odometry(dir, test::odometry_csv(4), test::odometry_yaml());
  const Result<Dataset> ds = open_dataset(dir);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  ASSERT_TRUE(ds->odometry.has_value());
  const OdometryTrack& o = *ds->odometry;
  EXPECT_EQ(o.list_file, folder + "/data.csv");
  EXPECT_EQ(o.sensor_yaml, folder + "/sensor.yaml");
  EXPECT_EQ(o.rate_hz, 50.0);
  ASSERT_TRUE(o.T_BC.has_value());
  EXPECT_EQ((*o.T_BC)[2], 1.0);
  EXPECT_EQ((*o.T_BC)[3], 0.1);
  EXPECT_EQ((*o.T_BC)[4], -1.0);
  EXPECT_EQ((*o.T_BC)[11], 0.08);
  // 20 ms steps from 40 ms before the first frame to a frame past the fourth (200 ms later).
  ASSERT_EQ(o.rows.size(), 13u);
  EXPECT_EQ(o.rows.front().timestamp_ns, test::fixture_timestamp_ns(0) - 40000000);
  EXPECT_EQ(o.rows.back().timestamp_ns, test::fixture_timestamp_ns(4));
  EXPECT_TRUE(o.rows[3].has_gyro);
  EXPECT_TRUE(o.rows[3].has_wheels);
  EXPECT_EQ(o.rows[3].v_right_mps, 0.2);
  EXPECT_NEAR(o.rows[3].x_m, 0.012, 1e-12);
  // Not asked for: not read.
  DatasetOptions no_odometry;
  no_odometry.odometry = false;
  const Result<Dataset> without = open_dataset(dir, no_odometry);
  ASSERT_TRUE(without.ok()) << without.status().to_string();
  EXPECT_FALSE(without->odometry.has_value());
}

// Columns are found by their names: 4, 5, 6 or 7 of them, in any order; "nan" is a value (the
// consumer refuses it as it would a live MCU's).
TEST(ReplayDatasetTest, OdometryColumnsByName) {
  const std::string dir = ale::test::make_temp_dir("odometry");
  test::write_euroc(dir, 2, 16, 8);
  const std::string yaml = "rate_hz: 20\n";
  test::write_odometry(dir, "#timestamp [ns],x [m],y [m],theta [rad]\n10,1,2,3\n20,1.5,2,nan\n", yaml);
  Result<OdometryTrack> o = read_odometry_folder(dir + "/mav0/odometry0");
  ASSERT_TRUE(o.ok()) << o.status().to_string();
  ASSERT_EQ(o->rows.size(), 2u);
  EXPECT_FALSE(o->rows[0].has_gyro);
  EXPECT_FALSE(o->rows[0].has_wheels);
  EXPECT_EQ(o->rows[1].x_m, 1.5);
  EXPECT_TRUE(std::isnan(o->rows[1].theta_rad));
  EXPECT_FALSE(o->T_BC.has_value());  // the daemon decides what a missing T_BC means

  test::write_odometry(dir, "# timestamp [ns], theta [rad], gyro_z [rad/s], x [m], y [m]\n10,0.5,0.25,1,2\n", yaml);
  o = read_odometry_folder(dir + "/mav0/odometry0");
  ASSERT_TRUE(o.ok()) << o.status().to_string();
  EXPECT_EQ(o->rows[0].theta_rad, 0.5);
  EXPECT_EQ(o->rows[0].x_m, 1.0);
  EXPECT_TRUE(o->rows[0].has_gyro);
  EXPECT_EQ(o->rows[0].gyro_z_rps, 0.25);
  EXPECT_FALSE(o->rows[0].has_wheels);
}

// A file that lies is refused at open, naming the file and line: the replay would otherwise feed
// the SLAM something else than what the robot saw.
TEST(ReplayDatasetTest, OdometryCsvProblemsNameTheLine) {
  const std::string dir = ale::test::make_temp_dir("odometry");
  test::write_euroc(dir, 2, 16, 8);
  const std::string folder = test::write_odometry(dir, "", test::odometry_yaml());
  const std::string csv = folder + "/data.csv";
  const std::string h4 = "#timestamp [ns],x [m],y [m],theta [rad]\n";
  const struct {
    std::string content;
    std::string what;
  } cases[] = {
      {"10,1,2,3\n", ":1: no header"},                                                 // no header
      {"#timestamp [ns],x [m],y [m]\n10,1,2\n", ":1: no column 'theta [rad]'"},      // missing column
      {"#timestamp [ns],x [mm],y [m],theta [rad]\n", ":1: unknown column 'x [mm]'"},  // wrong unit
      {"#timestamp [ns],x [m],y [m],theta [rad],x [m]\n", ":1: column 'x [m]' appears twice"},
      {"#timestamp [ns],x [m],y [m],theta [rad],v_left [m/s]\n", ":1: 'v_left [m/s]' and 'v_right [m/s]'"},
      {h4 + "10,1,2,3\n20,1,2\n", ":3: expected 4 columns as the header on line 1, found 3"},
      {h4 + "10,1,2,3,4\n", ":2: expected 4 columns"},
      {h4 + "10,1,2,3\n20,1,two,3\n", ":3: 'y [m]': 'two' is not a number"},
      {h4 + "10,1,2,3\n2.5e1,1,2,3\n", ":3: timestamp '2.5e1' is not an integer of ns"},
      {h4 + "10,1,2,3\n\n# a comment\n10,1,2,3\n", ":5: timestamp 10 ns is not after 10 ns on line 2"},
      {h4 + "20,1,2,3\n10,1,2,3\n", ":3: timestamp 10 ns is not after 20 ns on line 2"},
      // OdometryTrack promises a row (ale-eval's interpolation reads rows.front()); found by
      // tests/fuzz/dataset_fuzz.cpp
      {h4, ":1: a header and no rows"},
      {"\n" + h4 + "\n# a comment\n", ":2: a header and no rows"},
  };
  for (const auto& c : cases) {
    ASSERT_TRUE(ale::test::write_file(csv, c.content));
    EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kCorruptData, csv + c.what)) << c.content;
  }
  // --no-odometry (DatasetOptions::odometry false) still opens the dataset.
  DatasetOptions no_odometry;
  no_odometry.odometry = false;
  EXPECT_TRUE(open_dataset(dir, no_odometry).ok());
}

TEST(ReplayDatasetTest, OdometrySensorYamlProblems) {
  const std::string dir = ale::test::make_temp_dir("odometry");
  test::write_euroc(dir, 2, 16, 8);
  const std::string folder = test::write_odometry(dir, test::odometry_csv(2), "");
  const std::string yaml = folder + "/sensor.yaml";
  EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kNotFound, yaml + ": no such file"));
  const struct {
    std::string content;
    std::string what;
  } cases[] = {
      {"rate_hz: fast\n", ":1: 'rate_hz': 'fast' is not a number"},
      {"rate_hz: -5\n", ":1: rate_hz must be positive"},
      {"T_BC:\n  rows: 4\n", ":1: 'T_BC' has no 'data'"},
      {"T_BC:\n  rows: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n", ":1: 'T_BC' must be 4x4"},
      {"T_BC:\n  data: [1, 0, 0, 0, 1, 0]\n", ":2: 'T_BC.data' must be a list of 16 numbers"},
      {"T_BC:\n  data: [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, one]\n", ":2: 'T_BC.data': 'one' is not"},
  };
  for (const auto& c : cases) {
    ASSERT_TRUE(ale::test::write_file(yaml, c.content));
    EXPECT_TRUE(fails_naming(open_dataset(dir).status(), StatusCode::kCorruptData, yaml + c.what)) << c.content;
  }
  // Unknown keys are ignored; T_BC may be missing (nullopt).
  ASSERT_TRUE(ale::test::write_file(yaml, "sensor_type: odometry\nwheel_base_m: 0.23\n"));
  const Result<Dataset> ds = open_dataset(dir);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  EXPECT_FALSE(ds->odometry->T_BC.has_value());
  EXPECT_EQ(ds->odometry->rate_hz, 0.0);
}

// The writer's layout is the reader's: sensor.yaml comes back exactly (the real V1_01 lens), the
// list in order; time going back, a second list in one folder and an unusable root are errors.
TEST(EurocWriterTest, WritesWhatOpenDatasetReadsBack) {
  ALE_REQUIRE_DATA(yaml, "euroc_v101_micro/mav0/cam0/sensor.yaml");
  const Result<hal::CameraCalibration> lens = read_euroc_sensor_yaml(yaml);
  ASSERT_TRUE(lens.ok()) << lens.status().to_string();
  const std::string root = ale::test::make_temp_dir("euroc-writer") + "/seq";
  Result<EurocWriter> w = EurocWriter::create(root);
  ASSERT_TRUE(w.ok()) << w.status().to_string();
  ASSERT_TRUE(w->write_calibration(*lens).ok());
  GrayImage frame(lens->width, lens->height, 90);
  for (std::int64_t t : {1403715273262142976LL, 1403715273312143104LL}) {
    ASSERT_TRUE(io::write_png(w->frame_path(t), frame.view()).ok());
    ASSERT_TRUE(w->append(t).ok());
  }
  const Status back = w->append(1403715273262142976LL);
  EXPECT_EQ(back.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(back.message().find("does not follow"), std::string::npos) << back.message();
  ASSERT_TRUE(w->close().ok());

  const Result<Dataset> ds = open_dataset(root);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  ASSERT_EQ(ds->frames.size(), 2u);
  EXPECT_EQ(ds->frames[1].timestamp_ns, 1403715273312143104LL);
  ASSERT_TRUE(ds->calibration.has_value());
  const hal::CameraCalibration& c = *ds->calibration;
  EXPECT_EQ(c.width, lens->width);
  EXPECT_EQ(c.height, lens->height);
  EXPECT_EQ(c.fx, lens->fx);
  EXPECT_EQ(c.cy, lens->cy);
  EXPECT_EQ(c.distortion_model, lens->distortion_model);
  EXPECT_EQ(c.distortion, lens->distortion);
  EXPECT_EQ(c.T_BS, lens->T_BS);
  EXPECT_EQ(c.rate_hz, lens->rate_hz);

  EXPECT_TRUE(fails_naming(EurocWriter::create(root).status(), StatusCode::kIoError, root + "/mav0/cam0/data.csv"));
  ASSERT_TRUE(ale::test::write_file(root + "-file", "x"));
  EXPECT_TRUE(fails_naming(EurocWriter::create(root + "-file/seq").status(), StatusCode::kIoError, root + "-file/seq"));
}

// The odometry writer: sensor.yaml at once (a folder without data.csv is no odometry), data.csv
// with the first row's columns; time going back and other columns are refused, nothing written;
// an unusable root names the folder.
TEST(OdometryWriterTest, WritesWhatTheReaderReadsBack) {
  const std::string root = ale::test::make_temp_dir("odometry-writer") + "/seq";
  const std::array<double, 16> T_BC = {0, 0, 1, 0.15, -1, 0, 0, 0, 0, -1, 0, 0.09, 0, 0, 0, 1};
  Result<OdometryWriter> w = OdometryWriter::create(root, T_BC, 0);
  ASSERT_TRUE(w.ok()) << w.status().to_string();
  EXPECT_EQ(w->folder(), root + "/mav0/odometry0");
  EXPECT_TRUE(std::filesystem::is_regular_file(w->folder() + "/sensor.yaml"));
  EXPECT_FALSE(std::filesystem::is_regular_file(w->folder() + "/data.csv"));
  OdometryRow r;
  r.timestamp_ns = 1000;
  r.x_m = 0.1;
  r.y_m = -1.0 / 3.0;
  r.theta_rad = 1e-300;
  r.has_gyro = true;
  r.gyro_z_rps = 0.7;
  ASSERT_TRUE(w->append(r).ok());
  OdometryRow same = r;
  EXPECT_TRUE(fails_naming(w->append(same), StatusCode::kInvalidArgument, "does not follow"));
  OdometryRow wheels = r;
  wheels.timestamp_ns = 2000;
  wheels.has_wheels = true;
  EXPECT_TRUE(fails_naming(w->append(wheels), StatusCode::kInvalidArgument, "has wheel speeds, unlike"));
  OdometryRow next = r;
  next.timestamp_ns = 3000;
  next.x_m = 0.30000000000000004;
  ASSERT_TRUE(w->append(next).ok());
  ASSERT_TRUE(w->close().ok());
  const Result<OdometryTrack> track = read_odometry_folder(w->folder());
  ASSERT_TRUE(track.ok()) << track.status().to_string();
  ASSERT_EQ(track->rows.size(), 2u);
  EXPECT_EQ(track->rows[0].y_m, r.y_m);
  EXPECT_EQ(track->rows[0].theta_rad, r.theta_rad);
  EXPECT_TRUE(track->rows[0].has_gyro);
  EXPECT_FALSE(track->rows[0].has_wheels);
  EXPECT_EQ(track->rows[0].gyro_z_rps, 0.7);
  EXPECT_EQ(track->rows[1].x_m, 0.30000000000000004);
  EXPECT_EQ(track->rate_hz, 0.0);
  ASSERT_TRUE(track->T_BC.has_value());
  EXPECT_EQ(*track->T_BC, T_BC);
  EXPECT_EQ(w->text_bytes(), std::filesystem::file_size(w->folder() + "/data.csv") +
                                 std::filesystem::file_size(w->folder() + "/sensor.yaml"));

  ASSERT_TRUE(ale::test::write_file(root + "-file", "x"));
  EXPECT_TRUE(fails_naming(OdometryWriter::create(root + "-file/seq", T_BC, 50).status(), StatusCode::kIoError,
                           root + "-file/seq/mav0/odometry0"));
}

}  // namespace
}  // namespace ale::replay
