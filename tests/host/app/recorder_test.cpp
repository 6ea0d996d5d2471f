// The recorder: EuRoC sequences that the replay reads back unchanged (frames and wheel odometry),
// one per start and camera session, the cap dropping the oldest first, and every way writing can
// fail stopping recording only (the frame loop's side is in frame_loop_test.cpp).
#include "app/daemon/recorder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <thread>
#include <mutex>
#include <string>
#include <vector>

#include "core/io/image_io.h"
#include "hal/replay/dataset.h"
#include "tests/host/support/test_data.h"

namespace ale::app {
namespace {

namespace fs = std::filesystem;

// Noise (an LCG), so the PNGs are about the raw size and the cap arithmetic is predictable.
GrayImage noise_frame(int w, int h, int index) {
  GrayImage img(w, h);
  std::uint32_t x = 2654435761u * static_cast<std::uint32_t>(index + 1);
  for (std::uint8_t& p : img.pixels) {
    x = x * 1664525u + 1013904223u;
    p = static_cast<std::uint8_t>(x >> 24);
  }
  return img;
}

std::int64_t stamp(int i) { return 1000000000LL + 50000000LL * i; }

hal::Frame frame_of(const GrayImage& img, int i) {
  hal::Frame f;
  f.image = img.view();
  f.timestamp_ns = stamp(i);
  f.sequence = static_cast<std::uint64_t>(i);
  return f;
}

hal::CameraCalibration lens() {
  hal::CameraCalibration c;
  c.fx = 50.123456789012345;
  c.fy = 49.9;
  c.cx = 31.5;
  c.cy = 23.25;
  c.distortion_model = hal::DistortionModel::kRadialTangential;
  c.distortion = {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05};
  c.T_BS = {0.0148655429818, -0.999880929698, 0.00414029679422, -0.0216401454975, 0.999557249008, 0.0149672133247,
            0.025715529948, -0.064676986768, -0.0257744366974, 0.00375618835797, 0.999660727178, 0.00981073058949,
            0, 0, 0, 1};
  c.rate_hz = 30;
  return c;  // width/height 0: the frames give them
}

RecorderOptions options_for(const std::string& dir) {
  RecorderOptions o;
  o.dir = dir;
  o.queue_frames = 4;
  o.wait_when_full = true;
  return o;
}

// The sequence folders under dir, oldest first.
std::vector<std::string> sequences(const std::string& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.is_directory() && e.path().filename().string().size() > 7 && e.path().filename().string()[6] == '_')
      out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}

bool has_event(const std::vector<RecorderEvent>& events, LogLevel level, const std::string& text) {
  for (const RecorderEvent& e : events)
    if (e.level == level && e.message.find(text) != std::string::npos) return true;
  return false;
}

// Records frames [first, first + n) of the noise sequence as one session.
void record(Recorder& r, int first, int n, std::vector<GrayImage>* kept = nullptr) {
  r.new_sequence(lens());
  for (int i = first; i < first + n; ++i) {
    const GrayImage img = noise_frame(64, 48, i);
    r.submit(frame_of(img, i));
    if (kept != nullptr) kept->push_back(img);
  }
}

// A daemon run of one camera session: start, n frames, finish.
RecorderStats one_session(Recorder& r, int n) {
  r.start();
  record(r, 0, n);
  r.finish();
  return r.stats();
}

// A PNG writer whose disk is full after `frames` files; `calls` counts the attempts.
FrameFileWriter disk_fills_after(int frames, int& calls) {
  return [frames, &calls](const std::string& path, GrayView image) {
    if (++calls > frames) return io_error(path + ": cannot write PNG: Write Error (No space left on device)");
    return io::write_png(path, image);
  };
}

std::uint64_t png_bytes_of_one_frame() {
  const std::string dir = test::make_temp_dir("recorder-size");
  EXPECT_TRUE(io::write_png(dir + "/f.png", noise_frame(64, 48, 0).view(), io::PngWriteOptions{1, false}).ok());
  return fs::file_size(dir + "/f.png");
}

TEST(RecorderTest, WritesAEurocSequenceTheReplayReadsBackUnchanged) {
  const std::string dir = test::make_temp_dir("recorder") + "/rec";  // made by the recorder
  Recorder r(options_for(dir));
  r.start();
  std::vector<GrayImage> sent;
  record(r, 0, 12, &sent);
  r.finish();
  const RecorderStats st = r.stats();
  EXPECT_EQ(st.state, hal::RecorderState::kRecording);
  EXPECT_EQ(st.frames_recorded, 12u);
  EXPECT_EQ(st.frames_not_recorded, 0u);
  EXPECT_EQ(st.write.count, 12u);
  EXPECT_EQ(st.submit.count, 12u);
  const std::vector<std::string> seqs = sequences(dir);
  ASSERT_EQ(seqs.size(), 1u);
  EXPECT_EQ(st.sequence, seqs[0]);
  EXPECT_EQ(fs::path(seqs[0]).filename().string().rfind("000001_", 0), 0u) << seqs[0];
  EXPECT_TRUE(has_event(r.take_events(), LogLevel::kInfo, "recording to " + seqs[0]));

  Result<replay::Dataset> ds = replay::open_dataset(seqs[0]);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  EXPECT_EQ(ds->format, replay::DatasetFormat::kEuroc);
  ASSERT_EQ(ds->frames.size(), 12u);
  for (int i = 0; i < 12; ++i) {
    EXPECT_EQ(ds->frames[static_cast<std::size_t>(i)].timestamp_ns, stamp(i));
    GrayImage back;
    ASSERT_TRUE(io::read_gray(ds->frames[static_cast<std::size_t>(i)].path, back).ok());
    EXPECT_EQ(back.pixels, sent[static_cast<std::size_t>(i)].pixels) << "frame " << i;
  }
  // sensor.yaml: the lens exactly, the size from the frames.
  ASSERT_TRUE(ds->calibration.has_value());
  const hal::CameraCalibration& c = *ds->calibration;
  const hal::CameraCalibration want = lens();
  EXPECT_EQ(c.width, 64);
  EXPECT_EQ(c.height, 48);
  EXPECT_EQ(c.fx, want.fx);
  EXPECT_EQ(c.fy, want.fy);
  EXPECT_EQ(c.cx, want.cx);
  EXPECT_EQ(c.cy, want.cy);
  EXPECT_EQ(c.distortion_model, want.distortion_model);
  EXPECT_EQ(c.distortion, want.distortion);
  EXPECT_EQ(c.T_BS, want.T_BS);
  EXPECT_EQ(c.rate_hz, want.rate_hz);
  // The cap's measure is what the folder holds.
  std::uint64_t on_disk = 0;
  for (const auto& e : fs::recursive_directory_iterator(seqs[0]))
    if (e.is_regular_file()) on_disk += e.file_size();
  EXPECT_EQ(st.bytes, on_disk);
}

// No lens (fx 0): the frames are recorded, no sensor.yaml is written, and an event says why.
TEST(RecorderTest, NoLensNoSensorYamlAndAWarningSayingWhy) {
  const std::string dir = test::make_temp_dir("recorder") + "/rec";
  Recorder r(options_for(dir));
  r.start();
  r.new_sequence(hal::CameraCalibration{});
  for (int i = 0; i < 3; ++i) {
    const GrayImage img = noise_frame(64, 48, i);
    r.submit(frame_of(img, i));
  }
  r.finish();
  EXPECT_EQ(r.stats().frames_recorded, 3u);
  const std::vector<std::string> seqs = sequences(dir);
  ASSERT_EQ(seqs.size(), 1u);
  EXPECT_FALSE(fs::exists(seqs[0] + "/mav0/cam0/sensor.yaml"));
  EXPECT_TRUE(fs::exists(seqs[0] + "/mav0/cam0/data.csv"));
  EXPECT_TRUE(has_event(r.take_events(), LogLevel::kWarning, seqs[0] + " gets no sensor.yaml: no lens was given (fx 0)"));
}

TEST(RecorderTest, OneSequencePerCameraSessionAndPerStart) {
  const std::string dir = test::make_temp_dir("recorder");
  {
    Recorder r(options_for(dir));
    r.start();
    record(r, 0, 3);
    record(r, 3, 3);  // the camera was reopened
  }  // the destructor finishes
  {
    Recorder r(options_for(dir));  // the daemon started again
    r.start();
    record(r, 6, 2);
    r.finish();
    EXPECT_EQ(r.stats().frames_recorded, 2u);
  }
  const std::vector<std::string> seqs = sequences(dir);
  ASSERT_EQ(seqs.size(), 3u);
  const std::size_t want[] = {3, 3, 2};
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(fs::path(seqs[i]).filename().string().rfind("00000" + std::to_string(i + 1) + "_", 0), 0u) << seqs[i];
    Result<replay::Dataset> ds = replay::open_dataset(seqs[i]);
    ASSERT_TRUE(ds.ok()) << ds.status().to_string();
    EXPECT_EQ(ds->frames.size(), want[i]) << seqs[i];
  }
}

