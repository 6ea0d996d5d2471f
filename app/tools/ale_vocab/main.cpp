// ale-vocab: trains, describes and evaluates the bag-of-words vocabulary (core/place/vocabulary.h,
// docs/place.md).
//
//   ale-vocab train --out FILE [--k K] [--levels L] [--seed S] [--iterations N] IMAGE_OR_FOLDER...
//   ale-vocab info [FILE]
//   ale-vocab eval [--vocab FILE] [--loop DIR] [--euroc DIR --sensor-yaml FILE] [--exclude-s S] [--hit-m M] [--hit-deg D] [--list]
//
// train: every PNG or JPEG given, or found (recursively, in name order) under a folder given,
// goes through the daemon's ORB front end with its default configuration (the ALE mode, 1000
// features, 8 levels; the grader reset for each image, as they are unrelated photos), and the
// descriptors of all of them train the vocabulary, written to FILE (replaced only once complete).
// info: the header, file size, checksum and parse time of FILE (without FILE: the vocabulary
// built into this binary). eval: size and parse time, then recall at 100 % precision:
//   --loop DIR   a rendered route driven more than once (ale-render, EuRoC layout with
//                groundtruth.txt): the first lap ends where the camera comes back nearest to its
//                first pose; every 10th frame after it is queried against every frame of the lap,
//                by score (`loop`) and through the keyframe database (`loop_database`: the first
//                relocalisation candidate);
//   --euroc DIR  euroc_v101_keyframes: each keyframe against the keyframes more than S seconds
//                (--exclude-s, default 10) away in time; body ground truth, camera through T_BS
//                of --sensor-yaml.
// A query is a hit when its best-scoring frame is within 0.5 m and 30 deg of it (ground truth;
// --hit-m and --hit-deg change that).
// Its precision at a threshold is the share of hits among queries whose best score reaches it;
// recall at 100 % precision is the share of queries (with a true match available) that are hits
// scoring above every wrong answer. --list prints each query's best answer, its score, distance
// and angle.
//
// Exit status: 0 ok, 1 bad data (unreadable image, no features, corrupt file), 2 bad usage.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "app/tools/lib/eval/trajectory.h"
#include "core/features/orb.h"
#include "core/frontend/frame_path.h"
#include "core/io/file_bytes.h"
#include "core/io/image_io.h"
#include "core/map/map_store.h"
#include "core/place/embedded/embedded_vocabulary.h"
#include "core/place/keyframe_database.h"
#include "core/place/vocabulary.h"
#include "hal/replay/dataset.h"

