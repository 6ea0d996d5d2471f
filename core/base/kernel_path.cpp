#include "core/base/kernel_path.h"

#include <cstdlib>
#include <cstring>

namespace ale {

const char* to_string(KernelPath path) {
  switch (path) {
    case KernelPath::kAuto: return "auto";
    case KernelPath::kReference: return "reference";
    case KernelPath::kNeon: return "neon";
    case KernelPath::kSse2: return "sse2";
  }
  return "?";
}

bool reference_kernels_forced() {
  // The environment does not change while frames are processed.
  static const bool forced = [] {
    const char* v = std::getenv("ALE_FORCE_REF");
    return v != nullptr && std::strcmp(v, "1") == 0;
  }();
  return forced;
}

KernelPath compiled_vector_path() {
#if defined(__ARM_NEON)
  return KernelPath::kNeon;
#elif defined(__SSE2__)
  return KernelPath::kSse2;
#else
  return KernelPath::kReference;
#endif
}

KernelPath active_kernel_path() {
  return reference_kernels_forced() ? KernelPath::kReference : compiled_vector_path();
}

bool kernel_path_compiled(KernelPath path) {
  return path == KernelPath::kAuto || path == KernelPath::kReference || path == compiled_vector_path();
}

KernelPath resolve_kernel_path(KernelPath path) {
  if (path == KernelPath::kAuto) return active_kernel_path();
  return kernel_path_compiled(path) ? path : KernelPath::kReference;
}

}  // namespace ale
