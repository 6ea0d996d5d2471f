// FAST-9 dispatch and argument checks shared by both kernels.
#include <string>

#include "core/features/fast.h"
#include "core/features/score_map.h"

namespace ale::features {

FastPath fast_auto_path() { return resolve_kernel_path(fast_neon_compiled(), fast_sse2_compiled()); }

FastPath fast_vector_path() {
  if (fast_neon_compiled()) return FastPath::kNeon;
  return fast_sse2_compiled() ? FastPath::kSse2 : FastPath::kReference;
}

Status fast9_detect(GrayView image, PixelRect rect, int threshold, MutableGrayView scores,
                    std::vector<FastCorner>& corners, FastPath path) {
  ALE_RETURN_IF_ERROR(check_view(image, "fast9 image"));
  ALE_RETURN_IF_ERROR(check_view(scores, "fast9 scores"));
  if (scores.width != image.width || scores.height != image.height)
    return invalid_argument("fast9: score map " + std::to_string(scores.width) + "x" +
                            std::to_string(scores.height) + " differs from image " + std::to_string(image.width) +
                            "x" + std::to_string(image.height));
  if (threshold < 1 || threshold > 254)
    return invalid_argument("fast9: threshold " + std::to_string(threshold) + " outside 1..254");
  if (image.width > 32767 || image.height > 32767)
    return invalid_argument("fast9: image wider or taller than 32767 pixels");
  if (rect.width <= 0 || rect.height <= 0) return {};
  if (rect.x < kFastRadius || rect.y < kFastRadius || rect.x + rect.width > image.width - kFastRadius ||
      rect.y + rect.height > image.height - kFastRadius)
    return invalid_argument("fast9: rect " + std::to_string(rect.x) + "," + std::to_string(rect.y) + " " +
                            std::to_string(rect.width) + "x" + std::to_string(rect.height) +
                            " does not keep 3 pixels inside the " + std::to_string(image.width) + "x" +
                            std::to_string(image.height) + " image");
  if (path == FastPath::kAuto) path = fast_auto_path();
  if (path == FastPath::kNeon && !fast_neon_compiled()) return unsupported("fast9: this build has no NEON kernel");
  if (path == FastPath::kSse2 && !fast_sse2_compiled()) return unsupported("fast9: this build has no SSE2 kernel");
  if (path == FastPath::kSse2) {  // the score map is FAST's output (score_map.h)
    internal::score_rect_sse2(image, rect, threshold, scores, corners);
    return {};
  }
  const int x_end = rect.x + rect.width;
  for (int y = rect.y; y < rect.y + rect.height; ++y) {
    if (path == FastPath::kNeon)
      internal::fast9_row_neon(image, y, rect.x, x_end, threshold, scores.row(y), corners);
    else
      internal::fast9_row_ref(image, y, rect.x, x_end, threshold, scores.row(y), corners);
  }
  return {};
}

}  // namespace ale::features
