// The kernel dispatch tables (core/enhance/kernels.h, core/features/kernels.h): kAuto's table is
// the reference's, entry by entry, when ALE_FORCE_REF=1 (ctest runs this binary a second time with
// it set), and otherwise the build's vector table; in the armhf build every NEON entry is a NEON
// kernel, not the reference, so a build that lost NEON, or a kernel that slipped out of the table,
// fails here.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "core/base/kernel_path.h"
#include "core/enhance/kernels.h"
#include "core/features/kernels.h"

namespace ale {
namespace {

using Entries = std::vector<std::pair<std::string, bool>>;  // entry name, equal in both tables

// Adding an entry to a table changes its size: list it below as well.
static_assert(sizeof(features::Kernels) == 9 * sizeof(void*), "features::Kernels changed: update this test");
static_assert(sizeof(enhance::Kernels) == 10 * sizeof(void*), "enhance::Kernels changed: update this test");

Entries compare(const features::Kernels& a, const features::Kernels& b) {
  return {{"fast9_row", a.fast9_row == b.fast9_row},    {"fast9_score", a.fast9_score == b.fast9_score},
          {"score_rect", a.score_rect == b.score_rect}, {"blur_rect", a.blur_rect == b.blur_rect},
          {"resize", a.resize == b.resize},             {"ic_moments", a.ic_moments == b.ic_moments},
          {"describe", a.describe == b.describe},       {"hamming", a.hamming == b.hamming}};
}

Entries compare(const enhance::Kernels& a, const enhance::Kernels& b) {
  return {{"histogram", a.histogram == b.histogram},       {"tile_histograms", a.tile_histograms == b.tile_histograms},
          {"clahe_apply", a.clahe_apply == b.clahe_apply}, {"min_gap", a.min_gap == b.min_gap},
          {"apply_lut", a.apply_lut == b.apply_lut},       {"moments", a.moments == b.moments},
          {"small_moments", a.small_moments == b.small_moments}, {"binomial3", a.binomial3 == b.binomial3}};
}

template <typename Table>
void expect_all_equal(const Table& a, const Table& b, const char* what) {
  for (const auto& [name, equal] : compare(a, b)) EXPECT_TRUE(equal) << what << ": " << name;
}

template <typename Table>
void expect_none_equal(const Table& a, const Table& b, const char* what) {
  for (const auto& [name, equal] : compare(a, b)) EXPECT_FALSE(equal) << what << ": " << name;
}

TEST(KernelTable, EveryEntryIsSet) {
  for (const KernelPath p : {KernelPath::kAuto, KernelPath::kReference, KernelPath::kNeon, KernelPath::kSse2}) {
    const features::Kernels& f = features::kernels(p);
    // A null entry would equal the default-constructed table's.
    for (const auto& [name, equal] : compare(f, features::Kernels{})) EXPECT_FALSE(equal) << to_string(p) << " " << name;
    const enhance::Kernels& e = enhance::kernels(p);
    for (const auto& [name, equal] : compare(e, enhance::Kernels{})) EXPECT_FALSE(equal) << to_string(p) << " " << name;
  }
}

TEST(KernelTable, AutoIsTheReferenceWhenForcedElseTheVectorPath) {
  const features::Kernels& f = features::kernels();
  const enhance::Kernels& e = enhance::kernels();
  std::printf("ALE_FORCE_REF %s, vector path %s\n", reference_kernels_forced() ? "1" : "unset",
              to_string(compiled_vector_path()));
  if (reference_kernels_forced()) {
    EXPECT_EQ(active_kernel_path(), KernelPath::kReference);
    EXPECT_EQ(f.path, KernelPath::kReference);
    EXPECT_EQ(e.path, KernelPath::kReference);
    expect_all_equal(f, features::kernels(KernelPath::kReference), "features");
    expect_all_equal(e, enhance::kernels(KernelPath::kReference), "enhance");
    return;
  }
  EXPECT_EQ(active_kernel_path(), compiled_vector_path());
  EXPECT_EQ(f.path, compiled_vector_path());
  expect_all_equal(f, features::kernels(compiled_vector_path()), "features");
  expect_all_equal(e, enhance::kernels(compiled_vector_path()), "enhance");
}

TEST(KernelTable, TheVectorTablesHoldVectorKernels) {
#if defined(__arm__) && !defined(__ARM_NEON)
  FAIL() << "an ARM build without NEON: the product's kernels would all run their references";
#elif defined(__ARM_NEON) && defined(__arm__) && defined(__thumb2__)
  EXPECT_EQ(compiled_vector_path(), KernelPath::kNeon);
  EXPECT_EQ(features::kernels(KernelPath::kNeon).path, KernelPath::kNeon);
  EXPECT_EQ(enhance::kernels(KernelPath::kNeon).path, KernelPath::kNeon);
  expect_none_equal(features::kernels(KernelPath::kNeon), features::kernels(KernelPath::kReference), "features");
  expect_none_equal(enhance::kernels(KernelPath::kNeon), enhance::kernels(KernelPath::kReference), "enhance");
#elif defined(__SSE2__)
  // SSE2 kernels exist for the score map, the resize and the moments (and FAST's row, which is the
  // score map's); the rest run the reference on x86 (features/kernels.h says why).
  const features::Kernels& sse2 = features::kernels(KernelPath::kSse2);
  const features::Kernels& ref = features::kernels(KernelPath::kReference);
  EXPECT_EQ(sse2.path, KernelPath::kSse2);
  EXPECT_NE(sse2.score_rect, ref.score_rect);
  EXPECT_NE(sse2.fast9_row, ref.fast9_row);
  EXPECT_NE(sse2.resize, ref.resize);
  EXPECT_NE(sse2.ic_moments, ref.ic_moments);
  EXPECT_EQ(sse2.blur_rect, ref.blur_rect);
  EXPECT_EQ(sse2.hamming, ref.hamming);
  EXPECT_EQ(enhance::kernels(KernelPath::kSse2).path, KernelPath::kReference);
#else
  GTEST_SKIP() << "no vector path in this build";
#endif
}

TEST(KernelTable, APathTheBuildLacksGetsTheReference) {
  for (const KernelPath p : {KernelPath::kNeon, KernelPath::kSse2}) {
    if (kernel_path_compiled(p)) continue;
    EXPECT_EQ(features::kernels(p).path, KernelPath::kReference) << to_string(p);
    expect_all_equal(features::kernels(p), features::kernels(KernelPath::kReference), to_string(p));
    EXPECT_EQ(enhance::kernels(p).path, KernelPath::kReference) << to_string(p);
    expect_all_equal(enhance::kernels(p), enhance::kernels(KernelPath::kReference), to_string(p));
  }
}

}  // namespace
}  // namespace ale