TEST(RecorderTest, TheCapDropsTheOldestSequenceFirstAndNothingElse) {
  const std::string dir = test::make_temp_dir("recorder");
  ASSERT_TRUE(test::write_file(dir + "/keep-me/notes.txt", "not a recording"));
  ASSERT_TRUE(test::write_file(dir + "/12/short-number.txt", "not a recording either"));
  const std::uint64_t frame = png_bytes_of_one_frame();
  RecorderOptions o = options_for(dir);
  // Room for about two and a half sequences of five frames (with their data.csv and sensor.yaml).
  o.max_bytes = 13 * frame;
  Recorder r(o);
  r.start();
  record(r, 0, 5);
  record(r, 5, 5);
  record(r, 10, 5);
  r.finish();
  const RecorderStats st = r.stats();
  EXPECT_EQ(st.state, hal::RecorderState::kRecording);
  EXPECT_EQ(st.frames_recorded, 15u);
  EXPECT_EQ(st.sequences_dropped, 1u);
  EXPECT_LE(st.bytes, o.max_bytes);
  const std::vector<std::string> seqs = sequences(dir);
  ASSERT_EQ(seqs.size(), 2u);
  EXPECT_EQ(fs::path(seqs[0]).filename().string().rfind("000002_", 0), 0u) << seqs[0];
  EXPECT_EQ(fs::path(seqs[1]).filename().string().rfind("000003_", 0), 0u) << seqs[1];
  for (const std::string& s : seqs) {
    Result<replay::Dataset> ds = replay::open_dataset(s);
    ASSERT_TRUE(ds.ok()) << ds.status().to_string();
    EXPECT_EQ(ds->frames.size(), 5u);
  }
  EXPECT_TRUE(has_event(r.take_events(), LogLevel::kInfo, "dropped the oldest sequence " + dir + "/000001_"));
  EXPECT_TRUE(fs::exists(dir + "/keep-me/notes.txt"));
  EXPECT_TRUE(fs::exists(dir + "/12/short-number.txt"));

  // A later start counts what is there: its first frames drop sequence 2, then 3 goes too.
  RecorderOptions o2 = o;
  o2.max_bytes = 7 * frame;
  Recorder again(o2);
  again.start();
  record(again, 15, 4);
  again.finish();
  const std::vector<std::string> left = sequences(dir);
  ASSERT_EQ(left.size(), 1u);
  EXPECT_EQ(fs::path(left[0]).filename().string().rfind("000004_", 0), 0u) << left[0];
  EXPECT_EQ(again.stats().sequences_dropped, 2u);
  EXPECT_EQ(again.stats().frames_recorded, 4u);
}