namespace {

namespace fs = std::filesystem;
using ale::Result;
using ale::Status;
using ale::place::BowVector;
using ale::place::FeatureVector;
using ale::place::Vocabulary;

constexpr int kExitData = 1;
constexpr int kExitUsage = 2;
// What counts as the same place (--hit-m, --hit-deg).
double g_hit_m = 0.5;
double g_hit_deg = 30.0;

int usage() {
  std::fprintf(stderr,
               "usage: ale-vocab train --out FILE [--k K] [--levels L] [--seed S] [--iterations N] IMAGE_OR_FOLDER...\n"
               "       ale-vocab info [FILE]\n"
               "       ale-vocab eval [--vocab FILE] [--loop DIR] [--euroc DIR --sensor-yaml FILE] [--exclude-s S] [--hit-m M] [--hit-deg D] [--list]\n");
  return kExitUsage;
}

bool parse_int(const char* s, long lo, long hi, long& out) {
  char* end = nullptr;
  const long v = std::strtol(s, &end, 10);
  if (end == s || *end != '\0' || v < lo || v > hi) return false;
  out = v;
  return true;
}

bool is_image(const fs::path& p) {
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".png" || ext == ".jpg" || ext == ".jpeg";
}

// The images named or found under the folders named, each folder's in name order.
Status collect_images(const std::vector<std::string>& inputs, std::vector<std::string>& out) {
  for (const std::string& in : inputs) {
    std::error_code ec;
    if (fs::is_directory(in, ec)) {
      std::vector<std::string> found;
      for (auto it = fs::recursive_directory_iterator(in, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
        if (it->is_regular_file(ec) && is_image(it->path())) found.push_back(it->path().string());
      }
      if (ec) return ale::io_error(in + ": cannot list: " + ec.message());
      if (found.empty()) return ale::not_found(in + ": no .png or .jpg images in this folder");
      std::sort(found.begin(), found.end());
      out.insert(out.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(in, ec)) {
      out.push_back(in);
    } else {
      return ale::not_found(in + ": no such image or folder");
    }
  }
  return {};
}

// The daemon's front end (default configuration) on one image, afresh.
class Extractor {
 public:
  Status init() { return path_.configure(ale::features::ExtractorConfig{}); }
  Status run(const std::string& file, std::vector<ale::features::Descriptor>& out) {
    ALE_RETURN_IF_ERROR(ale::io::read_gray(file, image_));
    path_.reset();
    const Status st = path_.extract(image_.view(), keypoints_, out);
    if (!st.ok()) return Status(st.code(), file + ": " + st.message());
    return {};
  }

 private:
  ale::frontend::FramePath path_;
  ale::GrayImage image_;
  std::vector<ale::features::Keypoint> keypoints_;
};

Status write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  const std::string tmp = path + ".part";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) return ale::io_error(tmp + ": cannot create");
    f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    f.close();
    if (!f) return ale::io_error(tmp + ": write failed");
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) return ale::io_error(path + ": cannot replace: " + ec.message());
  return {};
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// ---------------------------------------------------------------------------------------------

int train(int argc, char** argv) {
  std::string out;
  ale::place::VocabularyTrainParams params;
  std::vector<std::string> inputs;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    long v = 0;
    if (a == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (a == "--k" && i + 1 < argc && parse_int(argv[i + 1], 2, ale::place::kMaxBranching, v)) {
      params.k = static_cast<int>(v), ++i;
    } else if (a == "--levels" && i + 1 < argc && parse_int(argv[i + 1], 1, ale::place::kMaxVocabularyLevels, v)) {
      params.levels = static_cast<int>(v), ++i;
    } else if (a == "--seed" && i + 1 < argc && parse_int(argv[i + 1], 0, 0x7FFFFFFF, v)) {
      params.seed = static_cast<std::uint64_t>(v), ++i;
    } else if (a == "--iterations" && i + 1 < argc && parse_int(argv[i + 1], 1, 1000, v)) {
      params.max_iterations = static_cast<int>(v), ++i;
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "ale-vocab train: bad option or value: %s%s%s\n", a.c_str(), i + 1 < argc ? " " : "",
                   i + 1 < argc ? argv[i + 1] : "");
      return usage();
    } else {
      inputs.push_back(a);
    }
  }
  if (out.empty() || inputs.empty()) return usage();
  std::vector<std::string> files;
  Status st = collect_images(inputs, files);
  if (!st.ok()) {
    std::fprintf(stderr, "ale-vocab train: %s\n", st.to_string().c_str());
    return kExitData;
  }
  Extractor ex;
  st = ex.init();
  std::vector<std::vector<ale::features::Descriptor>> images;
  std::size_t total = 0;
  for (const std::string& f : files) {
    std::vector<ale::features::Descriptor> d;
    if (st.ok()) st = ex.run(f, d);
    if (!st.ok()) {
      std::fprintf(stderr, "ale-vocab train: %s\n", st.to_string().c_str());
      return kExitData;
    }
    if (d.empty()) std::fprintf(stderr, "ale-vocab train: warning: %s: no features\n", f.c_str());
    total += d.size();
    images.push_back(std::move(d));
  }
  if (total == 0) {
    std::fprintf(stderr, "ale-vocab train: no features in any of the %zu images\n", files.size());
    return kExitData;
  }
  std::printf("images=%zu descriptors=%zu k=%d levels=%d seed=%llu\n", files.size(), total, params.k, params.levels,
              static_cast<unsigned long long>(params.seed));
  const auto t0 = std::chrono::steady_clock::now();
  Result<Vocabulary> v = Vocabulary::train(images, params);
  if (!v.ok()) {
    std::fprintf(stderr, "ale-vocab train: %s\n", v.status().to_string().c_str());
    return kExitUsage;
  }
  const std::vector<std::uint8_t> bytes = v->serialize();
  st = write_bytes(out, bytes);
  if (!st.ok()) {
    std::fprintf(stderr, "ale-vocab train: %s\n", st.to_string().c_str());
    return kExitData;
  }
  std::printf("%s nodes=%d words=%d bytes=%zu checksum=%016llx train_s=%.1f\n", out.c_str(), v->num_nodes(), v->num_words(),
              bytes.size(), static_cast<unsigned long long>(v->checksum()), ms_since(t0) / 1000.0);
  return 0;
}

