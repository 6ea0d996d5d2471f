// The map file: a store saved and loaded again is the same store (every field, through a dump by
// dense index, and the same bytes when saved again), the previous file is kept as the backup, and
// a truncated, altered, other-version, other-vocabulary, other-camera or too large file is refused
// with the store left empty.
#include "core/io/map_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "core/base/checksum.h"
#include "core/io/file_bytes.h"
#include "core/map/dense_index.h"

namespace ale::io {
namespace {

using map::KeyframeId;
using map::LandmarkId;
using map::MapStore;

const map::MapCapacity kCapacity{16, 400, 64};

MapFileContext context() {
  MapFileContext c;
  c.camera = MapFileCamera{458.5, 457.25, 367.2, 248.4, 640, 480, 8, 1.2f};
  c.vocabulary_checksum = 0x1234567890ABCDEFull;
  return c;
}

std::vector<map::KeyframeFeature> features(int n, int seed) {
  std::vector<map::KeyframeFeature> f(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    map::KeyframeFeature& k = f[static_cast<std::size_t>(i)];
    k.u = 10.25f + static_cast<float>(i) * 3.5f;
    k.v = 20.5f + static_cast<float>(seed) * 1.75f;
    k.angle_deg = static_cast<float>((i * 37 + seed) % 360);
    k.level = static_cast<std::int16_t>(i % 8);
    for (std::size_t b = 0; b < k.descriptor.bytes.size(); ++b) k.descriptor.bytes[b] = static_cast<std::uint8_t>(i * 7 + b + seed);
  }
  return f;
}

// Two maps with the history a run leaves: erased keyframes and landmarks (slots out of order),
// a re-rooted tree, loop edges, odometry, observations of several keyframes.
struct TwoMaps {
  MapStore store{kCapacity};
  TwoMaps() {
    build_map(0, 6);
    store.set_metric(store.current_map(), true);
    store.start_map();
    build_map(100, 5);
  }
  void build_map(int seed, int n) {
    std::vector<KeyframeId> kfs;
    for (int i = 0; i < n; ++i) {
      const auto f = features(45, seed + i);
      const geometry::SE3 T(geometry::SO3::exp(geometry::Vec3(0.01 * i, -0.2 + 0.03 * i, 0.1)),
                            geometry::Vec3(0.1 * i + 1.0 / 3.0, -0.05 * i, 2.0 / 7.0));
      Result<KeyframeId> id = store.add_keyframe(1.5 + 0.2 * (seed + i), static_cast<std::uint64_t>(seed + i) * 3, T,
                                                 f.data(), 45);
      ASSERT_TRUE(id.ok());
      map::Keyframe& k = *store.keyframe(*id);
      k.has_odometry = i % 2 == 0;
      k.odometry_x_m = 0.1 * i;
      k.odometry_y_m = -0.01 * i;
      k.odometry_theta_rad = 0.3 * i;
      kfs.push_back(*id);
    }
    for (int l = 0; l < 40; ++l) {
      features::Descriptor d{};
      d.bytes[0] = static_cast<std::uint8_t>(l);
      Result<LandmarkId> lm = store.add_landmark(geometry::Vec3(0.1 * l, 1.0 / (l + 1), 3.0), d, kfs[l % n]);
      ASSERT_TRUE(lm.ok());
      for (int j = 0; j < 3; ++j) {
        ASSERT_TRUE(store.add_observation(*lm, kfs[static_cast<std::size_t>((l + j) % n)], l).ok());
      }
      map::Landmark& m = *store.landmark(*lm);
      m.normal = geometry::Vec3(0.0, 0.6, 0.8);
      m.min_distance = 0.5f + 0.01f * static_cast<float>(l);
      m.max_distance = 4.0f;
      m.visible = static_cast<std::uint32_t>(10 + l);
      m.found = static_cast<std::uint32_t>(5 + l);
      if (l % 9 == 4) store.erase_landmark(*lm);
    }
    // a chain, as tracking leaves it (update_connections alone would link these all-at-once
    // keyframes to later ones, in a cycle)
    for (std::size_t i = 1; i < kfs.size(); ++i) ASSERT_TRUE(store.restore_parent(kfs[i], kfs[i - 1]).ok());
    for (KeyframeId k : kfs) store.update_connections(k, 1);
    ASSERT_TRUE(store.add_loop_edge(kfs[0], kfs[static_cast<std::size_t>(n - 1)]).ok());
    store.erase_keyframe(kfs[0]);  // the root: its strongest child takes over
    store.erase_keyframe(kfs[2]);
  }
};

// Every field of every map by dense index: equal dumps, equal stores.
std::string dump(const MapStore& store) {
  std::ostringstream os;
  os.precision(17);
  map::DenseIndex index(store);
  os << "current " << store.current_map().value << "\n";
  for (const map::MapInfo& m : store.maps()) {
    index.build(store, m.id);
    os << "map " << m.id.value << " metric " << m.metric << " root " << index.index_of(m.root) << " kfs "
       << index.num_keyframes() << " lms " << index.num_landmarks() << "\n";
    for (int i = 0; i < index.num_keyframes(); ++i) {
      const KeyframeId id = index.keyframe_at(i);
      const map::Keyframe& k = *store.keyframe(id);
      const auto& q = k.T_cw.so3().quaternion();
      os << "kf " << i << " t " << k.timestamp_s << " seq " << k.frame_seq << " q " << q.w() << ' ' << q.x() << ' '
         << q.y() << ' ' << q.z() << " p " << k.T_cw.translation().transpose() << " parent "
         << index.index_of(k.parent) << " odo " << k.has_odometry << ' ' << k.odometry_x_m << ' ' << k.odometry_y_m
         << ' ' << k.odometry_theta_rad << "\n  cov";
      for (const map::Covisible& c : store.covisible_of(id)) os << ' ' << index.index_of(c.keyframe) << ':' << c.weight;
      os << "\n  loops";
      for (KeyframeId l : store.loop_edges(id)) os << ' ' << index.index_of(l);
      os << "\n  children";
      store.for_each_child(id, [&](KeyframeId c) { os << ' ' << index.index_of(c); });
      os << "\n  features";
      const auto lms = store.keypoint_landmarks_of(id);
      int f_at = 0;
      for (const map::KeyframeFeature& f : store.features_of(id)) {
        os << ' ' << f.u << ',' << f.v << ',' << f.angle_deg << ',' << f.level << ',' << int(f.descriptor.bytes[0])
           << ',' << int(f.descriptor.bytes[31]) << ',' << index.index_of(lms[f_at++]);
      }
      os << "\n";
    }
    for (int i = 0; i < index.num_landmarks(); ++i) {
      const LandmarkId id = index.landmark_at(i);
      const map::Landmark& l = *store.landmark(id);
      os << "lm " << i << " p " << l.p_w.transpose() << " n " << l.normal.transpose() << " d " << l.min_distance << ' '
         << l.max_distance << " ref " << index.index_of(l.reference) << " first " << index.index_of(l.first) << " vf "
         << l.visible << ' ' << l.found << " desc " << int(l.descriptor.bytes[0]) << " obs";
      for (const map::Observation& o : store.observations_of(id)) os << ' ' << index.index_of(o.keyframe) << '/' << o.keypoint;
      os << "\n";
    }
  }
  return os.str();
}

class MapFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/ale_map_file_XXXXXX";
    ASSERT_NE(::mkdtemp(tmpl), nullptr);
    dir_ = tmpl;
    path_ = dir_ + "/home.alemap";
  }
  void TearDown() override {
    for (const char* suffix : {"", ".bak", ".tmp", ".bak.tmp"}) std::remove((path_ + suffix).c_str());
    ::rmdir(dir_.c_str());
  }
  std::vector<std::uint8_t> bytes(const std::string& p) {
    std::vector<std::uint8_t> b;
    EXPECT_TRUE(read_file_bytes(p, b).ok());
    return b;
  }
  // Loads `b` into a fresh store: the status, and the store left empty when refused.
  Status load(const std::vector<std::uint8_t>& b, const MapFileContext& c = context()) {
    MapStore s(kCapacity);
    Result<MapFileSummary> r = load_map_bytes(b.data(), b.size(), c, s);
    if (!r.ok()) {
      EXPECT_EQ(s.stats().keyframes + s.stats().landmarks, 0u) << r.status().to_string();
    }
    return r.status();
  }
  std::string dir_, path_;
};

