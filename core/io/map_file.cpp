#include "core/io/map_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "core/base/checksum.h"
#include "core/map/dense_index.h"

namespace ale::io {
namespace {

using map::Covisible;
using map::KeyframeId;
using map::LandmarkId;
using map::MapStore;

enum SectionKind : std::uint32_t { kMeta = 1, kKeyframes = 2, kLandmarks = 3 };

constexpr std::size_t kTableEntryBytes = 32;
constexpr std::size_t kMetaBytes = 8 + 4 * 8 + 4 * 4;
constexpr std::size_t kMetaMapBytes = 16;
constexpr std::size_t kKeyframeBytes = 8 + 8 + 7 * 8 + 4 + 4 + 3 * 8 + 3 * 4;
constexpr std::size_t kFeatureBytes = 3 * 4 + 2 + 2 + sizeof(features::Descriptor{}.bytes);
constexpr std::size_t kCovisibleBytes = 8;
constexpr std::size_t kLoopEdgeBytes = 4;
constexpr std::size_t kLandmarkBytes = 3 * 8 + sizeof(features::Descriptor{}.bytes) + 3 * 8 + 2 * 4 + 2 * 4 + 3 * 4;
constexpr std::size_t kObservationBytes = 8;
// More maps than any store keeps (SlamSystem keeps slam.loop_closing.max_maps); a file saying more
// is corrupt.
constexpr std::uint32_t kMaxMaps = 64;

std::string path_error(const std::string& what, const std::string& path) {
  return "map file " + path + ": " + what + ": " + std::strerror(errno);
}

// A keyframe's references as the file writes them: indices in its map's DenseIndex, links to
// keyframes outside the index (none in a consistent store) left out, so the size pass and the
// write pass agree.
struct KeyframeLinks {
  std::int32_t parent = -1;
  std::array<std::pair<std::int32_t, std::int32_t>, map::kMaxCovisible> covisible{};
  int num_covisible = 0;
  std::array<std::int32_t, map::kMaxLoopEdges> loops{};
  int num_loops = 0;
};

void gather_links(const MapStore& store, const map::DenseIndex& index, KeyframeId kf, KeyframeLinks& out) {
  const map::Keyframe& k = *store.keyframe(kf);
  out.parent = index.index_of(k.parent);
  out.num_covisible = 0;
  for (const Covisible& c : store.covisible_of(kf)) {
    const int i = index.index_of(c.keyframe);
    if (i >= 0) out.covisible[static_cast<std::size_t>(out.num_covisible++)] = {i, c.weight};
  }
  // strongest first, ties by index: a store that loads the file numbers its keyframes in that
  // order, so it sorts them the same way and saves the same bytes
  std::sort(out.covisible.begin(), out.covisible.begin() + out.num_covisible,
            [](const auto& a, const auto& b) { return a.second != b.second ? a.second > b.second : a.first < b.first; });
  out.num_loops = 0;
  for (KeyframeId l : store.loop_edges(kf)) {
    const int i = index.index_of(l);
    if (i >= 0) out.loops[static_cast<std::size_t>(out.num_loops++)] = i;
  }
}

int live_observations(const MapStore& store, const map::DenseIndex& index, LandmarkId lm) {
  int n = 0;
  for (const map::Observation& o : store.observations_of(lm)) n += index.index_of(o.keyframe) >= 0 ? 1 : 0;
  return n;
}

// The maps in file order: the others oldest first, the current one last.
std::vector<map::MapInfo> file_maps(const MapStore& store) {
  std::vector<map::MapInfo> maps;
  const map::MapInfo* current = nullptr;
  for (const map::MapInfo& m : store.maps()) {
    if (m.id == store.current_map()) {
      current = &m;
    } else {
      maps.push_back(m);
    }
  }
  if (current) maps.push_back(*current);
  return maps;
}

struct SectionPlan {
  std::uint32_t kind = 0;
  std::uint64_t bytes = 0;
};

std::vector<SectionPlan> plan_sections(const MapStore& store, const std::vector<map::MapInfo>& maps,
                                       map::DenseIndex& index, KeyframeLinks& links) {
  std::vector<SectionPlan> plan;
  plan.push_back({kMeta, kMetaBytes + kMetaMapBytes * maps.size()});
  for (const map::MapInfo& m : maps) {
    index.build(store, m.id);
    std::uint64_t kf_bytes = 0;
    for (int i = 0; i < index.num_keyframes(); ++i) {
      const KeyframeId kf = index.keyframe_at(i);
      gather_links(store, index, kf, links);
      kf_bytes += kKeyframeBytes + kFeatureBytes * static_cast<std::uint64_t>(store.keyframe(kf)->num_features) +
                  kCovisibleBytes * static_cast<std::uint64_t>(links.num_covisible) +
                  kLoopEdgeBytes * static_cast<std::uint64_t>(links.num_loops);
    }
    std::uint64_t lm_bytes = 0;
    for (int i = 0; i < index.num_landmarks(); ++i) {
      lm_bytes += kLandmarkBytes + kObservationBytes * static_cast<std::uint64_t>(
                                                           live_observations(store, index, index.landmark_at(i)));
    }
    plan.push_back({kKeyframes, kf_bytes});
    plan.push_back({kLandmarks, lm_bytes});
  }
  return plan;
}

std::uint64_t total_bytes(const std::vector<SectionPlan>& plan) {
  std::uint64_t n = kMapFileHeaderBytes + kTableEntryBytes * plan.size() + kMapFileTrailerBytes;
  for (const SectionPlan& s : plan) n += s.bytes;
  return n;
}

// ---------------------------------------------------------------------------------------------
// Writing: a buffered sink that hashes what passes through it.

class Sink {
 public:
  explicit Sink(int fd) : fd_(fd), buffer_(64 * 1024) {}
  void put(const void* p, std::size_t n) {
    file_hash_.update(p, n);
    section_hash_.update(p, n);
    written_ += n;
    const auto* b = static_cast<const std::uint8_t*>(p);
    while (n > 0) {
      const std::size_t k = std::min(n, buffer_.size() - used_);
      std::memcpy(buffer_.data() + used_, b, k);
      used_ += k;
      b += k;
      n -= k;
      if (used_ == buffer_.size()) flush();
    }
  }
  template <class T>
  void pod(T v) {
    put(&v, sizeof v);
  }
  void zeros(std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) pod<std::uint8_t>(0);
  }
  bool flush() {
    std::size_t off = 0;
    while (ok_ && off < used_) {
      const ssize_t w = ::write(fd_, buffer_.data() + off, used_ - off);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) {
        ok_ = false;
        break;
      }
      off += static_cast<std::size_t>(w);
    }
    used_ = 0;
    return ok_;
  }
  void begin_section() { section_hash_ = Fnv1a64(); }
  std::uint64_t section_checksum() const { return section_hash_.value(); }
  std::uint64_t file_checksum() const { return file_hash_.value(); }
  std::uint64_t written() const { return written_; }
  bool ok() const { return ok_; }

