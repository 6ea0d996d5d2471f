#include "app/daemon/recorder.h"

#include <algorithm>
#include <charconv>
#include <ctime>
#include <filesystem>
#include <system_error>
#include <utility>

#include "app/daemon/odometry_input.h"
#include "core/base/frame_record.h"

namespace ale::app {
namespace {

namespace fs = std::filesystem;

constexpr int kNumberDigits = 6;

// The sequence number of a folder named <digits>[_<anything>] with at least kNumberDigits digits.
std::optional<std::uint64_t> sequence_number(const std::string& name) {
  std::uint64_t n = 0;
  const char* end = name.data() + name.size();
  const auto [stop, ec] = std::from_chars(name.data(), end, n);
  if (ec != std::errc() || stop - name.data() < kNumberDigits) return std::nullopt;
  if (stop != end && *stop != '_') return std::nullopt;
  return n;
}

std::uint64_t folder_bytes(const std::string& path) {
  std::uint64_t bytes = 0;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(path, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code size_ec;
    if (it->is_regular_file(size_ec)) {
      const std::uintmax_t size = it->file_size(size_ec);
      if (!size_ec) bytes += size;
    }
  }
  return bytes;
}

std::string sequence_name(std::uint64_t number) {
  char text[64];
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char when[32];
  std::strftime(when, sizeof when, "%Y%m%dT%H%M%SZ", &utc);
  std::snprintf(text, sizeof text, "%0*llu_%s", kNumberDigits, static_cast<unsigned long long>(number), when);
  return text;
}

std::string mib(std::uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / (1024.0 * 1024.0));
  return text;
}

}  // namespace

void CostFigure::add(std::int64_t ns) {
  ++count;
  total_ns += ns;
  max_ns = std::max(max_ns, ns);
}

Recorder::Recorder(RecorderOptions options, FrameFileWriter writer) : options_(std::move(options)), writer_(std::move(writer)) {
  if (!writer_) {
    const io::PngWriteOptions png = options_.png;
    writer_ = [png](const std::string& path, GrayView image) { return io::write_png(path, image, png); };
  }
  const int n = std::max(options_.queue_frames, 1);
  slots_.resize(static_cast<std::size_t>(n));
  ring_.resize(static_cast<std::size_t>(n));
  for (int i = n - 1; i >= 0; --i) free_.push_back(i);
  odometry_bound_ = static_cast<std::size_t>(std::max(options_.queue_odometry, 1));
  odometry_queue_.reserve(odometry_bound_);
  odometry_taken_.reserve(odometry_bound_);
}

Recorder::~Recorder() { finish(); }

void Recorder::start() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (started_) return;
    started_ = true;
    stats_.state = hal::RecorderState::kRecording;
  }
  thread_ = std::thread([this] { run(); });
}

void Recorder::new_sequence(const hal::CameraCalibration& lens) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++session_;
  lens_ = lens;
}

void Recorder::submit(const hal::Frame& frame) {
  std::int64_t t0 = steady_clock_ns();
  int index = -1;
  std::uint64_t session = 0;
  {
    std::unique_lock<std::mutex> lock(mutex_);
    const auto recording = [this] { return stats_.state == hal::RecorderState::kRecording && !finishing_; };
    if (recording() && free_.empty() && options_.wait_when_full) {
      space_.wait(lock, [&] { return !free_.empty() || !recording(); });
      const std::int64_t now = steady_clock_ns();
      stats_.waited.add(now - t0);
      t0 = now;
    }
    if (!recording() || free_.empty()) {
      ++stats_.frames_not_recorded;
      return;
    }
    index = free_.back();
    free_.pop_back();
    session = session_;
  }
  // The slot is this thread's until it is queued.
  Slot& slot = slots_[static_cast<std::size_t>(index)];
  if (slot.image.width != frame.image.width || slot.image.height != frame.image.height)
    slot.image = GrayImage(frame.image.width, frame.image.height);  // once per size
  copy_pixels(frame.image, slot.image.view());
  slot.timestamp_ns = frame.timestamp_ns;
  slot.session = session;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ring_[(ring_head_ + ring_count_) % ring_.size()] = index;
    ++ring_count_;
    stats_.submit.add(steady_clock_ns() - t0);
  }
  work_.notify_one();
}

void Recorder::submit_odometry(const std::vector<slam::OdometrySample>& samples) {
  if (samples.empty()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool recording = stats_.state == hal::RecorderState::kRecording && !finishing_ && options_.odometry;
    for (const slam::OdometrySample& sample : samples) {
      if (!recording || odometry_held_ >= odometry_bound_) {
        ++stats_.odometry_not_recorded;
        continue;
      }
      odometry_queue_.push_back({sample, session_});
      ++odometry_held_;
    }
  }
  work_.notify_one();
}

std::vector<RecorderEvent> Recorder::take_events() {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<RecorderEvent> out;
  out.swap(events_);
  return out;
}

RecorderStats Recorder::stats() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stats_;
}