TEST(RecorderTest, ASequenceAloneAtTheCapStopsRecording) {
  const std::string dir = test::make_temp_dir("recorder");
  RecorderOptions o = options_for(dir);
  o.max_bytes = 3 * png_bytes_of_one_frame();
  Recorder r(o);
  const RecorderStats st = one_session(r, 10);
  EXPECT_EQ(st.state, hal::RecorderState::kStopped);
  EXPECT_GE(st.frames_recorded, 1u);
  EXPECT_LT(st.frames_recorded, 3u);
  EXPECT_EQ(st.frames_recorded + st.frames_not_recorded, 10u);
  EXPECT_LE(st.bytes, o.max_bytes);
  EXPECT_TRUE(has_event(r.take_events(), LogLevel::kWarning, "alone fills recorder.max_mb"));
  const std::vector<std::string> seqs = sequences(dir);
  ASSERT_EQ(seqs.size(), 1u);
  Result<replay::Dataset> ds = replay::open_dataset(seqs[0]);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  EXPECT_EQ(ds->frames.size(), st.frames_recorded);
}

TEST(RecorderTest, AWriteErrorStopsRecordingAndLeavesAReadableSequence) {
  const std::string dir = test::make_temp_dir("recorder");
  int calls = 0;
  Recorder r(options_for(dir), disk_fills_after(4, calls));
  const RecorderStats st = one_session(r, 10);
  EXPECT_EQ(st.state, hal::RecorderState::kStopped);
  EXPECT_EQ(st.frames_recorded, 4u);
  EXPECT_EQ(st.frames_not_recorded, 6u);
  EXPECT_EQ(calls, 5) << "nothing is written after the error";
  const std::vector<RecorderEvent> events = r.take_events();
  EXPECT_TRUE(has_event(events, LogLevel::kError, "No space left on device")) << events.size();
  EXPECT_TRUE(has_event(events, LogLevel::kError, "recording stops, tracking goes on"));
  const std::vector<std::string> seqs = sequences(dir);
  ASSERT_EQ(seqs.size(), 1u);
  Result<replay::Dataset> ds = replay::open_dataset(seqs[0]);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  EXPECT_EQ(ds->frames.size(), 4u);
}

