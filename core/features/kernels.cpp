#include "core/features/kernels.h"

namespace ale::features {

namespace {

using namespace internal;

constexpr Kernels kReferenceKernels{KernelPath::kReference, &fast9_row_ref, &fast9_score_ref, &score_rect_ref,
                                    &blur_rect_ref, &resize_ref, &ic_moments_ref, &describe_ref, &hamming_ref};
#if defined(__ARM_NEON)
// The Gaussian and BRIEF have 32-bit ARM kernels only (inline assembly); 64-bit ARM would run their
// references.
#if defined(__arm__)
constexpr auto kBlurNeon = &blur_rect_neon;
#else
constexpr auto kBlurNeon = &blur_rect_ref;
#endif
#if defined(__thumb2__)
constexpr auto kDescribeNeon = &describe_neon;
#else
constexpr auto kDescribeNeon = &describe_ref;
#endif
constexpr Kernels kNeonKernels{KernelPath::kNeon, &fast9_row_neon, &fast9_score_neon, &score_rect_neon,
                               kBlurNeon,         &resize_neon,    &ic_moments_neon,  kDescribeNeon,
                               &hamming_neon};
#endif
#if defined(__SSE2__)
constexpr Kernels kSse2Kernels{KernelPath::kSse2, &fast9_row_sse2, &fast9_score_ref, &score_rect_sse2,
                               &blur_rect_ref, &resize_sse2, &ic_moments_sse2, &describe_ref, &hamming_ref};
#endif

const Kernels& table(KernelPath resolved) {
#if defined(__ARM_NEON)
  if (resolved == KernelPath::kNeon) return kNeonKernels;
#endif
#if defined(__SSE2__)
  if (resolved == KernelPath::kSse2) return kSse2Kernels;
#endif
  (void)resolved;
  return kReferenceKernels;
}

}  // namespace

namespace internal {

const Kernels* const active_kernels = &table(active_kernel_path());

const Kernels& kernels_for(KernelPath path) { return table(resolve_kernel_path(path)); }

}  // namespace internal

}  // namespace ale::features
