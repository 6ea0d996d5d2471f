// The camera and vocabulary the map-file fuzz target loads with and its generated seeds are saved
// with (make_seeds.cpp), so a seed loads and the fuzzer starts from files that get past the checks.
#pragma once

#include "core/io/map_file.h"
#include "core/map/map_store.h"

namespace ale::fuzz {

inline io::MapFileContext map_file_context() {
  io::MapFileContext c;
  c.camera = io::MapFileCamera{200.0, 200.0, 160.0, 120.0, 320, 240, 8, 1.2f};
  c.vocabulary_checksum = 0x1234;
  return c;
}

// Small enough to allocate quickly, large enough for the seeds.
constexpr map::MapCapacity kMapFileCapacity{16, 400, 64};

}  // namespace ale::fuzz
