// A whole file read into memory, for binary formats parsed from bytes (the place-recognition
// vocabulary, core/place/vocabulary.h): the tools and the daemon read, the core parses.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/base/status.h"

namespace ale::io {

// kNotFound naming the path when it cannot be opened, kIoError when reading fails.
Status read_file_bytes(const std::string& path, std::vector<std::uint8_t>& out);

}  // namespace ale::io
