// ale-map: checks, describes and re-saves the daemon's map files (core/io/map_file.h,
// docs/daemon.md "Map files").
//
//   ale-map check FILE [--camera-from DATASET] [CAPACITY]
//                                           the whole file checked and loaded; one summary line
//   ale-map info FILE [--camera-from DATASET] [CAPACITY]
//                                           the same, then the camera, the vocabulary checksum and
//                                           each map (id, metric, keyframes, landmarks, times)
//   ale-map resave SRC DST [--count N] [CAPACITY]
//                                           SRC loaded, then saved to DST N times in a row (default
//                                           1), each save's time printed as it ends (the power-cut
//                                           bench, scripts/map-powercut.sh, kills it mid-save)
// CAPACITY: --set slam.capacity.KEY=VALUE, any number of them (max_keyframes, max_landmarks,
// max_keypoints_per_keyframe: the daemon's keys, ranges and defaults, docs/configuration.md): the
// store the file is loaded into; a file beyond it is refused as the daemon would refuse it.
//
// A file is loaded with the camera and vocabulary checksum it records (read_map_file_context,
// after its frame and checksums are checked), so no dataset or vocabulary is needed; the daemon
// refuses a file whose camera or vocabulary differs from its own, which info shows. With
// --camera-from DATASET (check, info) the camera is instead the one a daemon replaying DATASET
// would have (its sensor.yaml's focal lengths and centre, its frames' size, the default features.*
// pyramid: 8 levels, scale 1.2), and a file made with another is refused saying what differs.
// Times are wall-clock milliseconds: check_ms reads the recorded camera and runs every check
// without a store (what the daemon does first), load_ms loads into the store (every checksum
// again, then the records).
//
// Exit status: 0 ok, 1 a file missing, refused (truncated, altered, another version, beyond the
// capacity) or not writable, 2 bad usage.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/features/orb.h"
#include "core/io/map_file.h"
#include "core/map/map_config.h"
#include "core/map/map_store.h"
#include "hal/replay/dataset.h"

