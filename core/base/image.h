// Image views (non-owning) and pooled images (owning, move-only).
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "core/base/memory_pool.h"
#include "core/base/status.h"

namespace ale {

// A non-owning view of a 2-D array of T: row y starts at data + y * stride (stride in elements).
template <class T>
struct ImageView {
  T* data = nullptr;
  int width = 0;
  int height = 0;
  int stride = 0;

  T* row(int y) const { return data + static_cast<std::ptrdiff_t>(y) * stride; }
  T& at(int x, int y) const { return row(y)[x]; }
  bool empty() const { return data == nullptr || width <= 0 || height <= 0; }

  // The rectangle [x, x+w) x [y, y+h); the caller keeps it inside the view (see contains()).
  ImageView sub(int x, int y, int w, int h) const { return {row(y) + x, w, h, stride}; }
  bool contains(int x, int y, int w, int h) const {
    return x >= 0 && y >= 0 && w >= 0 && h >= 0 && x + w <= width && y + h <= height;
  }

  // A view of mutable pixels converts to a view of const pixels, not the other way round.
  template <class U = T, class = std::enable_if_t<!std::is_const_v<U>>>
  operator ImageView<const U>() const {  // NOLINT: implicit on purpose
    return {data, width, height, stride};
  }
};

using GrayView = ImageView<const std::uint8_t>;
using MutableGrayView = ImageView<std::uint8_t>;

// ok when the view points somewhere, is at least 1x1 and its stride covers a row.
template <class T>
Status check_view(const ImageView<T>& v, const char* what) {
  if (v.data == nullptr) return invalid_argument(std::string(what) + ": null image");
  if (v.width <= 0 || v.height <= 0)
    return invalid_argument(std::string(what) + ": empty image " + std::to_string(v.width) + "x" +
                            std::to_string(v.height));
  if (v.stride < v.width)
    return invalid_argument(std::string(what) + ": stride " + std::to_string(v.stride) + " < width " +
                            std::to_string(v.width));
  return {};
}

// Row stride (bytes) used for pooled 8-bit images: rows start 16-byte aligned for NEON.
constexpr int aligned_stride(int width) { return (width + 15) & ~15; }

// An 8-bit grey image whose pixels live in one block of a BlockPool. Move-only; the block goes
// back to the pool when the image is destroyed. The pool must outlive the image.
class PooledImage {
 public:
  PooledImage() = default;
  ~PooledImage() { reset(); }
  PooledImage(PooledImage&& other) noexcept { *this = std::move(other); }
  PooledImage& operator=(PooledImage&& other) noexcept;
  PooledImage(const PooledImage&) = delete;
  PooledImage& operator=(const PooledImage&) = delete;

  // Fails with kInvalidArgument if the size does not fit the pool's blocks and with
  // kOutOfMemory if the pool has no free block.
  static Result<PooledImage> create(BlockPool& pool, int width, int height);

  MutableGrayView view() { return {data_, width_, height_, stride_}; }
  GrayView view() const { return {data_, width_, height_, stride_}; }
  int width() const { return width_; }
  int height() const { return height_; }
  int stride() const { return stride_; }
  bool empty() const { return data_ == nullptr; }
  void reset();

 private:
  BlockPool* pool_ = nullptr;
  std::uint8_t* data_ = nullptr;
  int width_ = 0;
  int height_ = 0;
  int stride_ = 0;
};

// An 8-bit grey image on the heap, for tools, tests and start-up work; the per-frame path uses
// PooledImage instead.
struct GrayImage {
  std::vector<std::uint8_t> pixels;  // width * height, stride == width
  int width = 0;
  int height = 0;

  GrayImage() = default;
  GrayImage(int w, int h, std::uint8_t fill = 0)
      : pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill), width(w), height(h) {}
  MutableGrayView view() { return {pixels.data(), width, height, width}; }
  GrayView view() const { return {pixels.data(), width, height, width}; }
};

// Copies `src` into `dst` row by row; both must have the same size.
void copy_pixels(GrayView src, MutableGrayView dst);

}  // namespace ale
