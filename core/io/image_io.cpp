#include "core/io/image_io.h"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <new>

// jpeglib.h uses FILE and size_t without including their headers.
#include <jpeglib.h>
#include <png.h>

namespace ale::io {

namespace {

// Larger images are refused before anything is allocated for them: no camera we replay comes
// near this, and a corrupt header must not make us reserve gigabytes.
constexpr int kMaxDimension = 16384;
constexpr std::size_t kMaxFileBytes = std::size_t{256} << 20;

enum class FileKind { kPng, kJpeg, kUnknown };

FileKind sniff(const std::uint8_t* bytes, std::size_t size) {
  static const std::uint8_t kPngMagic[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (size >= 8 && std::memcmp(bytes, kPngMagic, 8) == 0) return FileKind::kPng;
  if (size >= 3 && bytes[0] == 0xff && bytes[1] == 0xd8 && bytes[2] == 0xff) return FileKind::kJpeg;
  return FileKind::kUnknown;
}

std::string first_bytes_hex(const std::uint8_t* bytes, std::size_t size) {
  std::string s;
  char buf[4];
  for (std::size_t i = 0; i < size && i < 8; ++i) {
    std::snprintf(buf, sizeof buf, "%s%02x", i == 0 ? "" : " ", bytes[i]);
    s += buf;
  }
  return s;
}

Status read_whole_file(const std::string& path, std::vector<std::uint8_t>& bytes) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    const int err = errno;
    if (err == ENOENT || err == ENOTDIR) return not_found(path + ": no such file");
    return io_error(path + ": cannot open: " + std::strerror(err));
  }
  struct stat st {};
  if (::fstat(::fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
    std::fclose(f);
    return io_error(path + ": not a regular file");
  }
  const auto size = static_cast<std::size_t>(st.st_size);
  if (size > kMaxFileBytes) {
    std::fclose(f);
    return corrupt_data(path + ": file of " + std::to_string(size) + " bytes is too large for an image");
  }
  try {
    bytes.resize(size);
  } catch (const std::bad_alloc&) {
    std::fclose(f);
    return out_of_memory(path + ": cannot hold " + std::to_string(size) + " bytes");
  }
  const std::size_t got = size == 0 ? 0 : std::fread(bytes.data(), 1, size, f);
  const bool read_failed = std::ferror(f) != 0;
  std::fclose(f);
  if (read_failed || got != size) return io_error(path + ": read failed");
  if (size == 0) return corrupt_data(path + ": empty file");
  return {};
}

// BT.601 luma in Q16 (the weights sum to 65536, so white stays 255), rounded to nearest.
inline std::uint8_t luma(unsigned r, unsigned g, unsigned b) {
  return static_cast<std::uint8_t>((19595u * r + 38470u * g + 7471u * b + 32768u) >> 16);
}

void rgb_row_to_gray(const std::uint8_t* rgb, std::uint8_t* gray, int width) {
  for (int x = 0; x < width; ++x, rgb += 3) gray[x] = luma(rgb[0], rgb[1], rgb[2]);
}

// What the decoders need to know from the header before the pixels are read.
struct Header {
  ImageFileInfo info;
  bool interlaced = false;
  bool colour = false;  // decodes through RGB rows (RGB, RGBA, palette)
};

// ---------------------------------------------------------------------------------------------
// PNG. libpng reports errors by longjmp to the setjmp in png_decode(); that function keeps only
// trivially destructible locals, so the jump skips no destructor.

struct PngSource {
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
  std::size_t pos = 0;
  char message[256] = {};  // libpng's error pointer, for reading and writing alike
};

void png_read_memory(png_structp png, png_bytep out, png_size_t n) {
  auto* src = static_cast<PngSource*>(png_get_io_ptr(png));
  if (n > src->size - src->pos) png_error(png, "file is truncated");
  std::memcpy(out, src->data + src->pos, n);
  src->pos += n;
}

void png_on_error(png_structp png, png_const_charp message) {
  auto* text = static_cast<char*>(png_get_error_ptr(png));
  std::snprintf(text, sizeof PngSource::message, "%s", message);
  png_longjmp(png, 1);
}

void png_on_warning(png_structp /*png*/, png_const_charp /*message*/) {
  // Ancillary-chunk complaints (sRGB profiles, text chunks) do not affect the pixels.
}

// Reads the header into `header`, then, when `out` is given, the pixels into it (whose size the
// caller has checked). `rgb_rows` must hold a colour row (or the whole image when interlaced).
bool png_decode(PngSource& src, Header& header, const MutableGrayView* out, std::uint8_t* rgb_rows) {
  png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, src.message, png_on_error, png_on_warning);
  if (png == nullptr) {
    std::snprintf(src.message, sizeof src.message, "libpng could not start");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_read_struct(&png, nullptr, nullptr);
    std::snprintf(src.message, sizeof src.message, "libpng could not start");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_read_struct(&png, &info, nullptr);
    return false;
  }
  png_set_read_fn(png, &src, png_read_memory);
  png_set_user_limits(png, kMaxDimension, kMaxDimension);
  png_read_info(png, info);

