// The image decoders (core/io/image_io.h decode_gray(): PNG through libpng, JPEG through
// libjpeg-turbo, chosen by content) on arbitrary bytes. A decode either fails with a message or
// gives an image of at least one pixel whose every byte is readable (ASan checks the reads).
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "core/io/image_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  ale::GrayImage image;
  if (!ale::io::decode_gray(data, size, "fuzz input", image).ok()) return 0;
  const ale::GrayView v = image.view();
  if (v.width < 1 || v.height < 1) std::abort();
  unsigned sum = 0;
  for (int y = 0; y < v.height; ++y)
    for (int x = 0; x < v.width; ++x) sum += v.row(y)[x];
  volatile unsigned keep = sum;  // so that the reads are not optimised away
  (void)keep;
  return 0;
}
