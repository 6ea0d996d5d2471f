// The enhancement kernels' dispatch table: one entry per kernel, one table per path, filled at
// compile time in kernels.cpp. kernels() gives the table of active_kernel_path() (ALE_FORCE_REF=1:
// the reference), chosen before main(); kernels(path) the table of a given path, or the
// reference's when this build lacks it (its `path` says which). There are no SSE2 kernels here:
// on x86 every path is the reference. The tail policy is in core/base/kernel_path.h.
#pragma once

#include "core/base/kernel_path.h"
#include "core/enhance/clahe.h"
#include "core/enhance/gamma.h"
#include "core/enhance/grading.h"
#include "core/enhance/noise.h"

namespace ale::enhance {

struct Kernels {
  KernelPath path = KernelPath::kReference;
  decltype(&internal::histogram_ref) histogram = nullptr;              // clahe.h
  decltype(&internal::tile_histograms_ref) tile_histograms = nullptr;  // clahe.h
  decltype(&ClaheContext::apply_ref) clahe_apply = nullptr;            // clahe.h
  decltype(&internal::min_gap_ref) min_gap = nullptr;                  // clahe.h (the cells' table)
  decltype(&internal::apply_lut_ref) apply_lut = nullptr;              // gamma.h
  decltype(&internal::moments_ref) moments = nullptr;                  // grading.h
  decltype(&internal::moments_ref) small_moments = nullptr;            // grading.h (the cells)
  decltype(&internal::binomial3_ref) binomial3 = nullptr;              // noise.h
};

namespace internal {
// The table of active_kernel_path(), set before main() (kernels.cpp): what kernels() reads, in
// three instructions on ARM, where an out-of-line call with a guarded static cost about nine.
extern const Kernels* const active_kernels;
const Kernels& kernels_for(KernelPath path);
}  // namespace internal

inline const Kernels& kernels(KernelPath path = KernelPath::kAuto) {
  return path == KernelPath::kAuto ? *internal::active_kernels : internal::kernels_for(path);
}

}  // namespace ale::enhance
