// The recorder: EuRoC sequences that the replay reads back unchanged, one per start and camera
// session, the cap dropping the oldest first, and every way writing can fail stopping recording
// only (the frame loop's side is in frame_loop_test.cpp).
#include "app/daemon/recorder.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <condition_variable>
#include <cstdint>
#include <filesystem>
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
  FrameFileWriter disk_fills_after_four = [&calls](const std::string& path, GrayView image) {
    if (++calls > 4) return io_error(path + ": cannot write PNG: Write Error (No space left on device)");
    return io::write_png(path, image);
  };
  Recorder r(options_for(dir), disk_fills_after_four);
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

}  // namespace
}  // namespace ale::app