 private:
  int fd_;
  std::vector<std::uint8_t> buffer_;
  std::size_t used_ = 0;
  std::uint64_t written_ = 0;
  bool ok_ = true;
  Fnv1a64 file_hash_;
  Fnv1a64 section_hash_;
};

void put_pose(Sink& out, const geometry::SE3& T) {
  const Eigen::Quaterniond& q = T.so3().quaternion();
  out.pod(q.w());
  out.pod(q.x());
  out.pod(q.y());
  out.pod(q.z());
  for (int i = 0; i < 3; ++i) out.pod(T.translation()[i]);
}

void write_keyframes(Sink& out, const MapStore& store, const map::DenseIndex& index, KeyframeLinks& links) {
  for (int i = 0; i < index.num_keyframes(); ++i) {
    const KeyframeId id = index.keyframe_at(i);
    const map::Keyframe& k = *store.keyframe(id);
    gather_links(store, index, id, links);
    out.pod(k.timestamp_s);
    out.pod(static_cast<std::uint64_t>(k.frame_seq));
    put_pose(out, k.T_cw);
    out.pod(links.parent);
    out.pod(static_cast<std::uint32_t>(k.has_odometry ? 1 : 0));
    out.pod(k.odometry_x_m);
    out.pod(k.odometry_y_m);
    out.pod(k.odometry_theta_rad);
    out.pod(static_cast<std::uint32_t>(k.num_features));
    out.pod(static_cast<std::uint32_t>(links.num_covisible));
    out.pod(static_cast<std::uint32_t>(links.num_loops));
    for (const map::KeyframeFeature& f : store.features_of(id)) {
      out.pod(f.u);
      out.pod(f.v);
      out.pod(f.angle_deg);
      out.pod(f.level);
      out.pod(std::int16_t{0});
      out.put(f.descriptor.bytes.data(), f.descriptor.bytes.size());
    }
    for (int c = 0; c < links.num_covisible; ++c) {
      out.pod(links.covisible[static_cast<std::size_t>(c)].first);
      out.pod(links.covisible[static_cast<std::size_t>(c)].second);
    }
    for (int l = 0; l < links.num_loops; ++l) out.pod(links.loops[static_cast<std::size_t>(l)]);
  }
}

void write_landmarks(Sink& out, const MapStore& store, const map::DenseIndex& index) {
  for (int i = 0; i < index.num_landmarks(); ++i) {
    const LandmarkId id = index.landmark_at(i);
    const map::Landmark& l = *store.landmark(id);
    for (int a = 0; a < 3; ++a) out.pod(l.p_w[a]);
    out.put(l.descriptor.bytes.data(), l.descriptor.bytes.size());
    for (int a = 0; a < 3; ++a) out.pod(l.normal[a]);
    out.pod(l.min_distance);
    out.pod(l.max_distance);
    out.pod(static_cast<std::int32_t>(index.index_of(l.reference)));
    out.pod(static_cast<std::int32_t>(index.index_of(l.first)));
    out.pod(l.visible);
    out.pod(l.found);
    out.pod(static_cast<std::uint32_t>(live_observations(store, index, id)));
    for (const map::Observation& o : store.observations_of(id)) {
      const int k = index.index_of(o.keyframe);
      if (k < 0) continue;
      out.pod(static_cast<std::int32_t>(k));
      out.pod(o.keypoint);
    }
  }
}

Status sync_directory_of(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  const std::string dir = slash == std::string::npos ? "." : (slash == 0 ? "/" : path.substr(0, slash));
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) return io_error(path_error("open its directory " + dir, path));
  const int r = ::fsync(fd);
  ::close(fd);
  if (r != 0) return io_error(path_error("fsync its directory " + dir, path));
  return {};
}

// ---------------------------------------------------------------------------------------------
// Reading: a source of bytes (a file or memory) read in order, and the records' parsers.

class Source {
 public:
  virtual ~Source() = default;
  virtual std::uint64_t size() const = 0;
  // Reads n bytes at the current offset; false when fewer are there or the read fails.
  virtual bool read(void* p, std::size_t n) = 0;
  virtual bool seek(std::uint64_t offset) = 0;
};

