// Applying a 256-entry LUT in C: the specification gamma_neon.cpp reproduces (gamma.h).
#include "core/enhance/gamma.h"

namespace ale::enhance::internal {

void apply_lut_ref(GrayView src, MutableGrayView dst, const std::uint8_t* lut) {
  for (int y = 0; y < src.height; ++y) lut_row_words(src.row(y), dst.row(y), 0, src.width, lut);
}

}  // namespace ale::enhance::internal
