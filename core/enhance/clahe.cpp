// CLAHE dispatch: which kernel runs, argument checks shared by both.
#include <string>

#include "core/enhance/clahe.h"
#include "core/enhance/kernels.h"

namespace ale::enhance {

Status ClaheContext::apply(GrayView src, MutableGrayView dst, KernelPath path) {
  if (!configured_) return invalid_argument("clahe: apply() before configure()");
  ALE_RETURN_IF_ERROR(check_view(src, "clahe source"));
  ALE_RETURN_IF_ERROR(check_view(dst, "clahe destination"));
  if (src.width != width_ || src.height != height_ || dst.width != width_ || dst.height != height_)
    return invalid_argument("clahe: configured for " + std::to_string(width_) + "x" + std::to_string(height_) +
                            ", got source " + std::to_string(src.width) + "x" + std::to_string(src.height) +
                            " and destination " + std::to_string(dst.width) + "x" +
                            std::to_string(dst.height));
  const bool same = src.data == dst.data && src.stride == dst.stride;
  if (!same) {
    const std::uint8_t* s0 = src.data;
    const std::uint8_t* s1 = src.row(src.height - 1) + src.width;
    const std::uint8_t* d0 = dst.data;
    const std::uint8_t* d1 = dst.row(dst.height - 1) + dst.width;
    if (s0 < d1 && d0 < s1) return invalid_argument("clahe: source and destination overlap partially");
  }
  if (path != KernelPath::kAuto && !kernel_path_compiled(path))
    return unsupported(std::string("clahe: this build has no ") + to_string(path) + " kernel");
  (this->*kernels(path).clahe_apply)(src, dst);
  return {};
}

Status clahe(ClaheContext& ctx, const ClaheParams& params, GrayView src, MutableGrayView dst, KernelPath path) {
  ALE_RETURN_IF_ERROR(check_view(src, "clahe source"));
  ALE_RETURN_IF_ERROR(ctx.configure(src.width, src.height, params));
  return ctx.apply(src, dst, path);
}

}  // namespace ale::enhance
