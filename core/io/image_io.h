// Reading and writing image files: PNG (libpng) and JPEG (libjpeg-turbo), both linked
// statically from Debian's packages. Colour is converted to grey (BT.601 luma, rounded).
// Every failure names the file and what is wrong with it; nothing here throws or aborts.
// A file format, not a device: it sits beside core/base, below hal/, so the replay backend, the
// tools and the tests read and write images without reaching into a backend.
#pragma once

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

// Writes an 8-bit grey PNG.
Status write_png(const std::string& path, GrayView image);
// Writes an 8-bit RGB PNG; `rgb` holds width*3 bytes per row, rows `stride_bytes` apart.
Status write_png_rgb(const std::string& path, const std::uint8_t* rgb, int width, int height, int stride_bytes);

}  // namespace ale::io

