#include "hal/linux/v4l2_formats.h"

#include <linux/videodev2.h>

#include <algorithm>
#include <cstddef>

namespace ale::linux_hal {

namespace {

// In order of preference.
constexpr LumaFormat kFormats[] = {
    {V4L2_PIX_FMT_GREY, LumaLayout::kGrey, 0},
    {V4L2_PIX_FMT_NV12, LumaLayout::kPlanar, 0},
    {V4L2_PIX_FMT_NV21, LumaLayout::kPlanar, 0},
    {V4L2_PIX_FMT_YUV420, LumaLayout::kPlanar, 0},
    {V4L2_PIX_FMT_YVU420, LumaLayout::kPlanar, 0},
    {V4L2_PIX_FMT_NV16, LumaLayout::kPlanar, 0},
    {V4L2_PIX_FMT_NV61, LumaLayout::kPlanar, 0},
    // Multi-planar variants (the Y plane is plane 0), offered by sunxi-style capture drivers.
    {V4L2_PIX_FMT_NV12M, LumaLayout::kPlanar, 0},
    {V4L2_PIX_FMT_NV21M, LumaLayout::kPlanar, 0},
    {V4L2_PIX_FMT_YUV420M, LumaLayout::kPlanar, 0},
    {V4L2_PIX_FMT_YVU420M, LumaLayout::kPlanar, 0},
    {V4L2_PIX_FMT_YUYV, LumaLayout::kPacked422, 0},
    {V4L2_PIX_FMT_YVYU, LumaLayout::kPacked422, 0},
    {V4L2_PIX_FMT_UYVY, LumaLayout::kPacked422, 1},
    {V4L2_PIX_FMT_VYUY, LumaLayout::kPacked422, 1},
};

}  // namespace

std::optional<LumaFormat> luma_format(std::uint32_t fourcc) {
  for (const LumaFormat& f : kFormats)
    if (f.fourcc == fourcc) return f;
  return std::nullopt;
}

std::vector<LumaFormat> usable_formats(const std::vector<std::uint32_t>& offered) {
  std::vector<LumaFormat> usable;
  for (const LumaFormat& f : kFormats)
    if (std::find(offered.begin(), offered.end(), f.fourcc) != offered.end()) usable.push_back(f);
  return usable;
}

std::optional<LumaFormat> choose_format(const std::vector<std::uint32_t>& offered) {
  const std::vector<LumaFormat> usable = usable_formats(offered);
  if (usable.empty()) return std::nullopt;
  return usable.front();
}

std::string accepted_formats() {
  std::string list;
  for (const LumaFormat& f : kFormats) list += (list.empty() ? "" : " ") + fourcc_to_string(f.fourcc);
  return list;
}

int min_bytes_per_line(const LumaFormat& format, int width) {
  return format.layout == LumaLayout::kPacked422 ? 2 * width : width;
}

std::string fourcc_to_string(std::uint32_t fourcc) {
  std::string s(4, '?');
  for (std::size_t i = 0; i < 4; ++i) {
    const auto c = static_cast<char>((fourcc >> (8 * i)) & 0xff);
    if (c >= 0x20 && c < 0x7f) s[i] = c;
  }
  return s;
}

std::string describe_luma(const LumaFormat& format) {
  const std::string name = fourcc_to_string(format.fourcc);
  switch (format.layout) {
    case LumaLayout::kGrey: return name + " (grey, zero copy)";
    case LumaLayout::kPlanar: return name + " (Y plane taken as grey, zero copy)";
    case LumaLayout::kPacked422: return name + " (luma de-interleaved into a pooled grey buffer)";
  }
  return name;
}

void packed422_to_gray(const std::uint8_t* src, int src_stride_bytes, int luma_offset, MutableGrayView dst) {
  for (int y = 0; y < dst.height; ++y) {
    const std::uint8_t* s = src + static_cast<std::ptrdiff_t>(y) * src_stride_bytes + luma_offset;
    std::uint8_t* d = dst.row(y);
    for (int x = 0; x < dst.width; ++x) d[x] = s[2 * x];
  }
}

}  // namespace ale::linux_hal