// The vocabulary of `file` (the built-in one when empty), its size and the median parse time of
// 21 parses in ms.
struct Loaded {
  Vocabulary vocab;
  std::size_t bytes = 0;
  double parse_ms = 0.0;
  std::string name;
};

Result<Loaded> load(const std::string& file) {
  std::vector<std::uint8_t> bytes;
  if (!file.empty()) {
    ALE_RETURN_IF_ERROR(ale::io::read_file_bytes(file, bytes));
  } else {
    const ale::Span<const std::uint8_t> e = ale::place::embedded_vocabulary_bytes();
    bytes.assign(e.begin(), e.end());
  }
  std::vector<double> times;
  Result<Vocabulary> v = Vocabulary::parse(bytes.data(), bytes.size());
  if (!v.ok()) return Status(v.status().code(), (file.empty() ? "built-in vocabulary" : file) + ": " + v.status().message());
  for (int i = 0; i < 21; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    Result<Vocabulary> again = Vocabulary::parse(bytes.data(), bytes.size());
    times.push_back(ms_since(t0));
  }
  std::nth_element(times.begin(), times.begin() + 10, times.end());
  return Loaded{std::move(*v), bytes.size(), times[10], file.empty() ? "built-in" : file};
}

void print_summary(const Loaded& l) {
  std::printf("vocabulary=%s bytes=%zu format=%u k=%d levels=%d nodes=%d words=%d checksum=%016llx parse_ms=%.2f\n",
              l.name.c_str(), l.bytes, ale::place::kVocabularyFormatVersion, l.vocab.branching(), l.vocab.levels(),
              l.vocab.num_nodes(), l.vocab.num_words(), static_cast<unsigned long long>(l.vocab.checksum()), l.parse_ms);
}

int info(int argc, char** argv) {
  if (argc > 3) return usage();
  Result<Loaded> l = load(argc == 3 ? argv[2] : "");
  if (!l.ok()) {
    std::fprintf(stderr, "ale-vocab info: %s\n", l.status().to_string().c_str());
    return kExitData;
  }
  print_summary(*l);
  return 0;
}

// ---------------------------------------------------------------------------------------------
// eval

struct Place {
  std::string file;
  double t_s = 0.0;
  Eigen::Matrix3d R_wc = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_wc = Eigen::Vector3d::Zero();
  BowVector bow;
  std::vector<ale::features::Descriptor> descriptors;
};

bool near(const Place& a, const Place& b) {
  const double angle = Eigen::AngleAxisd(a.R_wc.transpose() * b.R_wc).angle() * 180.0 / M_PI;
  return (a.p_wc - b.p_wc).norm() <= g_hit_m && angle <= g_hit_deg;
}

// The pose at time t (the nearest ground-truth pose, within 2 ms); false when none.
bool pose_at(const ale::eval::Trajectory& gt, double t_s, Eigen::Matrix3d& R, Eigen::Vector3d& p) {
  const auto it = std::lower_bound(gt.poses.begin(), gt.poses.end(), t_s,
                                   [](const ale::eval::StampedPose& s, double t) { return s.t_s < t; });
  const ale::eval::StampedPose* best = nullptr;
  if (it != gt.poses.end()) best = &*it;
  if (it != gt.poses.begin() && (best == nullptr || t_s - std::prev(it)->t_s < best->t_s - t_s)) best = &*std::prev(it);
  if (best == nullptr || std::abs(best->t_s - t_s) > 0.002) return false;
  R = best->R_wb;
  p = best->p_wb;
  return true;
}