namespace {

using ale::Result;
using ale::Status;
using ale::io::MapFileContext;
using ale::io::MapFileSummary;
using ale::map::MapStore;

constexpr int kExitData = 1;
constexpr int kExitUsage = 2;

const char kUsage[] =
    "usage: ale-map check FILE [--camera-from DATASET] [CAPACITY]\n"
    "       ale-map info FILE [--camera-from DATASET] [CAPACITY]\n"
    "       ale-map resave SRC DST [--count N] [CAPACITY]\n"
    "CAPACITY: --set slam.capacity.KEY=VALUE ... (the daemon's max_keyframes, max_landmarks,\n"
    "          max_keypoints_per_keyframe; defaults: the daemon's)\n"
    "exit status: 0 ok, 1 a file missing, refused or not writable, 2 bad usage\n";

int usage(const std::string& complaint = "") {
  if (!complaint.empty()) std::fprintf(stderr, "ale-map: %s\n", complaint.c_str());
  std::fputs(kUsage, stderr);
  return kExitUsage;
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// The command line after the subcommand: positional arguments and the options every subcommand
// takes (the capacity) or only resave takes (--count).
struct Args {
  std::vector<std::string> files;
  ale::map::MapCapacity capacity;
  long count = 1;
  bool count_given = false;
  std::string camera_from;  // a dataset; empty: the file's own camera
};

// Parses argv[first..]; returns an empty string or what is wrong.
std::string parse_args(int argc, char** argv, int first, Args& a) {
  const std::string capacity_prefix = "slam.capacity.";
  for (int i = first; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--", 0) != 0) {
      a.files.push_back(arg);
      continue;
    }
    if (i + 1 >= argc) return arg + " needs a value";
    const std::string value = argv[++i];
    if (arg == "--count") {
      // a whole number from 1 to 999999
      if (value.empty() || value.size() > 6 || value.find_first_not_of("0123456789") != std::string::npos ||
          std::stol(value) < 1) {
        return "bad value for --count: " + value;
      }
      a.count = std::stol(value);
      a.count_given = true;
    } else if (arg == "--camera-from") {
      a.camera_from = value;
    } else if (arg == "--set") {
      // slam.capacity.KEY=VALUE, checked against the daemon's table (its ranges)
      const std::size_t eq = value.find('=');
      if (value.rfind(capacity_prefix, 0) != 0 || eq == std::string::npos) {
        return "--set takes slam.capacity.KEY=VALUE, not " + value;
      }
      const std::string key = value.substr(capacity_prefix.size(), eq - capacity_prefix.size());
      const Status s = ale::set_field(ale::map::kMapCapacityConfig, &a.capacity, key, value.substr(eq + 1),
                                      "--set " + value.substr(0, eq));
      if (!s.ok()) return s.message();
    } else {
      return "unknown option " + arg;
    }
  }
  return "";
}

// A file checked and loaded into a store of `capacity`, with the times it took.
struct Loaded {
  MapFileContext context;
  std::unique_ptr<MapStore> store;
  MapFileSummary summary;
  double check_ms = 0.0;
  double load_ms = 0.0;
};

// The camera a daemon replaying `dataset` loads a map with (its camera_of: the calibration's
// focal lengths and centre, the frames' size; the pyramid of the default features.*).
Result<ale::io::MapFileCamera> camera_from(const std::string& dataset) {
  ale::replay::DatasetOptions options;
  options.odometry = false;
  Result<ale::replay::Dataset> d = ale::replay::open_dataset(dataset, options);
  if (!d.ok()) return Status(d.status().code(), "--camera-from " + dataset + ": " + d.status().message());
  if (!d->calibration) return ale::not_found("--camera-from " + dataset + ": no sensor.yaml (a EuRoC layout has one)");
  const ale::hal::CameraCalibration& c = *d->calibration;
  const ale::features::ExtractorConfig features;
  return ale::io::MapFileCamera{c.fx, c.fy, c.cx, c.cy, d->width, d->height, features.num_levels,
                                static_cast<float>(features.scale_factor)};
}

// `camera`: what to check the file's camera against; nullptr: the file's own.
Result<Loaded> load(const std::string& path, const ale::map::MapCapacity& capacity,
                    const ale::io::MapFileCamera* camera = nullptr) {
  Loaded l;
  const auto t0 = std::chrono::steady_clock::now();
  Result<MapFileContext> context = ale::io::read_map_file_context(path);
  if (!context.ok()) return context.status();
  l.context = *context;
  if (camera) l.context.camera = *camera;
  Result<MapFileSummary> checked = ale::io::check_map_file(path, l.context, capacity);
  if (!checked.ok()) return checked.status();
  l.check_ms = ms_since(t0);
  l.store = std::make_unique<MapStore>(capacity);
  const auto t1 = std::chrono::steady_clock::now();
  Result<MapFileSummary> loaded = ale::io::load_map_file(path, l.context, *l.store);
  if (!loaded.ok()) return loaded.status();
  l.load_ms = ms_since(t1);
  l.summary = *loaded;
  return l;
}

int refused(const std::string& path, const Status& s) {
  std::fprintf(stderr, "ale-map: %s: refused: %s\n", path.c_str(), s.to_string().c_str());
  return kExitData;
}

void print_summary(const std::string& path, const Loaded& l) {
  const MapFileSummary& s = l.summary;
  std::printf("map=%s version=%u bytes=%llu maps=%d keyframes=%d landmarks=%d current_map=%u check_ms=%.2f load_ms=%.2f\n",
              path.c_str(), ale::io::kMapFileVersion, static_cast<unsigned long long>(s.bytes), s.maps, s.keyframes,
              s.landmarks, s.current_map, l.check_ms, l.load_ms);
}

void print_details(const Loaded& l) {
  const ale::io::MapFileCamera& c = l.context.camera;
  std::printf("camera: %dx%d fx=%.4f fy=%.4f cx=%.4f cy=%.4f pyramid_levels=%d scale_factor=%.4f\n", c.width, c.height,
              c.fx, c.fy, c.cx, c.cy, c.levels, static_cast<double>(c.scale_factor));
  if (l.context.vocabulary_checksum == 0) {
    std::printf("vocabulary: none (made without place recognition)\n");
  } else {
    std::printf("vocabulary: checksum=%016llx\n", static_cast<unsigned long long>(l.context.vocabulary_checksum));
  }
  const MapStore& store = *l.store;
  for (const ale::map::MapInfo& m : store.maps()) {
    double first = 0.0, last = 0.0;
    bool any = false;
    store.for_each_keyframe([&](ale::map::KeyframeId, const ale::map::Keyframe& k) {
      if (!(k.map_id == m.id)) return;
      first = any ? std::min(first, k.timestamp_s) : k.timestamp_s;
      last = any ? std::max(last, k.timestamp_s) : k.timestamp_s;
      any = true;
    });
    std::printf("map id=%u%s metric=%d keyframes=%zu landmarks=%zu keyframe_times_s=%.3f..%.3f\n", m.id.value,
                m.id.value == store.current_map().value ? " (current)" : "", m.metric ? 1 : 0, m.keyframes, m.landmarks, first, last);
  }
}

int check(const Args& a, bool details) {
  if (a.files.size() != 1 || a.count_given) return usage();
  std::optional<ale::io::MapFileCamera> camera;
  if (!a.camera_from.empty()) {
    Result<ale::io::MapFileCamera> c = camera_from(a.camera_from);
    if (!c.ok()) {
      std::fprintf(stderr, "ale-map: %s\n", c.status().to_string().c_str());
      return kExitData;
    }
    camera = *c;
  }
  Result<Loaded> l = load(a.files[0], a.capacity, camera ? &*camera : nullptr);
  if (!l.ok()) return refused(a.files[0], l.status());
  print_summary(a.files[0], *l);
  if (details) print_details(*l);
  return 0;
}

int resave(const Args& a) {
  if (a.files.size() != 2 || !a.camera_from.empty()) return usage();
  const std::string& src = a.files[0];
  const std::string& dst = a.files[1];
  Result<Loaded> l = load(src, a.capacity);
  if (!l.ok()) return refused(src, l.status());
  print_summary(src, *l);
  std::fflush(stdout);
  for (long i = 1; i <= a.count; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    Result<MapFileSummary> saved = ale::io::save_map_file(*l->store, l->context, dst);
    if (!saved.ok()) {
      std::fprintf(stderr, "ale-map: save %ld of %ld: %s\n", i, a.count, saved.status().to_string().c_str());
      return kExitData;
    }
    std::printf("save=%ld/%ld map=%s bytes=%llu save_ms=%.2f\n", i, a.count, dst.c_str(),
                static_cast<unsigned long long>(saved->bytes), ms_since(t0));
    std::fflush(stdout);  // the bench reads how many saves ended before the kill
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  const std::string command = argv[1];
  if (command == "--help" || command == "-h" || command == "help") {
    std::fputs(kUsage, stdout);
    return 0;
  }
  Args a;
  if (const std::string bad = parse_args(argc, argv, 2, a); !bad.empty()) return usage(bad);
  if (command == "check") return check(a, false);
  if (command == "info") return check(a, true);
  if (command == "resave") return resave(a);
  return usage("unknown command " + command);
}