void Recorder::counters(hal::StatusReport& status) const {
  std::lock_guard<std::mutex> lock(mutex_);
  status.recorder_state = stats_.state;
  status.frames_recorded = stats_.frames_recorded;
  status.frames_not_recorded = stats_.frames_not_recorded;
}

void Recorder::finish() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    finishing_ = true;
  }
  work_.notify_all();
  space_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void Recorder::event(LogLevel level, std::string message) {
  std::lock_guard<std::mutex> lock(mutex_);
  events_.push_back({level, std::move(message)});
}

void Recorder::stop_recording(LogLevel level, const std::string& why) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.state = hal::RecorderState::kStopped;
  }
  stopped_ = true;
  space_.notify_all();
  if (euroc_) {
    (void)euroc_->close();
    euroc_.reset();
  }
  odometry_writer_.reset();
  event(level, "recorder: " + why + "; recording stops, tracking goes on");
}

std::uint64_t Recorder::total_bytes() const {
  std::uint64_t total = 0;
  for (const Sequence& s : sequences_) total += s.bytes;
  return total;
}

void Recorder::scan() {
  std::error_code ec;
  fs::create_directories(options_.dir, ec);
  if (ec || !fs::is_directory(options_.dir)) {
    stop_recording(LogLevel::kError, "recorder.dir " + options_.dir + ": cannot create: " +
                                         (ec ? ec.message() : std::string("not a directory")));
    return;
  }
  for (fs::directory_iterator it(options_.dir, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code type_ec;
    if (!it->is_directory(type_ec)) continue;
    const std::optional<std::uint64_t> n = sequence_number(it->path().filename().string());
    if (n) sequences_.push_back({*n, it->path().string(), folder_bytes(it->path().string())});
  }
  if (ec) {
    stop_recording(LogLevel::kError, "recorder.dir " + options_.dir + ": cannot list: " + ec.message());
    return;
  }
  std::sort(sequences_.begin(), sequences_.end(), [](const Sequence& a, const Sequence& b) { return a.number < b.number; });
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.bytes = total_bytes();
}

bool Recorder::open_sequence(std::uint64_t session, int width, int height) {
  if (euroc_) {
    (void)euroc_->close();
    euroc_.reset();
  }
  if (odometry_writer_) {
    (void)odometry_writer_->close();
    odometry_writer_.reset();
  }
  std::optional<hal::CameraCalibration> lens;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    lens = lens_;
  }
  const std::uint64_t number = sequences_.empty() ? 1 : sequences_.back().number + 1;
  const std::string path = options_.dir + "/" + sequence_name(number);
  Result<replay::EurocWriter> created = replay::EurocWriter::create(path);
  if (!created.ok()) {
    stop_recording(LogLevel::kError, created.status().to_string());
    return false;
  }
  replay::EurocWriter writer = std::move(*created);
  if (lens && lens->fx > 0.0) {
    hal::CameraCalibration c = *lens;
    if (c.width <= 0 || c.height <= 0) {
      c.width = width;
      c.height = height;
    }
    if (Status s = writer.write_calibration(c); !s.ok()) {
      stop_recording(LogLevel::kError, s.to_string());
      return false;
    }
  } else {
    // A sensor.yaml with fx 0 would be refused by every reader (the daemon's, ale-calibrate's).
    event(LogLevel::kWarning, "recorder: " + path + " gets no sensor.yaml: no lens was given (fx 0); "
                              "replay it with --set camera.calibration_file=FILE");
  }
  // Before any sample's row: a data.csv without its sensor.yaml would make the whole sequence
  // unreadable.
  std::optional<replay::OdometryWriter> odometry;
  if (options_.odometry) {
    Result<replay::OdometryWriter> made =
        replay::OdometryWriter::create(path, options_.odometry->T_bc, options_.odometry->rate_hz);
    if (!made.ok()) {
      stop_recording(LogLevel::kError, made.status().to_string());
      return false;
    }
    odometry = std::move(*made);
  }
  sequences_.push_back({number, path, writer.text_bytes() + (odometry ? odometry->text_bytes() : 0)});
  euroc_ = std::move(writer);
  odometry_writer_ = std::move(odometry);
  odometry_warned_ = false;
  writing_session_ = session;
  last_t_ns_.reset();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stats_.sequence = path;
    stats_.bytes = total_bytes();
  }
  event(LogLevel::kInfo, "recorder: recording to " + path);
  return true;
}

bool Recorder::make_room(std::uint64_t needed) {
  while (total_bytes() + needed > options_.max_bytes) {
    if (sequences_.size() <= 1) {
      stop_recording(LogLevel::kWarning, "the sequence " + sequences_.back().path + " alone fills recorder.max_mb (" +
                                             mib(options_.max_bytes) + ")");
      return false;
    }
    const Sequence oldest = sequences_.front();
    std::error_code ec;
    fs::remove_all(oldest.path, ec);
    if (ec) {
      stop_recording(LogLevel::kError, "cannot delete the oldest sequence " + oldest.path + ": " + ec.message());
      return false;
    }
    sequences_.erase(sequences_.begin());
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ++stats_.sequences_dropped;
      stats_.bytes = total_bytes();
    }
    event(LogLevel::kInfo, "recorder: dropped the oldest sequence " + oldest.path + " (" + mib(oldest.bytes) +
                               ") to stay within recorder.max_mb");
  }
  return true;
}