TEST(RecorderTest, AnUnusableFolderIsAnErrorNotACrash) {
  const std::string base = test::make_temp_dir("recorder");
  ASSERT_TRUE(test::write_file(base + "/a-file", "x"));
  const std::string dir = base + "/a-file/rec";  // below a regular file: even root cannot make it
  Recorder r(options_for(dir));
  const RecorderStats st = one_session(r, 3);
  EXPECT_EQ(st.state, hal::RecorderState::kStopped);
  EXPECT_EQ(st.frames_recorded, 0u);
  EXPECT_EQ(st.frames_not_recorded, 3u);
  EXPECT_TRUE(has_event(r.take_events(), LogLevel::kError, "recorder.dir " + dir));
}

// A live camera's frames never wait: with the writer stuck, the queue's buffers fill and every
// further frame is left out (counted), whatever the threads' timing.
TEST(RecorderTest, ALiveCameraNeverWaitsForTheWriter) {
  const std::string dir = test::make_temp_dir("recorder");
  std::mutex m;
  std::condition_variable cv;
  bool release = false;
  FrameFileWriter stuck = [&](const std::string& path, GrayView image) {
    std::unique_lock<std::mutex> lock(m);
    cv.wait(lock, [&] { return release; });
    return io::write_png(path, image);
  };
  RecorderOptions o = options_for(dir);
  o.wait_when_full = false;
  o.queue_frames = 4;
  Recorder r(o, stuck);
  r.start();
  record(r, 0, 20);
  EXPECT_EQ(r.stats().frames_not_recorded, 16u) << "four buffers, all queued or being written";
  {
    std::lock_guard<std::mutex> lock(m);
    release = true;
  }
  cv.notify_all();
  r.finish();
  EXPECT_EQ(r.stats().frames_recorded, 4u);
  EXPECT_EQ(r.stats().frames_not_recorded, 16u);
  EXPECT_EQ(r.stats().waited.count, 0u);
}


// --- Wheel odometry ---

OdometrySensor odometry_sensor() {
  OdometrySensor o;
  o.T_bc = {0.0, 0.0, 1.0, 0.1234567890123,  -1.0, 0.0, 0.0, 0.01,  0.0, -1.0, 0.0, 0.0871,  0.0, 0.0, 0.0, 1.0};
  o.rate_hz = 50;
  return o;
}

RecorderOptions odometry_options_for(const std::string& dir) {
  RecorderOptions o = options_for(dir);
  o.odometry = odometry_sensor();
  return o;
}

// Sample i at 20 ms steps from 0.98 s (one before the first frame), values that need all 17 digits.
slam::OdometrySample sample(int i, bool gyro = true, bool wheels = true) {
  slam::OdometrySample s;
  s.t_ns = 980000000LL + 20000000LL * i;
  s.sequence = static_cast<std::uint32_t>(1000 + i);
  s.x_m = 0.1 * i + 1.0 / 3.0;
  s.y_m = -0.2 * i / 7.0;
  s.theta_rad = 0.01 * i * i - 1e-9;
  s.has_gyro = gyro;
  s.gyro_z_rps = gyro ? 0.3 + i / 11.0 : 0.0;
  s.has_wheels = wheels;
  s.v_left_mps = wheels ? 0.25 - i / 13.0 : 0.0;
  s.v_right_mps = wheels ? 0.27 + i * 1e-7 : 0.0;
  return s;
}

