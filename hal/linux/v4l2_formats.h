// Which V4L2 pixel formats give a grey image, and how to get the luma out of them. Pure
// functions, so they are tested without a camera.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/base/image.h"

namespace ale::linux_hal {

enum class LumaLayout {
  kGrey,       // the image is the grey image: lent as is
  kPlanar,     // a Y plane comes first (NV12, YUV420...): the Y plane is lent as is
  kPacked422,  // Y interleaved with chroma (YUYV, UYVY): de-interleaved into a pooled buffer
};

struct LumaFormat {
  std::uint32_t fourcc = 0;
  LumaLayout layout = LumaLayout::kGrey;
  int luma_offset = 0;  // kPacked422: byte of the first Y in each 4-byte group (YUYV 0, UYVY 1)
};

// The format for `fourcc`, or nullopt when its luma cannot be taken as grey.
std::optional<LumaFormat> luma_format(std::uint32_t fourcc);

// The formats among those a driver offers (in any order) that give grey, best first: GREY, then
// the planar formats (zero copy, and 1.5 bytes a pixel on the bus), then packed 4:2:2.
std::vector<LumaFormat> usable_formats(const std::vector<std::uint32_t>& offered);
// The first of usable_formats(), or nullopt when none fits.
std::optional<LumaFormat> choose_format(const std::vector<std::uint32_t>& offered);
// "GREY NV12 ...": every format this backend accepts, best first (for error messages and docs).
std::string accepted_formats();

// The smallest bytes-per-line of the first plane at `width` (drivers may pad more).
int min_bytes_per_line(const LumaFormat& format, int width);

// "YUYV"; unprintable bytes appear as '?'.
std::string fourcc_to_string(std::uint32_t fourcc);

// What describe() says about how grey is obtained, e.g. "luma of YUYV, de-interleaved".
std::string describe_luma(const LumaFormat& format);

// Copies the luma of a packed 4:2:2 image into `dst` (dst.width x dst.height pixels). Row y of
// the source starts at src + y * src_stride_bytes and holds 2 * dst.width bytes; luma_offset is
// 0 for YUYV/YVYU and 1 for UYVY/VYUY.
void packed422_to_gray(const std::uint8_t* src, int src_stride_bytes, int luma_offset, MutableGrayView dst);

}  // namespace ale::linux_hal