  const int color_type = png_get_color_type(png, info);
  const int bit_depth = png_get_bit_depth(png, info);
  header.info.width = static_cast<int>(png_get_image_width(png, info));
  header.info.height = static_cast<int>(png_get_image_height(png, info));
  header.info.channels = color_type == PNG_COLOR_TYPE_GRAY         ? 1
                         : color_type == PNG_COLOR_TYPE_GRAY_ALPHA ? 2
                         : color_type == PNG_COLOR_TYPE_RGB_ALPHA  ? 4
                                                                   : 3;
  header.interlaced = png_get_interlace_type(png, info) != PNG_INTERLACE_NONE;
  header.colour = (color_type & PNG_COLOR_MASK_COLOR) != 0;
  if (out == nullptr) {
    png_destroy_read_struct(&png, &info, nullptr);
    return true;
  }

  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if (color_type == PNG_COLOR_TYPE_GRAY && bit_depth < 8) png_set_expand_gray_1_2_4_to_8(png);
  if (bit_depth == 16) png_set_scale_16(png);  // rounds, unlike png_set_strip_16
  // Alpha is dropped, not composited: a camera frame has no background to blend with.
  if ((color_type & PNG_COLOR_MASK_ALPHA) != 0) png_set_strip_alpha(png);
  const int passes = png_set_interlace_handling(png);
  png_read_update_info(png, info);

  const int width = header.info.width;
  const int height = header.info.height;
  const int channels = png_get_channels(png, info);
  if (channels != (header.colour ? 3 : 1) ||
      png_get_rowbytes(png, info) != static_cast<png_size_t>(width) * static_cast<png_size_t>(channels))
    png_error(png, "unexpected row layout after conversion");

  const auto rgb_row_bytes = static_cast<std::size_t>(width) * 3;
  for (int pass = 0; pass < passes; ++pass) {
    for (int y = 0; y < height; ++y) {
      png_bytep row = !header.colour      ? out->row(y)
                      : header.interlaced ? rgb_rows + static_cast<std::size_t>(y) * rgb_row_bytes
                                          : rgb_rows;
      png_read_row(png, row, nullptr);
      if (header.colour && !header.interlaced) rgb_row_to_gray(row, out->row(y), width);
    }
  }
  if (header.colour && header.interlaced)
    for (int y = 0; y < height; ++y)
      rgb_row_to_gray(rgb_rows + static_cast<std::size_t>(y) * rgb_row_bytes, out->row(y), width);
  png_read_end(png, nullptr);  // checks the CRCs up to IEND
  png_destroy_read_struct(&png, &info, nullptr);
  return true;
}

// ---------------------------------------------------------------------------------------------
// JPEG. libjpeg calls error_exit on fatal errors and would exit() by default; ours longjmps back
// to jpeg_decode(), which, like png_decode(), keeps only trivially destructible locals.

struct JpegErrors {
  jpeg_error_mgr mgr;  // first: libjpeg hands us back a pointer to it
  std::jmp_buf jump;
  char message[JMSG_LENGTH_MAX];
  int warnings;
};

void jpeg_on_error(j_common_ptr cinfo) {
  auto* errors = reinterpret_cast<JpegErrors*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, errors->message);
  std::longjmp(errors->jump, 1);
}

