// An image in a buffer of its own whose rows are `stride` bytes apart and whose first row starts
// `offset` bytes in, every byte first set to `fill` (so a kernel that writes past a row's end or
// reads padding shows), with `slack` bytes more at the end.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/base/image.h"

namespace ale::test {

struct PaddedImage {
  std::vector<std::uint8_t> bytes;
  MutableGrayView view;
};

inline PaddedImage padded_image(int width, int height, int stride, int offset, std::uint8_t fill, std::size_t slack = 0) {
  PaddedImage p;
  p.bytes.assign(static_cast<std::size_t>(stride) * static_cast<std::size_t>(height) + static_cast<std::size_t>(offset) + slack,
                 fill);
  p.view = {p.bytes.data() + offset, width, height, stride};
  return p;
}

}  // namespace ale::test
