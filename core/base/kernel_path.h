// Which implementation of the image kernels runs: the portable scalar reference (the
// specification) or the build's vector path, which must be bit-exact with it: NEON on ARM, SSE2 on
// x86_64 (the x86_64 baseline, so always available there). A build has one vector path.
//
// Each kernel library keeps one dispatch table of its kernels per path (enhance::kernels(),
// features::kernels()), filled at compile time; kAuto selects, once per process, the table of
// active_kernel_path(). So ALE_FORCE_REF=1 reaches every kernel.
//
// One tail policy for every vector kernel (the role of libyuv's "Any" wrappers): the vector code
// runs on whole vectors, and a row's remainder is done by one more vector that overlaps the one
// before it (a map rewrites the overlapped outputs with the same values; a reduction or a
// corner list masks the overlapped lanes out). Inputs narrower than one vector run the reference.
// Where a kernel departs from this (its header says so), the overlap costs more ARM instructions
// than its scalar tail on the sizes the extractor feeds it (docs/performance.md, "Kernel tails").
#pragma once

namespace ale {

enum class KernelPath { kAuto, kReference, kNeon, kSse2 };
const char* to_string(KernelPath path);

// True when the environment variable ALE_FORCE_REF is "1" (read once per process): every
// kernel then runs its reference path, for equivalence tests and for bisecting a vector bug.
bool reference_kernels_forced();

// The vector path this build has (kNeon, kSse2, else kReference), whatever ALE_FORCE_REF says:
// what equivalence tests compare the reference with.
KernelPath compiled_vector_path();

// What kAuto means in this process: compiled_vector_path() unless the reference is forced.
KernelPath active_kernel_path();

// `path` with kAuto resolved by active_kernel_path() and a vector path this build lacks replaced by
// kReference: the table a request for `path` gets.
KernelPath resolve_kernel_path(KernelPath path);

// Whether this build has `path` (kAuto and kReference always).
bool kernel_path_compiled(KernelPath path);

}  // namespace ale