bool Recorder::write(Slot& slot) {
  if (!euroc_ || slot.session != writing_session_) {
    if (!open_sequence(slot.session, slot.image.width, slot.image.height)) return false;
  }
  // A timestamp that does not increase would overwrite a frame's file (and a replay refuses it).
  if (last_t_ns_ && slot.timestamp_ns <= *last_t_ns_) return false;
  const std::uint64_t estimate =
      last_frame_bytes_ > 0 ? last_frame_bytes_ : static_cast<std::uint64_t>(slot.image.pixels.size());
  if (!make_room(estimate)) return false;
  const std::string path = euroc_->frame_path(slot.timestamp_ns);
  if (Status s = writer_(path, slot.image.view()); !s.ok()) {
    stop_recording(LogLevel::kError, s.to_string());
    return false;
  }
  std::error_code ec;
  const std::uint64_t size = fs::file_size(path, ec);
  const std::uint64_t text_before = euroc_->text_bytes();
  if (Status s = euroc_->append(slot.timestamp_ns); !s.ok()) {
    fs::remove(path, ec);
    stop_recording(LogLevel::kError, s.to_string());
    return false;
  }
  last_t_ns_ = slot.timestamp_ns;
  if (size > 0) last_frame_bytes_ = size;
  sequences_.back().bytes += size + (euroc_->text_bytes() - text_before);
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.bytes = total_bytes();
  return true;
}

bool Recorder::write_row(const slam::OdometrySample& sample) {
  const std::uint64_t before = odometry_writer_->text_bytes();
  const Status s = odometry_writer_->append(odometry_row(sample));
  if (s.code() == StatusCode::kInvalidArgument) {
    if (!odometry_warned_)
      event(LogLevel::kWarning, "recorder: " + s.message() + "; not recorded (told once per sequence)");
    odometry_warned_ = true;
    return false;
  }
  if (!s.ok()) {
    stop_recording(LogLevel::kError, s.to_string());
    return false;
  }
  sequences_.back().bytes += odometry_writer_->text_bytes() - before;
  return true;
}

void Recorder::write_odometry(bool final) {
  std::size_t recorded = 0, not_recorded = 0;
  while (!odometry_waiting_.empty()) {
    const QueuedSample& q = odometry_waiting_.front();
    const bool open = !stopped_ && odometry_writer_ && q.session <= writing_session_;
    if (!open && !final && !stopped_) break;  // waits for its session's first frame
    if (open && write_row(q.sample)) ++recorded;
    else ++not_recorded;
    odometry_waiting_.pop_front();
  }
  if (recorded + not_recorded == 0) return;
  std::lock_guard<std::mutex> lock(mutex_);
  stats_.odometry_recorded += recorded;
  stats_.odometry_not_recorded += not_recorded;
  odometry_held_ -= recorded + not_recorded;
  stats_.bytes = total_bytes();
}

void Recorder::run() {
  scan();
  for (;;) {
    int index = -1;
    bool recording = false;
    bool finishing = false;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      work_.wait(lock, [this] { return ring_count_ > 0 || !odometry_queue_.empty() || finishing_; });
      odometry_taken_.swap(odometry_queue_);
      finishing = finishing_;
      if (ring_count_ > 0) {
        index = ring_[ring_head_];
        ring_head_ = (ring_head_ + 1) % ring_.size();
        --ring_count_;
      }
      recording = stats_.state == hal::RecorderState::kRecording;
    }
    odometry_waiting_.insert(odometry_waiting_.end(), odometry_taken_.begin(), odometry_taken_.end());
    odometry_taken_.clear();
    // The samples of the open sequence go into it before a frame of the next session closes it.
    write_odometry(false);
    if (index < 0) {
      if (finishing) break;  // everything queued is written
      continue;
    }
    Slot& slot = slots_[static_cast<std::size_t>(index)];
    const std::int64_t t0 = steady_clock_ns();
    const bool written = recording && write(slot);
    const std::int64_t dt = steady_clock_ns() - t0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (written) {
        ++stats_.frames_recorded;
        stats_.write.add(dt);
      } else {
        ++stats_.frames_not_recorded;
      }
      free_.push_back(index);
    }
    space_.notify_one();
    write_odometry(false);  // the new sequence's, once its first frame opened it
  }
  write_odometry(true);  // what no frame came after is not recorded
  if (euroc_) {
    if (Status s = euroc_->close(); !s.ok()) event(LogLevel::kError, "recorder: " + s.to_string());
    euroc_.reset();
  }
  if (odometry_writer_) {
    if (Status s = odometry_writer_->close(); !s.ok()) event(LogLevel::kError, "recorder: " + s.to_string());
    odometry_writer_.reset();
  }
}

}  // namespace ale::app