// Reads images (name: the ns timestamp, then anything) and their poses; T_bc maps camera to
// ground-truth frame (identity when the ground truth is the camera).
Status read_places(const std::vector<std::string>& files, const ale::eval::Trajectory& gt, const Eigen::Matrix4d& T_bc,
                   const Vocabulary& vocab, std::vector<Place>& out) {
  Extractor ex;
  ALE_RETURN_IF_ERROR(ex.init());
  std::vector<ale::features::Descriptor> d;
  FeatureVector fv;
  for (const std::string& f : files) {
    Place pl;
    pl.file = f;
    pl.t_s = std::strtod(fs::path(f).stem().string().c_str(), nullptr) * 1e-9;
    Eigen::Matrix3d R;
    Eigen::Vector3d p;
    if (!pose_at(gt, pl.t_s, R, p)) return ale::not_found(f + ": no ground-truth pose within 2 ms of its timestamp");
    pl.R_wc = R * T_bc.topLeftCorner<3, 3>();
    pl.p_wc = p + R * T_bc.topRightCorner<3, 1>();
    ALE_RETURN_IF_ERROR(ex.run(f, d));
    vocab.transform(d.data(), static_cast<int>(d.size()), pl.bow, fv, 0);
    pl.descriptors = d;
    out.push_back(std::move(pl));
  }
  return {};
}

struct QueryResult {
  double score = 0.0;
  bool hit = false;
  bool has_true = false;  // a true match was among the candidates
  int query = -1;
  int best = -1;  // the best-scoring reference
};

bool g_list = false;  // --list: one line per query

// Recall at 100 % precision and the top-1 rate; prints one line.
void report(const char* name, std::vector<QueryResult> q) {
  std::sort(q.begin(), q.end(), [](const QueryResult& a, const QueryResult& b) { return a.score > b.score; });
  double max_wrong = -1.0;
  int positives = 0, top1 = 0;
  for (const QueryResult& r : q) {
    if (!r.hit) max_wrong = std::max(max_wrong, r.score);
    positives += r.has_true;
    top1 += r.hit;
  }
  int recalled = 0;
  for (const QueryResult& r : q) recalled += r.hit && r.score > max_wrong;
  std::printf("%s hit_within=%.2fm,%.0fdeg queries=%zu with_true_match=%d top1_hits=%d recall_at_100_precision=%.3f (%d/%d, threshold %.4f)\n", name,
              g_hit_m, g_hit_deg, q.size(), positives, top1, positives > 0 ? static_cast<double>(recalled) / positives : 0.0, recalled, positives,
              max_wrong);
}

// Each query against the references it may match (allowed(query, reference)).
template <class Allowed>
std::vector<QueryResult> query_all(const std::vector<Place>& places, const std::vector<int>& queries, Allowed&& allowed) {
  std::vector<QueryResult> out;
  for (int qi : queries) {
    const Place& q = places[static_cast<std::size_t>(qi)];
    QueryResult r;
    int best = -1;
    r.score = -1.0;
    for (int ri = 0; ri < static_cast<int>(places.size()); ++ri) {
      if (!allowed(qi, ri)) continue;
      const double s = Vocabulary::score(q.bow, places[static_cast<std::size_t>(ri)].bow);
      if (s > r.score) r.score = s, best = ri;
      r.has_true = r.has_true || near(q, places[static_cast<std::size_t>(ri)]);
    }
    r.hit = best >= 0 && near(q, places[static_cast<std::size_t>(best)]);
    r.query = qi;
    r.best = best;
    if (g_list && best >= 0) {
      const Place& b = places[static_cast<std::size_t>(best)];
      std::printf("  query=%s best=%s score=%.4f distance_m=%.2f angle_deg=%.1f hit=%d true_match_available=%d\n",
                  fs::path(q.file).filename().c_str(), fs::path(b.file).filename().c_str(), r.score, (q.p_wc - b.p_wc).norm(),
                  Eigen::AngleAxisd(q.R_wc.transpose() * b.R_wc).angle() * 180.0 / M_PI, r.hit, r.has_true);
    }
    out.push_back(r);
  }
  return out;
}