TEST_F(MapFileTest, ALoadedStoreEqualsTheSavedOneAndSavesTheSameBytes) {
  TwoMaps a;
  Result<MapFileSummary> saved = save_map_file(a.store, context(), path_);
  ASSERT_TRUE(saved.ok()) << saved.status().to_string();
  EXPECT_EQ(saved->maps, 2);
  EXPECT_EQ(saved->bytes, map_file_bytes(a.store));
  EXPECT_EQ(bytes(path_).size(), saved->bytes);

  MapStore b(kCapacity);
  Result<MapFileSummary> loaded = load_map_file(path_, context(), b);
  ASSERT_TRUE(loaded.ok()) << loaded.status().to_string();
  EXPECT_EQ(loaded->keyframes, saved->keyframes);
  EXPECT_EQ(loaded->landmarks, saved->landmarks);
  EXPECT_EQ(b.current_map(), a.store.current_map());
  EXPECT_EQ(dump(b), dump(a.store));
  EXPECT_GT(dump(a.store).size(), 10000u);  // the dump really holds the maps

  const std::string again = dir_ + "/again.alemap";
  ASSERT_TRUE(save_map_file(b, context(), again).ok());
  EXPECT_EQ(bytes(again), bytes(path_));
  std::remove(again.c_str());

  // a new map after the loaded ones takes an id above theirs
  b.start_map();
  EXPECT_GT(b.current_map().value, a.store.current_map().value);
}

