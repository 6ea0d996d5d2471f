// The feature kernels' dispatch table: one entry per kernel, one table per path (reference, NEON,
// SSE2), all filled at compile time in kernels.cpp. kernels() gives the table of
// active_kernel_path() (ALE_FORCE_REF=1: the reference), chosen before main(); kernels(path)
// the table of a given path, or the reference's when this build lacks it (its `path` says which).
// The tail policy all vector kernels follow is in core/base/kernel_path.h.
//
// An SSE2 table entry is the reference where a kernel has no SSE2 version (GCC's -O3
// vectorisation of the reference is as fast on x86 for the Gaussian; FAST's row detector, BRIEF;
// the Hamming distance, which SSE2 has no bit count for).
#pragma once

#include "core/base/kernel_path.h"
#include "core/features/blur.h"
#include "core/features/brief.h"
#include "core/features/fast.h"
#include "core/features/orientation.h"
#include "core/features/pyramid.h"
#include "core/features/score_map.h"

namespace ale::features {

struct Kernels {
  KernelPath path = KernelPath::kReference;
  decltype(&internal::fast9_row_ref) fast9_row = nullptr;      // fast.h
  decltype(&internal::fast9_score_ref) fast9_score = nullptr;  // fast.h
  decltype(&internal::score_rect_ref) score_rect = nullptr;    // score_map.h
  decltype(&internal::blur_rect_ref) blur_rect = nullptr;      // blur.h
  decltype(&internal::resize_ref) resize = nullptr;            // pyramid.h
  decltype(&internal::ic_moments_ref) ic_moments = nullptr;    // orientation.h
  decltype(&internal::describe_ref) describe = nullptr;        // brief.h
  decltype(&internal::hamming_ref) hamming = nullptr;          // brief.h
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

}  // namespace ale::features
