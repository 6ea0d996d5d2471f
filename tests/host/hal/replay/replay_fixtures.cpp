#include "tests/host/hal/replay/replay_fixtures.h"

#include <gtest/gtest.h>

#include <csetjmp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

#include <jpeglib.h>
#include <png.h>

#include "core/io/image_io.h"
#include "tests/host/support/test_data.h"

namespace ale::replay::test {

::testing::AssertionResult fails_naming(const Status& st, StatusCode code, const std::string& what) {
  if (st.code() != code)
    return ::testing::AssertionFailure() << "expected " << to_string(code) << ", got " << st.to_string();
  if (st.message().find(what) == std::string::npos)
    return ::testing::AssertionFailure() << "message does not name '" << what << "': " << st.message();
  return ::testing::AssertionSuccess();
}

GrayImage pattern_frame(int width, int height, int index) {
  GrayImage img(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) img.view().at(x, y) = static_cast<std::uint8_t>((x + 3 * y + 40 * index) & 255);
  return img;
}

std::int64_t fixture_timestamp_ns(int index) { return 1000000000LL + 50000000LL * index; }

std::string euroc_yaml(int width, int height) {
  std::ostringstream s;
  s << "%YAML:1.0\n"
       "# written by replay_fixtures\n"
       "sensor_type: camera\n"
       "comment: fixture camera\n"
       "T_BS:\n"
       "  cols: 4\n"
       "  rows: 4\n"
       "  data: [0.0, -1.0, 0.0, 0.5,\n"
       "         1.0, 0.0, 0.0, -0.25,\n"
       "         0.0, 0.0, 1.0, 0.125,\n"
       "         0.0, 0.0, 0.0, 1.0]\n"
       "rate_hz: 20\n"
       "resolution: ["
    << width << ", " << height
    << "]\n"
       "camera_model: pinhole\n"
       "intrinsics: [400.5, 401.25, 160.125, 120.5] #fu, fv, cu, cv\n"
       "distortion_model: radial-tangential\n"
       "distortion_coefficients: [-0.25, 0.0625, 1e-3, -5.0e-04]\n";
  return s.str();
}

std::string write_euroc(const std::string& root, int count, int width, int height) {
  const std::string cam0 = root + "/mav0/cam0";
  std::string csv = "#timestamp [ns],filename\n";
  std::error_code ec;
  std::filesystem::create_directories(cam0 + "/data", ec);
  for (int i = 0; i < count; ++i) {
    const std::string name = std::to_string(fixture_timestamp_ns(i)) + ".png";
    csv += std::to_string(fixture_timestamp_ns(i)) + "," + name + "\n";
    const Status st = io::write_png(cam0 + "/data/" + name, pattern_frame(width, height, i).view());
    if (!st.ok()) ADD_FAILURE() << st.to_string();
  }
  if (!ale::test::write_file(cam0 + "/data.csv", csv) ||
      !ale::test::write_file(cam0 + "/sensor.yaml", euroc_yaml(width, height)))
    ADD_FAILURE() << "cannot write the EuRoC fixture under " << root;
  return cam0;
}

std::string odometry_yaml() {
  return "sensor_type: odometry\n"
         "comment: fixture\n"
         "rate_hz: 50\n"
         "T_BC:\n"
         "  cols: 4\n"
         "  rows: 4\n"
         "  data: [0.0, 0.0, 1.0, 0.1,\n"
         "         -1.0, 0.0, 0.0, 0.0,\n"
         "         0.0, -1.0, 0.0, 0.08,\n"
         "         0.0, 0.0, 0.0, 1.0]\n";
}

std::string odometry_csv(int frames) {
  std::string csv = "#timestamp [ns],x [m],y [m],theta [rad],gyro_z [rad/s],v_left [m/s],v_right [m/s]\n";
  const std::int64_t step_ns = 20000000;
  const std::int64_t t0 = fixture_timestamp_ns(0) - 2 * step_ns;
  for (std::int64_t t = t0; t <= fixture_timestamp_ns(frames); t += step_ns) {
    const double x = 0.2 * static_cast<double>(t - t0) * 1e-9;
    csv += std::to_string(t) + "," + std::to_string(x) + ",0,0,0,0.2,0.2\n";
  }
  return csv;
}

std::string write_odometry(const std::string& root, const std::string& csv, const std::string& yaml) {
  const std::string folder = root + "/mav0/odometry0";
  if (!ale::test::write_file(folder + "/data.csv", csv) ||
      (!yaml.empty() && !ale::test::write_file(folder + "/sensor.yaml", yaml)))
    ADD_FAILURE() << "cannot write the odometry fixture under " << root;
  return folder;
}

double mean_abs_diff(GrayView a, GrayView b) {
  double sum = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x) sum += std::abs(int{a.at(x, y)} - int{b.at(x, y)});
  return sum / (static_cast<double>(a.width) * a.height);
}

