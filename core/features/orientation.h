// Orientation by intensity centroid (spec section 6; ic_angle_deg() in brief.h): the angle of the
// moments m10 = sum u I(x + u, y + v) and m01 = sum v I(x + u, y + v) over the disk of radius
// kPatchRadius, row v spanning |u| <= disk_half_width(v). The moments are integers, so the NEON
// kernel (orientation_neon.cpp: the 32 pixels x - 15 .. x + 16 of two rows v and -v per step,
// masked to the disk) is bit-exact with the scalar reference (orientation_ref.cpp) and both give
// the same angle; dispatch through kernels.h.
#pragma once

#include "core/base/image.h"
#include "core/features/fast.h"

namespace ale::features {

struct Moments {
  int m10 = 0;
  int m01 = 0;
};

// The largest u with u^2 + v^2 <= r^2 + r (a disk of radius r + 1/2, r = kPatchRadius).
int disk_half_width(int v);

// The disk around (x, y) must lie inside `image`.
Moments ic_moments(GrayView image, int x, int y, KernelPath path = KernelPath::kAuto);

namespace internal {
Moments ic_moments_ref(GrayView image, int x, int y);
// Also reads pixel x + 16 of every row (the reference when the image has no such column).
Moments ic_moments_neon(GrayView image, int x, int y);
// The same window on x86 (orientation_sse2.cpp).
Moments ic_moments_sse2(GrayView image, int x, int y);
}  // namespace internal

}  // namespace ale::features