TEST_F(MapFileTest, TheCurrentMapIsRestoredWhenItIsNotTheNewest) {
  TwoMaps a;
  const map::MapId first = a.store.maps()[0].id;
  // a third map merged into the first: the first is current, the second the newest
  a.store.start_map();
  const auto f = features(30, 7);
  Result<KeyframeId> k = a.store.add_keyframe(9.0, 900, geometry::SE3(), f.data(), 30);
  ASSERT_TRUE(k.ok());
  ASSERT_TRUE(a.store.merge_map(a.store.current_map(), first, a.store.root_of(first)).ok());
  ASSERT_EQ(a.store.current_map(), first);
  ASSERT_NE(a.store.maps()[a.store.maps().size() - 1].id, first);
  ASSERT_TRUE(save_map_file(a.store, context(), path_).ok());
  MapStore b(kCapacity);
  ASSERT_TRUE(load_map_file(path_, context(), b).ok());
  EXPECT_EQ(b.current_map(), first);
  b.start_map();
  EXPECT_GT(b.current_map().value, a.store.maps()[a.store.maps().size() - 1].id.value);
}

TEST_F(MapFileTest, SavingAgainKeepsThePreviousFileAsTheBackup) {
  TwoMaps a;
  ASSERT_TRUE(save_map_file(a.store, context(), path_).ok());
  const std::vector<std::uint8_t> first = bytes(path_);
  a.store.erase_keyframe(a.store.root());
  ASSERT_TRUE(save_map_file(a.store, context(), path_).ok());
  EXPECT_EQ(bytes(map_file_backup_path(path_)), first);
  EXPECT_NE(bytes(path_), first);
  EXPECT_NE(::access((path_ + ".tmp").c_str(), F_OK), 0);
  EXPECT_NE(::access((path_ + ".bak.tmp").c_str(), F_OK), 0);
  EXPECT_TRUE(load(bytes(path_)).ok());
  EXPECT_TRUE(load(bytes(map_file_backup_path(path_))).ok());
}

TEST_F(MapFileTest, SavingWhereNothingCanBeWrittenFailsNamingThePath) {
  TwoMaps a;
  Result<MapFileSummary> r = save_map_file(a.store, context(), dir_ + "/no/such/dir/home.alemap");
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kIoError);
  EXPECT_NE(r.status().message().find("no/such/dir"), std::string::npos);
}

TEST_F(MapFileTest, AMissingFileIsNotFoundAndANonEmptyStoreIsRefused) {
  MapStore s(kCapacity);
  EXPECT_EQ(load_map_file(path_, context(), s).status().code(), StatusCode::kNotFound);
  TwoMaps a;
  ASSERT_TRUE(save_map_file(a.store, context(), path_).ok());
  EXPECT_EQ(load_map_file(path_, context(), a.store).status().code(), StatusCode::kInvalidArgument);
}

TEST_F(MapFileTest, EveryTruncationIsRefused) {
  TwoMaps a;
  ASSERT_TRUE(save_map_file(a.store, context(), path_).ok());
  const std::vector<std::uint8_t> whole = bytes(path_);
  for (std::size_t n = 0; n < whole.size(); n += (n < 200 ? 1 : 61)) {
    const std::vector<std::uint8_t> cut(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(n));
    const Status s = load(cut);
    EXPECT_EQ(s.code(), StatusCode::kCorruptData) << n << " bytes: " << s.to_string();
  }
  const Status s = load(std::vector<std::uint8_t>(whole.begin(), whole.end() - 1));
  EXPECT_NE(s.message().find("truncated"), std::string::npos) << s.to_string();
}

TEST_F(MapFileTest, EveryChangedByteIsRefused) {
  TwoMaps a;
  ASSERT_TRUE(save_map_file(a.store, context(), path_).ok());
  const std::vector<std::uint8_t> whole = bytes(path_);
  int refused = 0, tried = 0;
  for (std::size_t i = 0; i < whole.size(); i += 13) {
    std::vector<std::uint8_t> b = whole;
    b[i] ^= static_cast<std::uint8_t>(1u << (i % 8));
    ++tried;
    const Status s = load(b);
    refused += s.ok() ? 0 : 1;
    EXPECT_FALSE(s.ok()) << "byte " << i;
  }
  EXPECT_EQ(refused, tried);
}