namespace {

void png_test_error(png_structp png, png_const_charp /*message*/) { png_longjmp(png, 1); }

// Only trivially destructible locals: libpng longjmps back here on error.
bool encode_png(std::FILE* f, int width, int height, int color_type, int bit_depth, bool interlaced,
                const std::uint8_t* rows, std::size_t row_bytes, const std::uint8_t* palette, int palette_entries) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, png_test_error, nullptr);
  png_infop info = png_create_info_struct(png);
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    return false;
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), bit_depth, color_type,
               interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_color colours[256];
  if (color_type == PNG_COLOR_TYPE_PALETTE) {
    for (int i = 0; i < palette_entries; ++i)
      colours[i] = {palette[3 * i], palette[3 * i + 1], palette[3 * i + 2]};
    png_set_PLTE(png, info, colours, palette_entries);
  }
  png_write_info(png, info);
  const int passes = png_set_interlace_handling(png);
  for (int pass = 0; pass < passes; ++pass)
    for (int y = 0; y < height; ++y) png_write_row(png, rows + static_cast<std::size_t>(y) * row_bytes);
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

struct JpegTestErrors {
  jpeg_error_mgr mgr;
  std::jmp_buf jump;
};

void jpeg_test_error(j_common_ptr cinfo) { std::longjmp(reinterpret_cast<JpegTestErrors*>(cinfo->err)->jump, 1); }

bool encode_jpeg(std::FILE* f, int width, int height, const std::uint8_t* rgb, int quality) {
  jpeg_compress_struct cinfo;
  JpegTestErrors errors;
  cinfo.err = jpeg_std_error(&errors.mgr);
  errors.mgr.error_exit = jpeg_test_error;
  if (setjmp(errors.jump)) {
    jpeg_destroy_compress(&cinfo);
    return false;
  }
  jpeg_create_compress(&cinfo);
  jpeg_stdio_dest(&cinfo, f);
  cinfo.image_width = static_cast<JDIMENSION>(width);
  cinfo.image_height = static_cast<JDIMENSION>(height);
  cinfo.input_components = 3;
  cinfo.in_color_space = JCS_RGB;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, quality, TRUE);
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    JSAMPROW row = const_cast<JSAMPROW>(rgb + static_cast<std::size_t>(cinfo.next_scanline) * 3 * width);
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  jpeg_destroy_compress(&cinfo);
  return true;
}

}  // namespace

bool write_png_raw(const std::string& path, int width, int height, int color_type, int bit_depth, bool interlaced,
                   const std::vector<std::uint8_t>& rows, const std::vector<std::uint8_t>& palette) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return false;
  const std::size_t row_bytes = rows.size() / static_cast<std::size_t>(height);
  const bool ok = encode_png(f, width, height, color_type, bit_depth, interlaced, rows.data(), row_bytes,
                             palette.data(), static_cast<int>(palette.size() / 3));
  return std::fclose(f) == 0 && ok;
}

bool write_jpeg_rgb(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb, int quality) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return false;
  const bool ok = encode_jpeg(f, width, height, rgb.data(), quality);
  return std::fclose(f) == 0 && ok;
}

}  // namespace ale::replay::test