// The same queries through the keyframe database the relocaliser uses: the first lap's frames
// as keyframes of a map (no covisibility: each is its own group), each query's first
// relocalisation candidate as its answer.
Status loop_through_database(const std::vector<Place>& places, int lap, const std::vector<int>& queries,
                             const Vocabulary& vocab) {
  int max_features = 1;
  for (const Place& p : places) max_features = std::max(max_features, static_cast<int>(p.descriptors.size()));
  const ale::map::MapCapacity capacity{lap, 1, max_features};
  ale::map::MapStore map(capacity);
  ale::place::KeyframeDatabase db(vocab, capacity);
  std::vector<int> place_of_slot(static_cast<std::size_t>(lap), -1);
  for (int i = 0; i < lap; ++i) {
    const Place& p = places[static_cast<std::size_t>(i)];
    std::vector<ale::map::KeyframeFeature> f(p.descriptors.size());
    for (std::size_t k = 0; k < f.size(); ++k) f[k].descriptor = p.descriptors[k];
    Result<ale::map::KeyframeId> id = map.add_keyframe(p.t_s, static_cast<std::uint64_t>(i), ale::geometry::SE3(), f.data(),
                                                       static_cast<int>(f.size()));
    if (!id.ok()) return id.status();
    place_of_slot[id->slot()] = i;
  }
  (void)db.sync(map);
  std::vector<QueryResult> results;
  std::vector<ale::place::PlaceCandidate> candidates;
  BowVector bow;
  FeatureVector fv;
  for (int qi : queries) {
    const Place& q = places[static_cast<std::size_t>(qi)];
    vocab.transform(q.descriptors.data(), static_cast<int>(q.descriptors.size()), bow, fv, db.params().fv_levels_up);
    db.relocalisation_candidates(bow, map, candidates);
    QueryResult r;
    r.query = qi;
    for (int i = 0; i < lap && !r.has_true; ++i) r.has_true = near(q, places[static_cast<std::size_t>(i)]);
    r.score = -1.0;
    if (!candidates.empty()) {
      r.best = place_of_slot[candidates.front().keyframe.slot()];
      r.score = candidates.front().score;
      r.hit = near(q, places[static_cast<std::size_t>(r.best)]);
    }
    results.push_back(r);
  }
  report("loop_database", results);
  return {};
}

Status eval_loop(const std::string& dir, const Vocabulary& vocab) {
  std::vector<std::string> files;
  ALE_RETURN_IF_ERROR(collect_images({dir + "/mav0/cam0/data"}, files));
  Result<ale::eval::Trajectory> gt = ale::eval::read_trajectory(dir + "/groundtruth.txt");  // the camera
  if (!gt.ok()) return gt.status();
  std::vector<Place> places;
  ALE_RETURN_IF_ERROR(read_places(files, *gt, Eigen::Matrix4d::Identity(), vocab, places));
  // The first lap ends where the route comes back nearest to its first pose (heading within
  // 30 deg), looking from a quarter of the frames on.
  const int n = static_cast<int>(places.size());
  int lap = -1;
  double nearest = 1e9;
  for (int i = n / 4; i < n; ++i) {
    const Place& a = places.front();
    const Place& b = places[static_cast<std::size_t>(i)];
    const double d = (a.p_wc - b.p_wc).norm();
    if (d < nearest && Eigen::AngleAxisd(a.R_wc.transpose() * b.R_wc).angle() < g_hit_deg * M_PI / 180.0) {
      nearest = d;
      lap = i;
    }
  }
  if (lap < 0 || nearest > 0.25)
    return ale::invalid_argument(dir + ": the route does not come back within 0.25 m of its start: not a revisit");
  std::vector<int> queries;
  for (int i = lap; i < n; i += 10) queries.push_back(i);
  std::printf("loop frames=%d lap_frames=%d (back within %.3f m)\n", n, lap, nearest);
  report("loop", query_all(places, queries, [&](int, int r) { return r < lap; }));
  return loop_through_database(places, lap, queries, vocab);
}

