// Which implementation of an image kernel runs: the portable scalar reference (the
// specification) or the NEON path that must be bit-exact with it.
#pragma once

namespace ale {

enum class KernelPath { kAuto, kReference, kNeon };
const char* to_string(KernelPath path);

// True when the environment variable ALE_FORCE_REF is "1" (read once per process): every
// kernel then runs its reference path, for equivalence tests and for bisecting a NEON bug.
bool reference_kernels_forced();

// kNeon when the NEON path was compiled in and the reference is not forced, else kReference.
KernelPath resolve_kernel_path(bool neon_compiled);

}  // namespace ale