// The header with one field changed and its checksum made right again.
std::vector<std::uint8_t> with_header_field(std::vector<std::uint8_t> b, std::size_t offset, std::uint64_t value,
                                            std::size_t width) {
  std::memcpy(b.data() + offset, &value, width);
  const std::uint64_t h = fnv1a64(b.data(), 56);
  std::memcpy(b.data() + 56, &h, 8);
  return b;
}

TEST_F(MapFileTest, AnotherVersionVocabularyOrCameraIsRefusedSayingSo) {
  TwoMaps a;
  ASSERT_TRUE(save_map_file(a.store, context(), path_).ok());
  const std::vector<std::uint8_t> whole = bytes(path_);
  const Status version = load(with_header_field(whole, 8, 2, 4));
  EXPECT_EQ(version.code(), StatusCode::kUnsupported);
  EXPECT_NE(version.message().find("format version 2"), std::string::npos) << version.to_string();

  MapFileContext other = context();
  other.vocabulary_checksum ^= 1;
  const Status vocabulary = load(whole, other);
  EXPECT_EQ(vocabulary.code(), StatusCode::kUnsupported);
  EXPECT_NE(vocabulary.message().find("vocabulary"), std::string::npos) << vocabulary.to_string();

  other = context();
  other.camera.width = 320;
  const Status camera = load(whole, other);
  EXPECT_EQ(camera.code(), StatusCode::kUnsupported);
  EXPECT_NE(camera.message().find("camera"), std::string::npos) << camera.to_string();
}

TEST_F(MapFileTest, AMapBeyondTheStoresCapacityIsRefusedBeforeLoading) {
  TwoMaps a;
  ASSERT_TRUE(save_map_file(a.store, context(), path_).ok());
  MapStore small(map::MapCapacity{4, 400, 64});
  Result<MapFileSummary> r = load_map_file(path_, context(), small);
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.status().message().find("capacity"), std::string::npos) << r.status().to_string();
  EXPECT_EQ(small.stats().keyframes, 0u);

  MapStore few_points(map::MapCapacity{16, 400, 16});  // fewer keypoints a keyframe than saved
  r = load_map_file(path_, context(), few_points);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.status().code(), StatusCode::kCorruptData);
  EXPECT_EQ(few_points.stats().keyframes, 0u);
}

TEST_F(MapFileTest, AnEmptyStoreRoundTrips) {
  MapStore a(kCapacity);
  ASSERT_TRUE(save_map_file(a, context(), path_).ok());
  MapStore b(kCapacity);
  Result<MapFileSummary> r = load_map_file(path_, context(), b);
  ASSERT_TRUE(r.ok()) << r.status().to_string();
  EXPECT_EQ(r->keyframes, 0);
  EXPECT_EQ(dump(b), dump(a));
}

// A tool without the daemon's camera and vocabulary reads them from the file: the ones it was
// saved with, which load it; a missing, truncated or altered file is refused as load refuses it.
TEST_F(MapFileTest, TheRecordedContextIsTheSavedOneAndLoadsTheFile) {
  TwoMaps a;
  EXPECT_EQ(read_map_file_context(path_).status().code(), StatusCode::kNotFound);
  MapFileContext saved = context();
  saved.camera.cx = 101.75;
  saved.vocabulary_checksum = 0xFEDCBA0987654321ull;
  ASSERT_TRUE(save_map_file(a.store, saved, path_).ok());
  Result<MapFileContext> recorded = read_map_file_context(path_);
  ASSERT_TRUE(recorded.ok()) << recorded.status().to_string();
  EXPECT_TRUE(recorded->camera == saved.camera);
  EXPECT_EQ(recorded->vocabulary_checksum, saved.vocabulary_checksum);
  MapStore b(kCapacity);
  EXPECT_TRUE(load_map_file(path_, *recorded, b).ok());

  const std::vector<std::uint8_t> whole = bytes(path_);
  const auto refused = [&](const std::vector<std::uint8_t>& file, const char* what) {
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(std::fwrite(file.data(), 1, file.size(), f), file.size());
    std::fclose(f);
    const Result<MapFileContext> r = read_map_file_context(path_);
    ASSERT_FALSE(r.ok()) << what;
    EXPECT_EQ(r.status().code(), StatusCode::kCorruptData) << what << ": " << r.status().to_string();
  };
  refused(std::vector<std::uint8_t>(whole.begin(), whole.end() - 1), "one byte short");
  std::vector<std::uint8_t> camera_changed = whole;
  camera_changed[kMapFileHeaderBytes + 8 + 16] ^= 1;  // a bit of cx in the meta section
  refused(camera_changed, "cx changed");
  refused(with_header_field(whole, 32, 7, 8), "another vocabulary checksum written without the file checksum");
}

}  // namespace
}  // namespace ale::io