Status eval_euroc(const std::string& dir, const std::string& sensor_yaml, double exclude_s, const Vocabulary& vocab) {
  std::vector<std::string> files;
  ALE_RETURN_IF_ERROR(collect_images({dir + "/cam0"}, files));
  Result<ale::eval::Trajectory> gt = ale::eval::read_trajectory(dir + "/gt_openvins_v101_at_keyframes.csv");  // the body
  if (!gt.ok()) return gt.status();
  Result<ale::hal::CameraCalibration> cal = ale::replay::read_euroc_sensor_yaml(sensor_yaml);
  if (!cal.ok()) return cal.status();
  Eigen::Matrix4d T_bc;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) T_bc(r, c) = cal->T_BS[static_cast<std::size_t>(4 * r + c)];
  std::vector<Place> places;
  ALE_RETURN_IF_ERROR(read_places(files, *gt, T_bc, vocab, places));
  std::vector<int> queries(places.size());
  for (std::size_t i = 0; i < queries.size(); ++i) queries[i] = static_cast<int>(i);
  char name[64];
  std::snprintf(name, sizeof name, "euroc_keyframes(exclude_%gs)", exclude_s);
  report(name, query_all(places, queries, [&](int q, int r) {
           return std::abs(places[static_cast<std::size_t>(q)].t_s - places[static_cast<std::size_t>(r)].t_s) > exclude_s;
         }));
  return {};
}

int eval(int argc, char** argv) {
  std::string vocab_file, loop, euroc, yaml;
  double exclude_s = 10.0;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (i + 1 >= argc && a != "--list") return usage();
    if (a == "--vocab") {
      vocab_file = argv[++i];
    } else if (a == "--loop") {
      loop = argv[++i];
    } else if (a == "--euroc") {
      euroc = argv[++i];
    } else if (a == "--sensor-yaml") {
      yaml = argv[++i];
    } else if (a == "--list") {
      g_list = true;
    } else if (a == "--exclude-s" || a == "--hit-m" || a == "--hit-deg") {
      char* end = nullptr;
      const double v = std::strtod(argv[++i], &end);
      if (*end != '\0' || !(v >= 0.0) || !std::isfinite(v)) {
        std::fprintf(stderr, "ale-vocab eval: %s %s: a number >= 0 is needed\n", a.c_str(), argv[i]);
        return usage();
      }
      (a == "--exclude-s" ? exclude_s : a == "--hit-m" ? g_hit_m : g_hit_deg) = v;
    } else {
      return usage();
    }
  }
  if (!euroc.empty() && yaml.empty()) {
    std::fprintf(stderr, "ale-vocab eval: --euroc needs --sensor-yaml (the camera's T_BS)\n");
    return usage();
  }
  Result<Loaded> l = load(vocab_file);
  Status st = l.ok() ? Status() : l.status();
  if (st.ok()) print_summary(*l);
  if (st.ok() && !loop.empty()) st = eval_loop(loop, l->vocab);
  if (st.ok() && !euroc.empty()) st = eval_euroc(euroc, yaml, exclude_s, l->vocab);
  if (!st.ok()) {
    std::fprintf(stderr, "ale-vocab eval: %s\n", st.to_string().c_str());
    return kExitData;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) return usage();
  const std::string cmd = argv[1];
  if (cmd == "train") return train(argc, argv);
  if (cmd == "info") return info(argc, argv);
  if (cmd == "eval") return eval(argc, argv);
  return usage();
}
