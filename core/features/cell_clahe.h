// The per-cell CLAHE of the ALE ladder (a cell plus the FAST margin, contrast-guided, spec
// section 5) without the machinery of a general CLAHE: the tile edge at any pyramid scale exceeds
// most cells, so their grid is a single tile, and a single-tile CLAHE is one histogram, one clipped
// CDF and one look-up table; the interpolation of core/enhance reduces to a fixed rescaling of that
// table. The result is bit-exact with enhance::contrast_guided_clahe() (tested); grids of more than
// one tile go to it.
#pragma once

#include <array>
#include <cstdint>

#include "core/base/image.h"
#include "core/base/status.h"
#include "core/enhance/clahe.h"
#include "core/enhance/params.h"

namespace ale::features {

class CellClahe {
 public:
  // dst = enhance::contrast_guided_clahe(p, scale, src) (dst must not overlap src).
  Status apply(const enhance::LevelClaheParams& p, double scale, GrayView src, MutableGrayView dst);
  // Whether the last apply() took the single-tile path.
  bool last_was_single_tile() const { return single_; }

 private:
  enhance::ClaheContext general_;
  std::array<std::uint32_t, 256> hist_{};
  std::array<std::uint8_t, 256> lut_{};
  bool single_ = false;
};

}  // namespace ale::features
