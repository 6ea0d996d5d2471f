// Which implementation of an image kernel runs: the portable scalar reference (the
// specification) or a vector path that must be bit-exact with it: NEON on ARM, SSE2 on x86_64
// (the x86_64 baseline, so always available there). A build has at most one vector path per kernel.
#pragma once

namespace ale {

enum class KernelPath { kAuto, kReference, kNeon, kSse2 };
const char* to_string(KernelPath path);

// True when the environment variable ALE_FORCE_REF is "1" (read once per process): every
// kernel then runs its reference path, for equivalence tests and for bisecting a NEON bug.
bool reference_kernels_forced();

// The vector path compiled in (kNeon, else kSse2) unless the reference is forced, else kReference.
KernelPath resolve_kernel_path(bool neon_compiled, bool sse2_compiled = false);

}  // namespace ale
