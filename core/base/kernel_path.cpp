#include "core/base/kernel_path.h"

#include <cstdlib>
#include <cstring>

namespace ale {

const char* to_string(KernelPath path) {
  switch (path) {
    case KernelPath::kAuto: return "auto";
    case KernelPath::kReference: return "reference";
    case KernelPath::kNeon: return "neon";
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

KernelPath resolve_kernel_path(bool neon_compiled) {
  return neon_compiled && !reference_kernels_forced() ? KernelPath::kNeon : KernelPath::kReference;
}

}  // namespace ale