class MemorySource : public Source {
 public:
  MemorySource(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint64_t size() const override { return size_; }
  bool read(void* p, std::size_t n) override {
    if (n > size_ - offset_) return false;
    if (n > 0) std::memcpy(p, data_ + offset_, n);
    offset_ += n;
    return true;
  }
  bool seek(std::uint64_t offset) override {
    if (offset > size_) return false;
    offset_ = static_cast<std::size_t>(offset);
    return true;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 0;
};

class FileSource : public Source {
 public:
  FileSource(std::FILE* f, std::uint64_t size) : f_(f), size_(size) {}
  ~FileSource() override { std::fclose(f_); }
  std::uint64_t size() const override { return size_; }
  bool read(void* p, std::size_t n) override { return n == 0 || std::fread(p, 1, n, f_) == n; }
  bool seek(std::uint64_t offset) override {
    return offset <= size_ && std::fseek(f_, static_cast<long>(offset), SEEK_SET) == 0;
  }

 private:
  std::FILE* f_;
  std::uint64_t size_;
};

struct TableEntry {
  std::uint32_t kind = 0;
  std::uint64_t offset = 0;
  std::uint64_t bytes = 0;
  std::uint64_t checksum = 0;
};

// Reads one section's records, counting what is left of it: a record that runs past the
// section's end is refused as corrupt, whatever the counts inside it said.
class Reader {
 public:
  Reader(Source& src, const TableEntry& section, std::string name)
      : src_(src), left_(section.bytes), name_(std::move(name)) {}
  template <class T>
  bool pod(T& v) {
    return bytes(&v, sizeof v);
  }
  bool bytes(void* p, std::size_t n) {
    if (!ok_ || n > left_ || !src_.read(p, n)) {
      ok_ = false;
      return false;
    }
    left_ -= n;
    return true;
  }
  // Whether n more records of `each` bytes can be in what is left (checked before storing them).
  bool fits(std::uint64_t n, std::uint64_t each) const { return each == 0 || n <= left_ / each; }
  std::uint64_t left() const { return left_; }
  bool ok() const { return ok_; }
  Status corrupt(const std::string& what) const { return corrupt_data("map file: " + name_ + ": " + what); }

 private:
  Source& src_;
  std::uint64_t left_;
  std::string name_;
  bool ok_ = true;
};

bool finite_all(const double* v, int n) {
  for (int i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  return true;
}

struct MetaMap {
  std::uint32_t id = 0;
  bool metric = false;
  std::uint32_t keyframes = 0;
  std::uint32_t landmarks = 0;
};

// What the keyframe records say about links, restored once the map's keyframes are all in.
struct PendingLinks {
  std::int32_t parent = -1;
  std::vector<std::pair<std::int32_t, std::int32_t>> covisible;  // (file index, weight)
  std::vector<std::int32_t> loops;
};

std::string section_name(std::uint32_t kind, std::size_t map) {
  switch (kind) {
    case kMeta: return "meta section";
    case kKeyframes: return "keyframes of map " + std::to_string(map);
    default: return "landmarks of map " + std::to_string(map);
  }
}

class Loader {
 public:
  // store: where run() loads the maps; check() reads only the capacity.
  Loader(Source& src, const MapFileContext& context, const map::MapCapacity& capacity, MapStore* store, std::string name)
      : src_(src), context_(context), capacity_(capacity), store_(store), name_(std::move(name)) {}

  // Everything that needs no store: the frame, the checksums, the meta section.
  Result<MapFileSummary> check() {
    if (Status s = check_frame(); !s.ok()) return s;
    if (Status s = check_checksums(); !s.ok()) return s;
    if (Status s = read_meta(); !s.ok()) return s;
    MapFileSummary summary;
    summary.bytes = src_.size();
    summary.maps = static_cast<int>(maps_.size());
    for (const MetaMap& m : maps_) {
      summary.keyframes += static_cast<int>(m.keyframes);
      summary.landmarks += static_cast<int>(m.landmarks);
    }
    summary.current_map = maps_.empty() ? 0 : maps_.back().id;
    return summary;
  }

  // The frame, the checksums and what the file records it was written with (compared with nothing).
  Result<MapFileContext> recorded() {
    if (Status s = check_frame(); !s.ok()) return s;
    if (Status s = check_checksums(); !s.ok()) return s;
    if (!src_.seek(table_[0].offset)) return corrupt("meta section unreadable");
    Reader r(src_, table_[0], "meta section");
    MapFileContext recorded;
    recorded.vocabulary_checksum = vocabulary_checksum_;
    std::uint32_t maps = 0;
    if (Status s = read_meta_head(r, maps, recorded.camera); !s.ok()) return s;
    return recorded;
  }

  Result<MapFileSummary> run() {
    if (store_->stats().keyframes != 0 || store_->stats().landmarks != 0) {
      return invalid_argument("map file: loading needs an empty map store");
    }
    Result<MapFileSummary> summary = check();
    if (!summary.ok()) return summary;
    for (std::size_t m = 0; m < maps_.size(); ++m) {
      if (Status s = read_map(m); !s.ok()) {
        store_->reset();
        return s;
      }
    }
    return summary;
  }

 private:
  Status corrupt(const std::string& what) const { return corrupt_data("map file " + name_ + ": " + what); }

  // The header, trailer and table: sizes and offsets that agree with each other and the file.
  Status check_frame() {
    const std::uint64_t size = src_.size();
    std::array<std::uint8_t, kMapFileHeaderBytes> h{};
    if (size < kMapFileHeaderBytes || !src_.seek(0) || !src_.read(h.data(), h.size())) {
      return corrupt("shorter than its " + std::to_string(kMapFileHeaderBytes) + "-byte header (" +
                     std::to_string(size) + " bytes)");
    }
    if (std::memcmp(h.data(), kMapFileMagic, sizeof kMapFileMagic) != 0) return corrupt("not a map file (bad magic)");
    std::uint32_t version = 0, header_bytes = 0, sections = 0;
    std::uint64_t file_bytes = 0, header_checksum = 0;
    std::memcpy(&version, h.data() + 8, 4);
    std::memcpy(&header_bytes, h.data() + 12, 4);
    std::memcpy(&sections, h.data() + 16, 4);
    std::memcpy(&file_bytes, h.data() + 24, 8);
    std::memcpy(&vocabulary_checksum_, h.data() + 32, 8);
    std::memcpy(&header_checksum, h.data() + 56, 8);
    if (fnv1a64(h.data(), 56) != header_checksum) return corrupt("header checksum mismatch");
    if (version != kMapFileVersion) {
      return unsupported("map file " + name_ + ": format version " + std::to_string(version) + ", this build reads " +
                         std::to_string(kMapFileVersion));
    }
    if (header_bytes != kMapFileHeaderBytes) return corrupt("header of " + std::to_string(header_bytes) + " bytes");
    if (file_bytes != size) {
      return corrupt((size < file_bytes ? "truncated: " : "longer than written: ") + std::to_string(size) +
                     " bytes, the header says " + std::to_string(file_bytes));
    }
    if (sections < 1 || sections > 1 + 2 * kMaxMaps || (sections - 1) % 2 != 0) {
      return corrupt(std::to_string(sections) + " sections");
    }
    const std::uint64_t fixed = kMapFileHeaderBytes + kTableEntryBytes * sections + kMapFileTrailerBytes;
    if (size < fixed) return corrupt("too short for its " + std::to_string(sections) + " sections' table");
    std::array<std::uint8_t, kMapFileTrailerBytes> t{};
    if (!src_.seek(size - kMapFileTrailerBytes) || !src_.read(t.data(), t.size())) return corrupt("trailer unreadable");
    if (std::memcmp(t.data(), kMapFileTrailerMagic, sizeof kMapFileTrailerMagic) != 0) return corrupt("bad trailer magic");
    std::uint64_t table_offset = 0;
    std::memcpy(&table_offset, t.data() + 8, 8);
    std::memcpy(&file_checksum_, t.data() + 16, 8);
    std::uint64_t trailer_reserved = 0;
    std::memcpy(&trailer_reserved, t.data() + 24, 8);
    if (trailer_reserved != 0) return corrupt("trailer's reserved field is not 0");
    if (table_offset != size - kMapFileTrailerBytes - kTableEntryBytes * sections) {
      return corrupt("table offset " + std::to_string(table_offset) + " does not end at the trailer");
    }
    if (!src_.seek(table_offset)) return corrupt("table unreadable");
    table_.resize(sections);
    std::uint64_t expect = kMapFileHeaderBytes;
    for (std::uint32_t i = 0; i < sections; ++i) {
      std::array<std::uint8_t, kTableEntryBytes> e{};
      if (!src_.read(e.data(), e.size())) return corrupt("table unreadable");
      TableEntry& s = table_[i];
      std::memcpy(&s.kind, e.data(), 4);
      std::memcpy(&s.offset, e.data() + 8, 8);
      std::memcpy(&s.bytes, e.data() + 16, 8);
      std::memcpy(&s.checksum, e.data() + 24, 8);
      const std::uint32_t want = i == 0 ? kMeta : (i % 2 == 1 ? kKeyframes : kLandmarks);
      if (s.kind != want) return corrupt("section " + std::to_string(i) + " of kind " + std::to_string(s.kind));
      if (s.offset != expect || s.bytes > table_offset - s.offset) {
        return corrupt("section " + std::to_string(i) + " at " + std::to_string(s.offset) + ", " +
                       std::to_string(s.bytes) + " bytes, does not follow the one before within the file");
      }
      expect = s.offset + s.bytes;
    }
    if (expect != table_offset) return corrupt("the sections do not end at the table");
    return {};
  }

  // Every byte before the trailer against the file checksum, each section against its own (the
  // sections follow each other from the header to the table, check_frame saw to that).
  Status check_checksums() {
    Fnv1a64 file;
    std::array<std::uint8_t, 16 * 1024> buf{};
    const auto stream = [&](std::uint64_t from, std::uint64_t to, Fnv1a64* section) {
      if (!src_.seek(from)) return false;
      for (std::uint64_t at = from; at < to;) {
        const auto n = static_cast<std::size_t>(std::min<std::uint64_t>(buf.size(), to - at));
        if (!src_.read(buf.data(), n)) return false;
        file.update(buf.data(), n);
        if (section) section->update(buf.data(), n);
        at += n;
      }
      return true;
    };
    if (!stream(0, kMapFileHeaderBytes, nullptr)) return corrupt("unreadable");
    for (std::size_t i = 0; i < table_.size(); ++i) {
      const TableEntry& s = table_[i];
      Fnv1a64 section;
      if (!stream(s.offset, s.offset + s.bytes, &section)) return corrupt("unreadable");
      if (section.value() != s.checksum) return corrupt(section_name(s.kind, (i + 1) / 2 - 1) + ": checksum mismatch");
    }
    const std::uint64_t table_offset = table_.back().offset + table_.back().bytes;
    if (!stream(table_offset, src_.size() - kMapFileTrailerBytes, nullptr)) return corrupt("unreadable");
    if (file.value() != file_checksum_) return corrupt("file checksum mismatch");
    return {};
  }

  // The meta section's fields before its maps: the map count (against the table) and the camera.
  Status read_meta_head(Reader& r, std::uint32_t& maps, MapFileCamera& cam) {
    std::uint32_t reserved = 0, width = 0, height = 0, levels = 0;
    r.pod(maps);
    r.pod(reserved);
    r.pod(cam.fx);
    r.pod(cam.fy);
    r.pod(cam.cx);
    r.pod(cam.cy);
    r.pod(width);
    r.pod(height);
    r.pod(levels);
    r.pod(cam.scale_factor);
    if (!r.ok()) return r.corrupt("shorter than its fields");
    if (maps != (table_.size() - 1) / 2) {
      return r.corrupt(std::to_string(maps) + " maps for " + std::to_string(table_.size()) + " sections");
    }
    cam.width = static_cast<int>(std::min<std::uint32_t>(width, 1u << 30));
    cam.height = static_cast<int>(std::min<std::uint32_t>(height, 1u << 30));
    cam.levels = static_cast<int>(std::min<std::uint32_t>(levels, 1u << 30));
    return {};
  }

  Status read_meta() {
    if (vocabulary_checksum_ != context_.vocabulary_checksum) {
      return unsupported("map file " + name_ + ": made with another place-recognition vocabulary (checksum " +
                         std::to_string(vocabulary_checksum_) + ", this one " +
                         std::to_string(context_.vocabulary_checksum) + ")");
    }
    if (!src_.seek(table_[0].offset)) return corrupt("meta section unreadable");
    Reader r(src_, table_[0], "meta section");
    std::uint32_t maps = 0;
    MapFileCamera cam;
    if (Status s = read_meta_head(r, maps, cam); !s.ok()) return s;
    if (!(cam == context_.camera)) {
      return unsupported("map file " + name_ + ": made with another camera (" + std::to_string(cam.width) + "x" +
                         std::to_string(cam.height) + ", fx " + std::to_string(cam.fx) + ", " +
                         std::to_string(cam.levels) + " levels; this one " + std::to_string(context_.camera.width) +
                         "x" + std::to_string(context_.camera.height) + ", fx " + std::to_string(context_.camera.fx) +
                         ", " + std::to_string(context_.camera.levels) + " levels)");
    }
    std::uint64_t keyframes = 0, landmarks = 0;
    for (std::uint32_t i = 0; i < maps; ++i) {
      MetaMap m;
      std::uint32_t metric = 0;
      r.pod(m.id);
      r.pod(metric);
      r.pod(m.keyframes);
      r.pod(m.landmarks);
      if (!r.ok()) return r.corrupt("shorter than its maps");
      if (metric > 1) return r.corrupt("map " + std::to_string(i) + "'s metric flag " + std::to_string(metric));
      m.metric = metric == 1;
      for (const MetaMap& o : maps_) {
        if (o.id == m.id) return r.corrupt("map id " + std::to_string(m.id) + " twice");
      }
      keyframes += m.keyframes;
      landmarks += m.landmarks;
      maps_.push_back(m);
    }
    if (r.left() != 0) return r.corrupt(std::to_string(r.left()) + " bytes after the maps");
    const map::MapCapacity& cap = capacity_;
    if (keyframes > static_cast<std::uint64_t>(cap.max_keyframes) ||
        landmarks > static_cast<std::uint64_t>(cap.max_landmarks)) {
      return corrupt(std::to_string(keyframes) + " keyframes and " + std::to_string(landmarks) +
                     " landmarks, beyond the map store's capacity (" + std::to_string(cap.max_keyframes) + ", " +
                     std::to_string(cap.max_landmarks) + "; slam.capacity.*)");
    }
    return {};
  }

  Status read_map(std::size_t m) {
    const MetaMap& meta = maps_[m];
    if (m > 0) store_->start_map();
    if (Status s = store_->restore_map_id(map::MapId{meta.id}); !s.ok()) return corrupt(s.message());
    store_->set_metric(store_->current_map(), meta.metric);
    if (Status s = read_keyframes(m); !s.ok()) return s;
    if (Status s = read_landmarks(m); !s.ok()) return s;
    return restore_links(m);
  }

  Status read_keyframes(std::size_t m) {
    const TableEntry& section = table_[1 + 2 * m];
    if (!src_.seek(section.offset)) return corrupt("unreadable");
    Reader r(src_, section, section_name(kKeyframes, m));
    const std::uint32_t n = maps_[m].keyframes;
    if (!r.fits(n, kKeyframeBytes)) return r.corrupt(std::to_string(n) + " keyframes do not fit its bytes");
    const int max_features = capacity_.max_keypoints_per_keyframe;
    features_.resize(static_cast<std::size_t>(max_features));
    keyframes_.clear();
    pending_.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) {
      double t = 0.0;
      std::uint64_t seq = 0;
      std::array<double, 7> pose{};
      std::int32_t parent = 0;
      std::uint32_t has_odometry = 0, nf = 0, nc = 0, nl = 0;
      std::array<double, 3> odo{};
      r.pod(t);
      r.pod(seq);
      for (double& v : pose) r.pod(v);
      r.pod(parent);
      r.pod(has_odometry);
      for (double& v : odo) r.pod(v);
      r.pod(nf);
      r.pod(nc);
      r.pod(nl);
      const std::string which = "keyframe " + std::to_string(i);
      if (!r.ok()) return r.corrupt(which + " runs past the section's end");
      if (!std::isfinite(t) || !finite_all(pose.data(), 7) || !finite_all(odo.data(), 3) || has_odometry > 1) {
        return r.corrupt(which + ": a non-finite time, pose or odometry, or a bad odometry flag");
      }
      const Eigen::Quaterniond q(pose[0], pose[1], pose[2], pose[3]);
      if (std::abs(q.norm() - 1.0) > 1e-6) return r.corrupt(which + ": its rotation is not a unit quaternion");
      if (parent < -1 || parent >= static_cast<std::int32_t>(n)) return r.corrupt(which + ": parent out of range");
      if (nf > static_cast<std::uint32_t>(max_features) || nc > map::kMaxCovisible || nl > map::kMaxLoopEdges) {
        return r.corrupt(which + ": " + std::to_string(nf) + " features, " + std::to_string(nc) + " covisible, " +
                         std::to_string(nl) + " loop edges: beyond the limits");
      }
      if (!r.fits(nf, kFeatureBytes)) return r.corrupt(which + "'s features run past the section's end");
      for (std::uint32_t f = 0; f < nf; ++f) {
        map::KeyframeFeature& kp = features_[f];
        std::int16_t pad = 0;
        r.pod(kp.u);
        r.pod(kp.v);
        r.pod(kp.angle_deg);
        r.pod(kp.level);
        r.pod(pad);
        r.bytes(kp.descriptor.bytes.data(), kp.descriptor.bytes.size());
        if (!std::isfinite(kp.u) || !std::isfinite(kp.v) || !std::isfinite(kp.angle_deg) || kp.level < 0 ||
            kp.level >= context_.camera.levels) {
          return r.corrupt(which + ": feature " + std::to_string(f) + " has a non-finite position or a level out of range");
        }
      }
      PendingLinks& p = pending_[i];
      p.parent = parent;
      p.covisible.clear();
      p.loops.clear();
      for (std::uint32_t c = 0; c < nc; ++c) {
        std::int32_t k = 0, w = 0;
        r.pod(k);
        r.pod(w);
        if (k < 0 || k >= static_cast<std::int32_t>(n)) return r.corrupt(which + ": a covisible keyframe out of range");
        p.covisible.emplace_back(k, w);
      }
      for (std::uint32_t l = 0; l < nl; ++l) {
        std::int32_t k = 0;
        r.pod(k);
        if (k < 0 || k >= static_cast<std::int32_t>(n)) return r.corrupt(which + ": a loop edge out of range");
        p.loops.push_back(k);
      }
      if (!r.ok()) return r.corrupt(which + " runs past the section's end");
      const geometry::SE3 T_cw(geometry::SO3::from_unit_quaternion(q), geometry::Vec3(pose[4], pose[5], pose[6]));
      Result<KeyframeId> id = store_->add_keyframe(t, seq, T_cw, features_.data(), static_cast<int>(nf));
      if (!id.ok()) return corrupt(which + " of map " + std::to_string(m) + ": " + id.status().message());
      map::Keyframe& k = *store_->keyframe(*id);
      k.has_odometry = has_odometry == 1;
      k.odometry_x_m = odo[0];
      k.odometry_y_m = odo[1];
      k.odometry_theta_rad = odo[2];
      keyframes_.push_back(*id);
    }
    if (r.left() != 0) return r.corrupt(std::to_string(r.left()) + " bytes after the last keyframe");
    return {};
  }

  Status read_landmarks(std::size_t m) {
    const TableEntry& section = table_[2 + 2 * m];
    if (!src_.seek(section.offset)) return corrupt("unreadable");
    Reader r(src_, section, section_name(kLandmarks, m));
    const std::uint32_t n = maps_[m].landmarks;
    const auto nk = static_cast<std::int32_t>(keyframes_.size());
    if (!r.fits(n, kLandmarkBytes)) return r.corrupt(std::to_string(n) + " landmarks do not fit its bytes");
    for (std::uint32_t i = 0; i < n; ++i) {
      std::array<double, 3> p{}, normal{};
      features::Descriptor d{};
      float dmin = 0.0f, dmax = 0.0f;
      std::int32_t reference = 0, first = 0;
      std::uint32_t visible = 0, found = 0, no = 0;
      for (double& v : p) r.pod(v);
      r.bytes(d.bytes.data(), d.bytes.size());
      for (double& v : normal) r.pod(v);
      r.pod(dmin);
      r.pod(dmax);
      r.pod(reference);
      r.pod(first);
      r.pod(visible);
      r.pod(found);
      r.pod(no);
      const std::string which = "landmark " + std::to_string(i);
      if (!r.ok()) return r.corrupt(which + " runs past the section's end");
      if (!finite_all(p.data(), 3) || !finite_all(normal.data(), 3) || !std::isfinite(dmin) || !std::isfinite(dmax) ||
          dmin < 0.0f || dmax < dmin) {
        return r.corrupt(which + ": a non-finite position or normal, or a bad distance range");
      }
      if (reference < -1 || reference >= nk || first < -1 || first >= nk) {
        return r.corrupt(which + ": its reference or first keyframe out of range");
      }
      if (no > map::kMaxObservations) return r.corrupt(which + ": " + std::to_string(no) + " observations");
      const auto kf_at = [&](std::int32_t k) { return k < 0 ? KeyframeId{} : keyframes_[static_cast<std::size_t>(k)]; };
      Result<LandmarkId> id = store_->add_landmark(geometry::Vec3(p[0], p[1], p[2]), d, kf_at(first));
      if (!id.ok()) return r.corrupt(which + ": " + id.status().message());
      for (std::uint32_t o = 0; o < no; ++o) {
        std::int32_t k = 0;
        std::uint32_t kp = 0;
        r.pod(k);
        r.pod(kp);
        if (!r.ok()) return r.corrupt(which + "'s observations run past the section's end");
        if (k < 0 || k >= nk || kp > static_cast<std::uint32_t>(capacity_.max_keypoints_per_keyframe)) {
          return r.corrupt(which + ": an observation out of range");
        }
        if (Status s = store_->add_observation(*id, kf_at(k), static_cast<int>(kp)); !s.ok()) {
          return r.corrupt(which + ": " + s.message());
        }
      }
      map::Landmark& l = *store_->landmark(*id);
      l.normal = geometry::Vec3(normal[0], normal[1], normal[2]);
      l.min_distance = dmin;
      l.max_distance = dmax;
      l.reference = kf_at(reference);
      l.first = kf_at(first);
      l.visible = visible;
      l.found = found;
    }
    if (r.left() != 0) return r.corrupt(std::to_string(r.left()) + " bytes after the last landmark");
    return {};
  }

  Status restore_links(std::size_t m) {
    const std::string where = "map " + std::to_string(m) + ": ";
    int roots = 0;
    for (std::size_t i = 0; i < keyframes_.size(); ++i) {
      const PendingLinks& p = pending_[i];
      if (p.parent < 0) ++roots;
      const KeyframeId parent = p.parent < 0 ? KeyframeId{} : keyframes_[static_cast<std::size_t>(p.parent)];
      if (Status s = store_->restore_parent(keyframes_[i], parent); !s.ok()) return corrupt(where + s.message());
      covisible_.clear();
      for (const auto& [k, w] : p.covisible) covisible_.push_back({keyframes_[static_cast<std::size_t>(k)], w});
      if (Status s = store_->restore_covisibility(keyframes_[i], Span<const Covisible>(covisible_.data(),
                                                                                      static_cast<int>(covisible_.size())));
          !s.ok()) {
        return corrupt(where + s.message());
      }
      for (std::int32_t l : p.loops) {
        if (Status s = store_->add_loop_edge(keyframes_[i], keyframes_[static_cast<std::size_t>(l)]); !s.ok()) {
          return corrupt(where + s.message());
        }
      }
    }
    if (!keyframes_.empty() && roots != 1) return corrupt(where + std::to_string(roots) + " spanning-tree roots");
    return {};
  }

  Source& src_;
  const MapFileContext& context_;
  const map::MapCapacity& capacity_;
  MapStore* store_;
  std::string name_;
  std::uint64_t vocabulary_checksum_ = 0;
  std::uint64_t file_checksum_ = 0;
  std::vector<TableEntry> table_;
  std::vector<MetaMap> maps_;
  std::vector<map::KeyframeFeature> features_;
  std::vector<KeyframeId> keyframes_;  // the map's keyframes by file index
  std::vector<PendingLinks> pending_;
  std::vector<Covisible> covisible_;
};

}  // namespace

std::string map_file_backup_path(const std::string& path) { return path + ".bak"; }

std::uint64_t map_file_bytes(const map::MapStore& store) {
  map::DenseIndex index(store);
  KeyframeLinks links;
  return total_bytes(plan_sections(store, file_maps(store), index, links));
}

Result<MapFileSummary> save_map_file(const map::MapStore& store, const MapFileContext& context, const std::string& path) {
  const std::vector<map::MapInfo> maps = file_maps(store);
  map::DenseIndex index(store);
  auto links = std::make_unique<KeyframeLinks>();
  const std::vector<SectionPlan> plan = plan_sections(store, maps, index, *links);
  const std::uint64_t bytes = total_bytes(plan);

  const std::string tmp = path + ".tmp";
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return io_error(path_error("open " + tmp, path));
  Sink out(fd);
  // header
  std::array<std::uint8_t, kMapFileHeaderBytes> h{};
  std::memcpy(h.data(), kMapFileMagic, sizeof kMapFileMagic);
  const std::uint32_t version = kMapFileVersion, header_bytes = kMapFileHeaderBytes;
  const auto sections = static_cast<std::uint32_t>(plan.size());
  std::memcpy(h.data() + 8, &version, 4);
  std::memcpy(h.data() + 12, &header_bytes, 4);
  std::memcpy(h.data() + 16, &sections, 4);
  std::memcpy(h.data() + 24, &bytes, 8);
  std::memcpy(h.data() + 32, &context.vocabulary_checksum, 8);
  const std::uint64_t header_checksum = fnv1a64(h.data(), 56);
  std::memcpy(h.data() + 56, &header_checksum, 8);
  out.put(h.data(), h.size());

  std::vector<TableEntry> table;
  table.reserve(plan.size());
  const auto begin = [&](std::uint32_t kind) {
    out.begin_section();
    table.push_back({kind, out.written(), 0, 0});
  };
  const auto end = [&]() {
    table.back().bytes = out.written() - table.back().offset;
    table.back().checksum = out.section_checksum();
  };
  begin(kMeta);
  out.pod(static_cast<std::uint32_t>(maps.size()));
  out.pod(std::uint32_t{0});
  out.pod(context.camera.fx);
  out.pod(context.camera.fy);
  out.pod(context.camera.cx);
  out.pod(context.camera.cy);
  out.pod(static_cast<std::uint32_t>(context.camera.width));
  out.pod(static_cast<std::uint32_t>(context.camera.height));
  out.pod(static_cast<std::uint32_t>(context.camera.levels));
  out.pod(context.camera.scale_factor);
  for (const map::MapInfo& m : maps) {
    index.build(store, m.id);
    out.pod(m.id.value);
    out.pod(static_cast<std::uint32_t>(m.metric ? 1 : 0));
    out.pod(static_cast<std::uint32_t>(index.num_keyframes()));
    out.pod(static_cast<std::uint32_t>(index.num_landmarks()));
  }
  end();
  for (const map::MapInfo& m : maps) {
    index.build(store, m.id);
    begin(kKeyframes);
    write_keyframes(out, store, index, *links);
    end();
    begin(kLandmarks);
    write_landmarks(out, store, index);
    end();
  }
  const std::uint64_t table_offset = out.written();
  for (const TableEntry& e : table) {
    out.pod(e.kind);
    out.pod(std::uint32_t{0});
    out.pod(e.offset);
    out.pod(e.bytes);
    out.pod(e.checksum);
  }
  const std::uint64_t file_checksum = out.file_checksum();
  out.put(kMapFileTrailerMagic, sizeof kMapFileTrailerMagic);
  out.pod(table_offset);
  out.pod(file_checksum);
  out.pod(std::uint64_t{0});
  const bool written = out.flush();
  const bool synced = written && ::fsync(fd) == 0;
  const int close_errno = ::close(fd) == 0 ? 0 : errno;
  if (!written || !synced || close_errno != 0) {
    const Status s = io_error(path_error(!written ? "write " + tmp : (!synced ? "fsync " + tmp : "close " + tmp), path));
    ::unlink(tmp.c_str());
    return s;
  }
  if (out.written() != bytes) {
    ::unlink(tmp.c_str());
    return internal_error("map file " + path + ": wrote " + std::to_string(out.written()) + " bytes, planned " +
                          std::to_string(bytes));
  }
  // keep the previous file as the backup: a second name of the old PATH made beside it, then
  // renamed over PATH.bak, so at every moment PATH.bak is an old file or the one before
  const std::string bak = map_file_backup_path(path);
  if (::access(path.c_str(), F_OK) == 0) {
    const std::string bak_tmp = bak + ".tmp";
    if (::unlink(bak_tmp.c_str()) != 0 && errno != ENOENT) return io_error(path_error("remove " + bak_tmp, path));
    if (::link(path.c_str(), bak_tmp.c_str()) != 0) return io_error(path_error("keep the previous file as " + bak_tmp, path));
    if (::rename(bak_tmp.c_str(), bak.c_str()) != 0) {
      const Status s = io_error(path_error("rename " + bak_tmp + " to " + bak, path));
      ::unlink(bak_tmp.c_str());
      return s;
    }
  }
  if (::rename(tmp.c_str(), path.c_str()) != 0) {
    const Status s = io_error(path_error("rename " + tmp, path));
    ::unlink(tmp.c_str());
    return s;
  }
  if (Status s = sync_directory_of(path); !s.ok()) return s;
  MapFileSummary summary;
  summary.bytes = bytes;
  summary.maps = static_cast<int>(maps.size());
  for (const map::MapInfo& m : maps) {
    summary.keyframes += static_cast<int>(m.keyframes);
    summary.landmarks += static_cast<int>(m.landmarks);
  }
  summary.current_map = store.current_map().value;
  return summary;
}

namespace {

// The file at `path` as a source; kNotFound when it does not exist.
Result<std::unique_ptr<FileSource>> open_source(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) {
    const bool missing = errno == ENOENT;
    const std::string m = path_error("open", path);
    return missing ? Status(not_found(m)) : Status(io_error(m));
  }
  const long size = std::fseek(f, 0, SEEK_END) == 0 ? std::ftell(f) : -1;
  if (size < 0) {
    std::fclose(f);
    return io_error(path_error("size", path));
  }
  return std::make_unique<FileSource>(f, static_cast<std::uint64_t>(size));
}

}  // namespace

Result<MapFileSummary> check_map_file(const std::string& path, const MapFileContext& context,
                                      const map::MapCapacity& capacity) {
  Result<std::unique_ptr<FileSource>> src = open_source(path);
  if (!src.ok()) return src.status();
  return Loader(**src, context, capacity, nullptr, path).check();
}

Result<MapFileContext> read_map_file_context(const std::string& path) {
  Result<std::unique_ptr<FileSource>> src = open_source(path);
  if (!src.ok()) return src.status();
  const MapFileContext any;
  const map::MapCapacity none{};
  return Loader(**src, any, none, nullptr, path).recorded();
}

Result<MapFileSummary> load_map_file(const std::string& path, const MapFileContext& context, map::MapStore& store) {
  Result<std::unique_ptr<FileSource>> src = open_source(path);
  if (!src.ok()) return src.status();
  return Loader(**src, context, store.capacity(), &store, path).run();
}

Result<MapFileSummary> load_map_bytes(const std::uint8_t* data, std::size_t size, const MapFileContext& context,
                                      map::MapStore& store) {
  MemorySource src(data, size);
  return Loader(src, context, store.capacity(), &store, "(memory)").run();
}

}  // namespace ale::io