// Warnings (level < 0) are how libjpeg reports a truncated or damaged stream it papered over
// with grey; we keep the first one and fail the decode. Trace messages (level >= 0) are ignored.
void jpeg_on_message(j_common_ptr cinfo, int level) {
  if (level >= 0) return;
  auto* errors = reinterpret_cast<JpegErrors*>(cinfo->err);
  if (errors->warnings++ == 0) (*cinfo->err->format_message)(cinfo, errors->message);
}

bool jpeg_decode(const std::uint8_t* data, std::size_t size, JpegErrors& errors, Header& header,
                 const MutableGrayView* out) {
  jpeg_decompress_struct cinfo;
  std::memset(&cinfo, 0, sizeof cinfo);
  cinfo.err = jpeg_std_error(&errors.mgr);
  errors.mgr.error_exit = jpeg_on_error;
  errors.mgr.emit_message = jpeg_on_message;
  errors.message[0] = '\0';
  errors.warnings = 0;
  if (setjmp(errors.jump)) {
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  jpeg_create_decompress(&cinfo);
  jpeg_mem_src(&cinfo, data, static_cast<unsigned long>(size));
  jpeg_read_header(&cinfo, TRUE);
  header.info.width = static_cast<int>(cinfo.image_width);
  header.info.height = static_cast<int>(cinfo.image_height);
  header.info.channels = cinfo.num_components;
  header.interlaced = false;
  header.colour = cinfo.num_components != 1;
  if (cinfo.image_width > static_cast<JDIMENSION>(kMaxDimension) ||
      cinfo.image_height > static_cast<JDIMENSION>(kMaxDimension)) {
    std::snprintf(errors.message, sizeof errors.message, "image of %ux%u is larger than %d pixels a side",
                  cinfo.image_width, cinfo.image_height, kMaxDimension);
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  if (out == nullptr) {
    jpeg_destroy_decompress(&cinfo);
    return true;
  }
  if (cinfo.jpeg_color_space != JCS_GRAYSCALE && cinfo.jpeg_color_space != JCS_YCbCr &&
      cinfo.jpeg_color_space != JCS_RGB) {
    std::snprintf(errors.message, sizeof errors.message, "colour space %d (CMYK/YCCK) is not supported",
                  static_cast<int>(cinfo.jpeg_color_space));
    jpeg_destroy_decompress(&cinfo);
    return false;
  }
  // From YCbCr libjpeg keeps Y, which is BT.601 luma; from RGB it applies the BT.601 weights.
  cinfo.out_color_space = JCS_GRAYSCALE;
  jpeg_start_decompress(&cinfo);
  while (cinfo.output_scanline < cinfo.output_height) {
    JSAMPROW row = out->row(static_cast<int>(cinfo.output_scanline));
    if (jpeg_read_scanlines(&cinfo, &row, 1) != 1) break;
  }
  const bool complete = cinfo.output_scanline == cinfo.output_height;
  if (complete) jpeg_finish_decompress(&cinfo);
  jpeg_destroy_decompress(&cinfo);
  if (!complete && errors.warnings == 0) {
    std::snprintf(errors.message, sizeof errors.message, "decoder stopped early");
    return false;
  }
  return errors.warnings == 0;
}

// ---------------------------------------------------------------------------------------------

// Reads the header of an encoded image held in `size` bytes at `bytes`.
Status decode_header(const std::string& path, const std::uint8_t* bytes, std::size_t size, Header& header) {
  switch (sniff(bytes, size)) {
    case FileKind::kPng: {
      PngSource src;
      src.data = bytes;
      src.size = size;
      if (!png_decode(src, header, nullptr, nullptr)) return corrupt_data(path + ": corrupt PNG: " + src.message);
      return {};
    }
    case FileKind::kJpeg: {
      JpegErrors errors{};
      if (!jpeg_decode(bytes, size, errors, header, nullptr))
        return corrupt_data(path + ": corrupt JPEG: " + errors.message);
      return {};
    }
    case FileKind::kUnknown:
      break;
  }
  return corrupt_data(path + ": not a PNG or JPEG file (starts with " + first_bytes_hex(bytes, size) + ")");
}

// Decodes the encoded image in `size` bytes at `bytes` (its header read into `header`) into `out`,
// whose size must match the header; scratch.rows holds colour rows.
Status decode_pixels(const std::string& path, const std::uint8_t* bytes, std::size_t size, const Header& header,
                     MutableGrayView out, DecodeScratch& scratch) {
  Header again;
  if (sniff(bytes, size) == FileKind::kPng) {
    std::uint8_t* rgb_rows = nullptr;
    if (header.colour) {
      const std::size_t row_bytes = static_cast<std::size_t>(header.info.width) * 3;
      const std::size_t rows = header.interlaced ? static_cast<std::size_t>(header.info.height) : 1;
      try {
        scratch.rows.resize(row_bytes * rows);
      } catch (const std::bad_alloc&) {
        return out_of_memory(path + ": cannot hold the decoded colour rows");
      }
      rgb_rows = scratch.rows.data();
    }
    PngSource src;
    src.data = bytes;
    src.size = size;
    if (!png_decode(src, again, &out, rgb_rows)) return corrupt_data(path + ": corrupt PNG: " + src.message);
    return {};
  }
  JpegErrors errors{};
  if (!jpeg_decode(bytes, size, errors, again, &out))
    return corrupt_data(path + ": corrupt JPEG: " + errors.message);
  return {};
}

std::string size_text(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

// ---------------------------------------------------------------------------------------------
// Writing. Errors longjmp back to png_encode() through png_on_error(); the FILE is closed (and
// the partial file removed) by the caller.

bool png_encode(std::FILE* file, char (&message)[sizeof PngSource::message], const std::uint8_t* pixels, int width, int height,
                std::size_t stride_bytes, int color_type, const PngWriteOptions& options) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, message, png_on_error, png_on_warning);
  if (png == nullptr) {
    std::snprintf(message, sizeof message, "libpng could not start");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    std::snprintf(message, sizeof message, "libpng could not start");
    return false;
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, file);
  if (options.compression_level >= 0) png_set_compression_level(png, std::min(options.compression_level, 9));
  if (!options.adaptive_filter) png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, color_type,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) png_write_row(png, pixels + static_cast<std::size_t>(y) * stride_bytes);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

Status write_png_rows(const std::string& path, const std::uint8_t* pixels, int width, int height,
                      std::size_t stride_bytes, int color_type, const PngWriteOptions& options = {}) {
  if (width > kMaxDimension || height > kMaxDimension)
    return invalid_argument(path + ": image of " + size_text(width, height) + " is too large to write");
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) return io_error(path + ": cannot create: " + std::strerror(errno));
  char message[sizeof PngSource::message] = {};
  // libpng's own message for a failed fwrite is "Write Error"; errno says why (ENOSPC, EIO). A
  // full disk often shows only when the buffered tail is flushed.
  errno = 0;
  const bool encoded = png_encode(file, message, pixels, width, height, stride_bytes, color_type, options);
  int why = encoded ? 0 : errno;
  errno = 0;
  const bool flushed = encoded && std::fflush(file) == 0;
  if (encoded && !flushed) why = errno;
  errno = 0;
  const bool closed = std::fclose(file) == 0;
  if (!closed && why == 0) why = errno;
  if (!encoded || !flushed || !closed) {
    // The partial file goes; a device or pipe written to (e.g. /dev/full) is never unlinked.
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode)) std::remove(path.c_str());
    std::string text = "cannot write PNG: ";
    text += !encoded ? std::string(message) : std::string(flushed ? "close failed" : "flush failed");
    if (why != 0) text += std::string(" (") + std::strerror(why) + ")";
    return io_error(path + ": " + text);
  }
  return {};
}

}  // namespace