void expect_row(const replay::OdometryRow& r, const slam::OdometrySample& s) {
  EXPECT_EQ(r.timestamp_ns, s.t_ns);
  EXPECT_EQ(r.x_m, s.x_m);
  EXPECT_EQ(r.y_m, s.y_m);
  EXPECT_EQ(r.theta_rad, s.theta_rad);
  EXPECT_EQ(r.has_gyro, s.has_gyro);
  EXPECT_EQ(r.has_wheels, s.has_wheels);
  if (s.has_gyro) {
    EXPECT_EQ(r.gyro_z_rps, s.gyro_z_rps);
  }
  if (s.has_wheels) {
    EXPECT_EQ(r.v_left_mps, s.v_left_mps);
    EXPECT_EQ(r.v_right_mps, s.v_right_mps);
  }
}

std::string first_line(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

std::uint64_t bytes_on_disk(const std::string& folder) {
  std::uint64_t on_disk = 0;
  for (const auto& e : fs::recursive_directory_iterator(folder))
    if (e.is_regular_file()) on_disk += e.file_size();
  return on_disk;
}

// Frames and samples interleaved as the frame loop hands them over; the replay reads back every
// sample exactly (all 17 digits, the MCU's clock), T_BC and rate_hz from odometry0/sensor.yaml.
TEST(RecorderTest, OdometrySamplesAreListedAndReadBackExactly) {
  const std::string dir = test::make_temp_dir("recorder") + "/rec";
  Recorder r(odometry_options_for(dir));
  r.start();
  r.new_sequence(lens());
  std::vector<slam::OdometrySample> sent;
  r.submit_odometry({sample(0), sample(1)});  // before the first frame: they wait for it
  sent.push_back(sample(0));
  sent.push_back(sample(1));
  for (int i = 0; i < 6; ++i) {
    const GrayImage img = noise_frame(64, 48, i);
    r.submit(frame_of(img, i));
    const std::vector<slam::OdometrySample> batch = {sample(2 + 2 * i), sample(3 + 2 * i)};
    r.submit_odometry(batch);
    sent.insert(sent.end(), batch.begin(), batch.end());
  }
  slam::OdometrySample glitch = sample(14);
  glitch.x_m = std::numeric_limits<double>::quiet_NaN();  // kept for the core to refuse, as live
  glitch.v_right_mps = -std::numeric_limits<double>::infinity();
  r.submit_odometry({glitch});
  r.finish();
  const RecorderStats st = r.stats();
  EXPECT_EQ(st.odometry_recorded, 15u);
  EXPECT_EQ(st.odometry_not_recorded, 0u);
  EXPECT_EQ(st.frames_recorded, 6u);
  const std::vector<std::string> seqs = sequences(dir);
  ASSERT_EQ(seqs.size(), 1u);
  const std::string odometry0 = seqs[0] + "/mav0/odometry0";
  EXPECT_EQ(first_line(odometry0 + "/data.csv"),
            "#timestamp [ns],x [m],y [m],theta [rad],gyro_z [rad/s],v_left [m/s],v_right [m/s]");
  Result<replay::Dataset> ds = replay::open_dataset(seqs[0]);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  EXPECT_EQ(ds->frames.size(), 6u);
  ASSERT_TRUE(ds->odometry.has_value());
  const replay::OdometryTrack& track = *ds->odometry;
  ASSERT_EQ(track.rows.size(), 15u);
  for (std::size_t i = 0; i < sent.size(); ++i) {
    SCOPED_TRACE("row " + std::to_string(i));
    expect_row(track.rows[i], sent[i]);
  }
  EXPECT_TRUE(std::isnan(track.rows[14].x_m));
  EXPECT_EQ(track.rows[14].v_right_mps, -std::numeric_limits<double>::infinity());
  EXPECT_EQ(track.rate_hz, 50.0);
  ASSERT_TRUE(track.T_BC.has_value());
  EXPECT_EQ(*track.T_BC, odometry_sensor().T_bc);
  EXPECT_EQ(st.bytes, bytes_on_disk(seqs[0]));
}

// The columns are the first sample's: 4 without gyro and wheel speeds. A sample with other
// columns, or a timestamp not after the last row's, is left out, counted and told once.
TEST(RecorderTest, OdometryColumnsFollowTheFirstSampleAndOddSamplesAreCounted) {
  const std::string dir = test::make_temp_dir("recorder");
  RecorderOptions o = odometry_options_for(dir);
  o.odometry->rate_hz = 0;  // not known: no rate_hz key
  Recorder r(o);
  r.start();
  record(r, 0, 1);
  r.submit_odometry({sample(1, false, false), sample(2, true, false), sample(3, false, false), sample(3, false, false),
                     sample(4, false, true), sample(5, false, false)});
  r.finish();
  EXPECT_EQ(r.stats().odometry_recorded, 3u);
  EXPECT_EQ(r.stats().odometry_not_recorded, 3u);
  const std::vector<RecorderEvent> events = r.take_events();
  EXPECT_TRUE(has_event(events, LogLevel::kWarning, "has gyro_z, unlike the file's columns"));
  EXPECT_EQ(std::count_if(events.begin(), events.end(), [](const RecorderEvent& e) { return e.level == LogLevel::kWarning; }), 1);
  const std::vector<std::string> seqs = sequences(dir);
  ASSERT_EQ(seqs.size(), 1u);
  EXPECT_EQ(first_line(seqs[0] + "/mav0/odometry0/data.csv"), "#timestamp [ns],x [m],y [m],theta [rad]");
  std::ifstream yaml(seqs[0] + "/mav0/odometry0/sensor.yaml");
  std::stringstream text;
  text << yaml.rdbuf();
  EXPECT_EQ(text.str().find("rate_hz"), std::string::npos) << text.str();
  Result<replay::Dataset> ds = replay::open_dataset(seqs[0]);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  ASSERT_TRUE(ds->odometry.has_value());
  ASSERT_EQ(ds->odometry->rows.size(), 3u);
  expect_row(ds->odometry->rows[0], sample(1, false, false));
  expect_row(ds->odometry->rows[1], sample(3, false, false));
  expect_row(ds->odometry->rows[2], sample(5, false, false));
  EXPECT_EQ(ds->odometry->rate_hz, 0.0);
}

// A sample goes to the sequence of the camera session it arrived in; one of a session that got no
// frame before the end is not recorded. Every sequence gets its odometry0/sensor.yaml at once.
TEST(RecorderTest, OdometrySamplesGoToTheirCameraSessionsSequence) {
  const std::string dir = test::make_temp_dir("recorder");
  Recorder r(odometry_options_for(dir));
  r.start();
  record(r, 0, 2);
  r.submit_odometry({sample(1), sample(2)});
  r.new_sequence(lens());  // the camera was reopened: its samples before its first frame wait for it
  r.submit_odometry({sample(3)});
  const GrayImage img = noise_frame(64, 48, 5);
  r.submit(frame_of(img, 5));
  r.submit_odometry({sample(4)});
  record(r, 6, 1);  // a session with a frame and no samples
  r.new_sequence(lens());  // a session with samples and no frame
  r.submit_odometry({sample(5)});
  r.finish();
  EXPECT_EQ(r.stats().odometry_recorded, 4u);
  EXPECT_EQ(r.stats().odometry_not_recorded, 1u);
  const std::vector<std::string> seqs = sequences(dir);
  ASSERT_EQ(seqs.size(), 3u);
  const std::vector<std::vector<int>> want = {{1, 2}, {3, 4}, {}};
  for (std::size_t i = 0; i < seqs.size(); ++i) {
    SCOPED_TRACE(seqs[i]);
    EXPECT_TRUE(fs::exists(seqs[i] + "/mav0/odometry0/sensor.yaml"));
    Result<replay::Dataset> ds = replay::open_dataset(seqs[i]);
    ASSERT_TRUE(ds.ok()) << ds.status().to_string();
    if (want[i].empty()) {
      EXPECT_FALSE(ds->odometry.has_value()) << "no data.csv without a sample";
      continue;
    }
    ASSERT_TRUE(ds->odometry.has_value());
    ASSERT_EQ(ds->odometry->rows.size(), want[i].size());
    for (std::size_t k = 0; k < want[i].size(); ++k) expect_row(ds->odometry->rows[k], sample(want[i][k]));
  }
}

// Samples wait for a frame at most queue_odometry at a time; the rest are counted. Without an
// odometry sensor nothing is recorded and there is no odometry0/.
TEST(RecorderTest, OdometryBeyondItsBoundOrWithoutASensorIsCounted) {
  const std::string dir = test::make_temp_dir("recorder");
  RecorderOptions o = odometry_options_for(dir + "/bounded");
  o.queue_odometry = 4;
  Recorder r(o);
  r.start();
  r.new_sequence(lens());
  std::vector<slam::OdometrySample> burst;
  for (int i = 0; i < 10; ++i) burst.push_back(sample(i));
  r.submit_odometry(burst);  // no frame yet: all wait
  EXPECT_EQ(r.stats().odometry_not_recorded, 6u);
  const GrayImage img = noise_frame(64, 48, 0);
  r.submit(frame_of(img, 0));
  r.finish();
  EXPECT_EQ(r.stats().odometry_recorded, 4u);
  Result<replay::Dataset> ds = replay::open_dataset(sequences(dir + "/bounded").at(0));
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  ASSERT_TRUE(ds->odometry.has_value());
  ASSERT_EQ(ds->odometry->rows.size(), 4u);
  expect_row(ds->odometry->rows[3], sample(3));

  Recorder plain(options_for(dir + "/plain"));
  plain.start();
  record(plain, 0, 2);
  plain.submit_odometry(burst);
  plain.finish();
  EXPECT_EQ(plain.stats().odometry_recorded, 0u);
  EXPECT_EQ(plain.stats().odometry_not_recorded, 10u);
  EXPECT_FALSE(fs::exists(sequences(dir + "/plain").at(0) + "/mav0/odometry0"));
}

// A sequence cut off is a dataset at every point: read while the recorder still writes it, and
// after a write error stopped recording (the samples after it counted).
TEST(RecorderTest, ASequenceCutOffKeepsItsOdometryReadable) {
  const std::string dir = test::make_temp_dir("recorder");
  int calls = 0;
  Recorder r(odometry_options_for(dir), disk_fills_after(3, calls));
  r.start();
  r.new_sequence(lens());
  for (int i = 0; i < 2; ++i) {
    const GrayImage img = noise_frame(64, 48, i);
    r.submit(frame_of(img, i));
    r.submit_odometry({sample(2 * i), sample(2 * i + 1)});
  }
  // Still open: what the writer has listed so far reads back.
  for (int tries = 0; tries < 2000 && r.stats().odometry_recorded < 4; ++tries)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ASSERT_EQ(r.stats().odometry_recorded, 4u);
  const std::vector<std::string> seqs = sequences(dir);
  ASSERT_EQ(seqs.size(), 1u);
  Result<replay::Dataset> open = replay::open_dataset(seqs[0]);
  ASSERT_TRUE(open.ok()) << open.status().to_string();
  ASSERT_TRUE(open->odometry.has_value());
  EXPECT_EQ(open->odometry->rows.size(), 4u);
  for (int i = 2; i < 6; ++i) {
    const GrayImage img = noise_frame(64, 48, i);
    r.submit(frame_of(img, i));
    r.submit_odometry({sample(2 * i), sample(2 * i + 1)});
  }
  r.finish();
  const RecorderStats st = r.stats();
  EXPECT_EQ(st.state, hal::RecorderState::kStopped);
  EXPECT_EQ(st.frames_recorded, 3u);
  EXPECT_EQ(st.odometry_recorded + st.odometry_not_recorded, 12u);
  EXPECT_GE(st.odometry_recorded, 6u) << "the third frame's samples were queued before the error";
  Result<replay::Dataset> ds = replay::open_dataset(seqs[0]);
  ASSERT_TRUE(ds.ok()) << ds.status().to_string();
  ASSERT_TRUE(ds->odometry.has_value());
  EXPECT_EQ(ds->odometry->rows.size(), st.odometry_recorded);
}

}  // namespace
}  // namespace ale::app
