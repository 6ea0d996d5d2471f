// Reading and writing image files: PNG (libpng) and JPEG (libjpeg-turbo), both linked
// statically from Debian's packages. Colour is converted to grey (BT.601 luma, rounded).
// Every failure names the file and what is wrong with it; nothing here throws or aborts.
// A file format, not a device: it sits beside core/base, below hal/, so the replay backend, the
// tools and the tests read and write images without reaching into a backend.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/base/image.h"
#include "core/base/status.h"

namespace ale::io {

struct ImageFileInfo {
  int width = 0;
  int height = 0;
  int channels = 0;  // in the file: 1 grey, 2 grey+alpha, 3 RGB, 4 RGBA
};

// Reads the header only.
Result<ImageFileInfo> probe_image(const std::string& path);

// Decodes a PNG or JPEG (chosen by content, not by extension) to 8-bit grey on the heap.
Status read_gray(const std::string& path, GrayImage& out);

// read_gray() of a file already in memory, the `size` bytes at `data`; `name` (the file's, or what
// the bytes are) heads every error message.
Status decode_gray(const std::uint8_t* data, std::size_t size, const std::string& name, GrayImage& out);

// Decodes into a caller-provided view of exactly the file's size (the replay camera's pooled
// buffers). kInvalidArgument when the sizes differ.
Status read_gray_into(const std::string& path, MutableGrayView out);

// Buffers reused from one decode to the next, so a replay stops allocating once the first frame
// has been read (the replay camera keeps one).
struct DecodeScratch {
  std::vector<std::uint8_t> file;  // the whole encoded file
  std::vector<std::uint8_t> rows;  // colour rows before conversion to grey
};

// read_gray_into() with caller-owned scratch buffers.
Status read_gray_into(const std::string& path, MutableGrayView out, DecodeScratch& scratch);

// How hard the PNG encoder works: zlib's level (0 stored .. 9 smallest; -1 zlib's default, 6) and
// the row filter (adaptive: libpng tries each per row; up: the difference to the row above, one
// pass). Level 1 with the up filter is what a recorder wants: a few times faster than the
// default for files some 10-20 % larger (docs/daemon.md has the figures).
struct PngWriteOptions {
  int compression_level = -1;
  bool adaptive_filter = true;  // false: the up filter on every row
};

// Writes an 8-bit grey PNG. An error (kIoError) names the file and why (a full disk says "No space
// left on device"); a partly written file is removed.
Status write_png(const std::string& path, GrayView image);
Status write_png(const std::string& path, GrayView image, const PngWriteOptions& options);
// Writes an 8-bit RGB PNG; `rgb` holds width*3 bytes per row, rows `stride_bytes` apart.
Status write_png_rgb(const std::string& path, const std::uint8_t* rgb, int width, int height, int stride_bytes);

}  // namespace ale::io