Result<ImageFileInfo> probe_image(const std::string& path) {
  std::vector<std::uint8_t> bytes;
  ALE_RETURN_IF_ERROR(read_whole_file(path, bytes));
  Header header;
  ALE_RETURN_IF_ERROR(decode_header(path, bytes.data(), bytes.size(), header));
  return header.info;
}

Status read_gray_into(const std::string& path, MutableGrayView out, DecodeScratch& scratch) {
  ALE_RETURN_IF_ERROR(check_view(out, (path + ": destination").c_str()));
  ALE_RETURN_IF_ERROR(read_whole_file(path, scratch.file));
  Header header;
  ALE_RETURN_IF_ERROR(decode_header(path, scratch.file.data(), scratch.file.size(), header));
  if (header.info.width != out.width || header.info.height != out.height)
    return invalid_argument(path + ": image is " + size_text(header.info.width, header.info.height) +
                            ", the buffer is " + size_text(out.width, out.height));
  return decode_pixels(path, scratch.file.data(), scratch.file.size(), header, out, scratch);
}

Status read_gray_into(const std::string& path, MutableGrayView out) {
  DecodeScratch scratch;
  return read_gray_into(path, out, scratch);
}

Status decode_gray(const std::uint8_t* data, std::size_t size, const std::string& name, GrayImage& out) {
  if (size == 0) return corrupt_data(name + ": empty file");
  Header header;
  ALE_RETURN_IF_ERROR(decode_header(name, data, size, header));
  GrayImage image;
  try {
    image = GrayImage(header.info.width, header.info.height);
  } catch (const std::bad_alloc&) {
    return out_of_memory(name + ": cannot hold a " + size_text(header.info.width, header.info.height) + " image");
  }
  DecodeScratch scratch;
  ALE_RETURN_IF_ERROR(decode_pixels(name, data, size, header, image.view(), scratch));
  out = std::move(image);
  return {};
}

Status read_gray(const std::string& path, GrayImage& out) {
  std::vector<std::uint8_t> bytes;
  ALE_RETURN_IF_ERROR(read_whole_file(path, bytes));
  return decode_gray(bytes.data(), bytes.size(), path, out);
}

Status write_png(const std::string& path, GrayView image, const PngWriteOptions& options) {
  ALE_RETURN_IF_ERROR(check_view(image, (path + ": image to write").c_str()));
  return write_png_rows(path, image.data, image.width, image.height, static_cast<std::size_t>(image.stride),
                        PNG_COLOR_TYPE_GRAY, options);
}

Status write_png(const std::string& path, GrayView image) { return write_png(path, image, PngWriteOptions{}); }

Status write_png_rgb(const std::string& path, const std::uint8_t* rgb, int width, int height, int stride_bytes) {
  if (rgb == nullptr || width <= 0 || height <= 0 || stride_bytes < width * 3)
    return invalid_argument(path + ": bad RGB image to write (" + size_text(width, height) + ", stride " +
                            std::to_string(stride_bytes) + ")");
  return write_png_rows(path, rgb, width, height, static_cast<std::size_t>(stride_bytes), PNG_COLOR_TYPE_RGB);
}

}  // namespace ale::io
