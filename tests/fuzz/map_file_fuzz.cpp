// load_map_bytes() on arbitrary bytes (core/io/map_file.h). The input's first byte is a switch:
// bit 0 set, the file's size field and its checksums (the header's, each section's in the table,
// the whole file's in the trailer) are made right for the bytes, so the fuzzer gets past them to
// the records; clear, the bytes are loaded as they are (the frame and checksum checks). A file
// that loads must leave a consistent store: every observation linked both ways, every link
// (parent, covisible, loop edge) to a live keyframe of the same map; a refused one an empty store.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/base/checksum.h"
#include "core/io/map_file.h"
#include "map_file_context.h"

namespace {

using namespace ale;

void check(bool ok) {
  if (!ok) std::abort();
}

template <class T>
T load_at(const std::vector<std::uint8_t>& b, std::size_t at) {
  T v{};
  std::memcpy(&v, b.data() + at, sizeof v);
  return v;
}

template <class T>
void store_at(std::vector<std::uint8_t>& b, std::size_t at, T v) {
  std::memcpy(b.data() + at, &v, sizeof v);
}

// The size field and every checksum made right, where the table can be found.
void repair(std::vector<std::uint8_t>& b) {
  const std::size_t size = b.size();
  if (size < io::kMapFileHeaderBytes + io::kMapFileTrailerBytes) return;
  store_at<std::uint64_t>(b, 24, size);
  store_at<std::uint64_t>(b, 56, fnv1a64(b.data(), 56));
  const std::uint32_t sections = load_at<std::uint32_t>(b, 16);
  const std::uint64_t table = load_at<std::uint64_t>(b, size - io::kMapFileTrailerBytes + 8);
  // the table ends at the trailer (compared without an addition that could wrap)
  const std::size_t room = size - io::kMapFileHeaderBytes - io::kMapFileTrailerBytes;
  if (sections <= 1024 && 32ull * sections <= room && table == size - io::kMapFileTrailerBytes - 32ull * sections) {
    for (std::uint32_t i = 0; i < sections; ++i) {
      const std::size_t entry = static_cast<std::size_t>(table) + 32u * i;
      const std::uint64_t offset = load_at<std::uint64_t>(b, entry + 8);
      const std::uint64_t bytes = load_at<std::uint64_t>(b, entry + 16);
      if (offset <= table && bytes <= table - offset) {
        store_at<std::uint64_t>(b, entry + 24, fnv1a64(b.data() + offset, static_cast<std::size_t>(bytes)));
      }
    }
  }
  store_at<std::uint64_t>(b, size - io::kMapFileTrailerBytes + 16, fnv1a64(b.data(), size - io::kMapFileTrailerBytes));
}

void check_consistent(const map::MapStore& store) {
  store.for_each_keyframe([&](map::KeyframeId id, const map::Keyframe& k) {
    const map::Keyframe* parent = store.keyframe(k.parent);
    check(!k.parent.valid() || (parent && parent->map_id == k.map_id));
    for (const map::Covisible& c : store.covisible_of(id)) {
      const map::Keyframe* o = store.keyframe(c.keyframe);
      check(o && o->map_id == k.map_id && c.weight > 0);
    }
    for (map::KeyframeId l : store.loop_edges(id)) check(store.keyframe(l) != nullptr);
    const Span<const map::LandmarkId> lms = store.keypoint_landmarks_of(id);
    for (int i = 0; i < lms.size(); ++i) {
      if (!lms[i].valid()) continue;
      bool back = false;
      for (const map::Observation& o : store.observations_of(lms[i])) back |= o.keyframe == id && o.keypoint == static_cast<std::uint32_t>(i);
      check(back);
    }
  });
  store.for_each_landmark([&](map::LandmarkId id, const map::Landmark& l) {
    check(l.p_w.allFinite());
    for (const map::Observation& o : store.observations_of(id)) {
      const map::Keyframe* k = store.keyframe(o.keyframe);
      check(k && k->map_id == l.map_id && store.keypoint_landmarks_of(o.keyframe)[static_cast<int>(o.keypoint)] == id);
    }
  });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static map::MapStore store(fuzz::kMapFileCapacity);
  std::vector<std::uint8_t> file(data + 1, data + size);
  if ((data[0] & 1) != 0) repair(file);
  const Result<io::MapFileSummary> loaded = io::load_map_bytes(file.data(), file.size(), fuzz::map_file_context(), store);
  if (loaded.ok()) {
    check(static_cast<int>(store.stats().keyframes) == loaded->keyframes);
    check(static_cast<int>(store.stats().landmarks) == loaded->landmarks);
    check_consistent(store);
  } else {
    check(store.stats().keyframes == 0 && store.stats().landmarks == 0);
  }
  store.reset();
  return 0;
}
