// The map file: every map a MapStore holds (keyframes with their features, landmarks with their
// observations, the spanning tree, covisibility and loop edges), so the next run starts from it.
//
// Layout (integers and floats little-endian, as every target ale-slam runs on):
//   header   64 bytes: magic "ALEMAP\r\n", u32 format version (1), u32 header bytes (64),
//            u32 section count, u32 reserved (0), u64 file bytes, u64 vocabulary checksum (the
//            place-recognition vocabulary's, 0 without one), u64 reserved (0), u64 reserved,
//            u64 header checksum (FNV-1a 64 of the 56 bytes before it)
//   sections in the table's order (their records below)
//   table    section count x 32 bytes: u32 kind, u32 reserved, u64 offset, u64 bytes,
//            u64 checksum (FNV-1a 64 of the section's bytes)
//   trailer  32 bytes: magic "ALEMAPND", u64 table offset, u64 file checksum (FNV-1a 64 of every
//            byte before the trailer), u64 reserved
// The file's size and every section's are known before the first byte is written (the records'
// sizes follow from the counts), so the header states the size and a truncated file is refused
// by its first read; the checksums, which are known only after, come in the table and trailer.
//
// Sections: one meta, then a keyframes and a landmarks section for each map, the maps oldest
// first and the current map last. Records:
//   meta       u32 maps, u32 reserved (0), the camera (f64 fx fy cx cy, u32 width height, u32
//              pyramid levels, f32 scale factor), then per map u32 id, u32 metric, u32 keyframes,
//              u32 landmarks
//   keyframe   (in DenseIndex order: their index in the map is what the map's records name)
//              f64 timestamp, u64 frame sequence, T_cw as f64 x4 quaternion (w x y z) and f64 x3
//              translation, i32 parent (-1: the root), u32 odometry flag, f64 x3 odometry (x, y,
//              theta), u32 features, u32 covisible, u32 loop edges; then the features (f32 u v
//              angle, i16 level, i16 0, 32 descriptor bytes), the covisible keyframes (i32
//              keyframe, i32 weight; strongest first, ties by index) and the loop edges (i32)
//   landmark   (DenseIndex order) f64 x3 position, 32 descriptor bytes, f64 x3 normal, f32 min
//              and max distance, i32 reference and first keyframe (-1: none), u32 visible, u32
//              found, u32 observations; then each observation (i32 keyframe, u32 keypoint)
//
// Saving streams the store through a 64 KB buffer (no second copy of the map) into PATH.tmp,
// fsyncs it, keeps the previous PATH as PATH.bak (a hard link made as PATH.bak.tmp and renamed
// over PATH.bak) and renames PATH.tmp over PATH, then fsyncs the directory: at every moment PATH
// is a whole file, old or new, and PATH.bak one of the files before.
// Loading reads the file twice, streaming: first every checksum, then the records, each count
// checked against the store's capacity and every index against the counts before it is used,
// into an empty store; on any error the store is emptied again. Loading never writes a file.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "core/base/status.h"
#include "core/map/map_store.h"

namespace ale::io {

constexpr char kMapFileMagic[8] = {'A', 'L', 'E', 'M', 'A', 'P', '\r', '\n'};
constexpr char kMapFileTrailerMagic[8] = {'A', 'L', 'E', 'M', 'A', 'P', 'N', 'D'};
constexpr std::uint32_t kMapFileVersion = 1;
constexpr std::size_t kMapFileHeaderBytes = 64;
constexpr std::size_t kMapFileTrailerBytes = 32;

// The camera the keyframes' undistorted keypoints and the landmarks' distance ranges belong to;
// a map is refused by a camera that differs.
struct MapFileCamera {
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0;
  int width = 0, height = 0;
  int levels = 0;
  float scale_factor = 0.0f;
  friend bool operator==(const MapFileCamera& a, const MapFileCamera& b) {
    return a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy && a.width == b.width &&
           a.height == b.height && a.levels == b.levels && a.scale_factor == b.scale_factor;
  }
};

// What a file was written with and must be loaded with.
struct MapFileContext {
  MapFileCamera camera;
  std::uint64_t vocabulary_checksum = 0;  // 0: no vocabulary
};

struct MapFileSummary {
  std::uint64_t bytes = 0;
  int maps = 0;
  int keyframes = 0;
  int landmarks = 0;
  std::uint32_t current_map = 0;  // its id
};

// The bytes a file of `store` takes (what save_map_file will write).
std::uint64_t map_file_bytes(const map::MapStore& store);

// Writes every map of `store` to `path` as above. kIoError naming the path and the step (open,
// write, fsync, link, rename) when the OS refuses; PATH is then as it was.
Result<MapFileSummary> save_map_file(const map::MapStore& store, const MapFileContext& context, const std::string& path);

// Loads `path` into `store`, which must hold no keyframe (kInvalidArgument otherwise).
// kNotFound when there is no file; kCorruptData naming what is wrong (a truncated file, a
// checksum, a count beyond the store's capacity, an index out of range); kUnsupported for another
// format version, another vocabulary or another camera. The file's current map is the store's.
Result<MapFileSummary> load_map_file(const std::string& path, const MapFileContext& context, map::MapStore& store);
// Everything load_map_file checks before it touches a store (the frame, every checksum, the
// version, vocabulary and camera, the counts against `capacity`): a file that passes loads unless
// its records themselves are inconsistent (which a file this code wrote never is).
Result<MapFileSummary> check_map_file(const std::string& path, const MapFileContext& context,
                                      const map::MapCapacity& capacity);
// The camera and vocabulary checksum `path` was written with, read after the checks that need
// neither (the frame, every checksum, the version): what a tool without the daemon's camera and
// vocabulary loads the file with. kNotFound, kCorruptData and kUnsupported as load_map_file.
Result<MapFileContext> read_map_file_context(const std::string& path);
// The same from bytes in memory (the fuzz target's entry).
Result<MapFileSummary> load_map_bytes(const std::uint8_t* data, std::size_t size, const MapFileContext& context,
                                      map::MapStore& store);

// The backup save_map_file keeps: PATH.bak.
std::string map_file_backup_path(const std::string& path);

}  // namespace ale::io
