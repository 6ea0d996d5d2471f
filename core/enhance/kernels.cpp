#include "core/enhance/kernels.h"

namespace ale::enhance {

namespace {

using namespace internal;

constexpr Kernels kReferenceKernels{KernelPath::kReference, &histogram_ref, &tile_histograms_ref,
                                    &ClaheContext::apply_ref, &min_gap_ref,  &apply_lut_ref,
                                    &moments_ref,             &moments_ref,  &binomial3_ref};
#if defined(__ARM_NEON)
// The histograms and the LUT are 32-bit ARM assembly; 64-bit ARM would run their references.
#if defined(__arm__)
constexpr auto kHistogramNeon = &histogram_neon;
constexpr auto kTileHistogramsNeon = &tile_histograms_neon;
constexpr auto kApplyLutNeon = &apply_lut_neon;
#else
constexpr auto kHistogramNeon = &histogram_ref;
constexpr auto kTileHistogramsNeon = &tile_histograms_ref;
constexpr auto kApplyLutNeon = &apply_lut_ref;
#endif
constexpr Kernels kNeonKernels{KernelPath::kNeon,        kHistogramNeon, kTileHistogramsNeon,
                               &ClaheContext::apply_neon, &min_gap_neon,  kApplyLutNeon,
                               &moments_neon,             &small_moments_neon, &binomial3_neon};
#endif

const Kernels& table(KernelPath resolved) {
#if defined(__ARM_NEON)
  if (resolved == KernelPath::kNeon) return kNeonKernels;
#endif
  (void)resolved;
  return kReferenceKernels;
}

}  // namespace

namespace internal {

const Kernels* const active_kernels = &table(active_kernel_path());

const Kernels& kernels_for(KernelPath path) { return table(resolve_kernel_path(path)); }

}  // namespace internal

}  // namespace ale::enhance
