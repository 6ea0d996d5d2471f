#include "core/base/image.h"

#include <cstring>
#include <string>
#include <utility>

namespace ale {

PooledImage& PooledImage::operator=(PooledImage&& other) noexcept {
  if (this != &other) {
    reset();
    std::swap(pool_, other.pool_);
    std::swap(data_, other.data_);
    std::swap(width_, other.width_);
    std::swap(height_, other.height_);
    std::swap(stride_, other.stride_);
  }
  return *this;
}

Result<PooledImage> PooledImage::create(BlockPool& pool, int width, int height) {
  if (width <= 0 || height <= 0 || width > (1 << 15) || height > (1 << 15))
    return invalid_argument("image size " + std::to_string(width) + "x" + std::to_string(height) +
                            " out of range");
  const int stride = aligned_stride(width);
  const std::size_t bytes = static_cast<std::size_t>(stride) * static_cast<std::size_t>(height);
  if (bytes > pool.block_bytes())
    return invalid_argument("image " + std::to_string(width) + "x" + std::to_string(height) + " needs " +
                            std::to_string(bytes) + " bytes, pool blocks hold " +
                            std::to_string(pool.block_bytes()));
  Result<void*> block = pool.allocate();
  if (!block.ok()) return block.status();
  PooledImage img;
  img.pool_ = &pool;
  img.data_ = static_cast<std::uint8_t*>(*block);
  img.width_ = width;
  img.height_ = height;
  img.stride_ = stride;
  return img;
}

void PooledImage::reset() {
  if (pool_ != nullptr && data_ != nullptr) {
    // The block came from this pool, so giving it back cannot fail.
    (void)pool_->free(data_);
  }
  pool_ = nullptr;
  data_ = nullptr;
  width_ = height_ = stride_ = 0;
}

void copy_pixels(GrayView src, MutableGrayView dst) {
  for (int y = 0; y < src.height && y < dst.height; ++y)
    std::memcpy(dst.row(y), src.row(y), static_cast<std::size_t>(src.width < dst.width ? src.width : dst.width));
}

}  // namespace ale
