#include "core/io/image_io.h"

#include <gtest/gtest.h>
#include <png.h>

#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "tests/host/hal/replay/replay_fixtures.h"
#include "tests/host/support/test_data.h"

namespace ale::io {
namespace {

namespace fixtures = ale::replay::test;  // image files written directly with libpng / libjpeg
using fixtures::fails_naming;
using fixtures::write_png_raw;

TEST(ImageIoTest, GrayPngRoundTripsAtOddSize) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  const GrayImage src = fixtures::pattern_frame(37, 23, 5);
  ASSERT_TRUE(write_png(dir + "/a.png", src.view()).ok());

  const Result<ImageFileInfo> info = probe_image(dir + "/a.png");
  ASSERT_TRUE(info.ok()) << info.status().to_string();
  EXPECT_EQ(info->width, 37);
  EXPECT_EQ(info->height, 23);
  EXPECT_EQ(info->channels, 1);

  GrayImage back;
  ASSERT_TRUE(read_gray(dir + "/a.png", back).ok());
  ASSERT_EQ(back.width, 37);
  ASSERT_EQ(back.height, 23);
  EXPECT_EQ(back.pixels, src.pixels);
}

// decode_gray() is read_gray() on bytes already in memory: the same pixels, and errors headed by
// the name it is given.
TEST(ImageIoTest, DecodingBytesInMemoryIsReadingTheFile) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  const GrayImage src = fixtures::pattern_frame(37, 23, 5);
  ASSERT_TRUE(write_png(dir + "/a.png", src.view()).ok());
  const std::string file = ale::test::read_file(dir + "/a.png");
  const std::vector<std::uint8_t> bytes(file.begin(), file.end());
  GrayImage decoded;
  ASSERT_TRUE(decode_gray(bytes.data(), bytes.size(), "frame 12", decoded).ok());
  EXPECT_EQ(decoded.width, 37);
  EXPECT_EQ(decoded.height, 23);
  EXPECT_EQ(decoded.pixels, src.pixels);

  for (const std::size_t size : {std::size_t{0}, std::size_t{20}, bytes.size() - 12}) {
    GrayImage g;
    EXPECT_TRUE(fails_naming(decode_gray(bytes.data(), size, "frame 12", g), StatusCode::kCorruptData, "frame 12"))
        << size << " bytes";
  }
}

TEST(ImageIoTest, ReadIntoStridedViewLeavesPaddingAlone) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  const GrayImage src = fixtures::pattern_frame(21, 9, 1);
  ASSERT_TRUE(write_png(dir + "/a.png", src.view()).ok());
  std::vector<std::uint8_t> buf(32 * 9, 0xab);
  const MutableGrayView view{buf.data(), 21, 9, 32};
  ASSERT_TRUE(read_gray_into(dir + "/a.png", view).ok());
  for (int y = 0; y < 9; ++y) {
    for (int x = 0; x < 21; ++x) ASSERT_EQ(view.at(x, y), src.view().at(x, y)) << x << "," << y;
    for (int x = 21; x < 32; ++x) ASSERT_EQ(buf[static_cast<std::size_t>(y * 32 + x)], 0xab);
  }
}

TEST(ImageIoTest, ReadIntoViewOfOtherSizeIsInvalidArgument) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  ASSERT_TRUE(write_png(dir + "/a.png", fixtures::pattern_frame(8, 8, 0).view()).ok());
  GrayImage wrong(8, 9);
  EXPECT_TRUE(fails_naming(read_gray_into(dir + "/a.png", wrong.view()), StatusCode::kInvalidArgument, dir + "/a.png"));
}

// Hand-computed BT.601 luma 0.299 R + 0.587 G + 0.114 B, rounded to nearest.
struct Rgb {
  std::uint8_t r, g, b, expected_gray;
};
const Rgb kColours[] = {
    {0, 0, 0, 0},       {255, 255, 255, 255}, {255, 0, 0, 76},    {0, 255, 0, 150},
    {0, 0, 255, 29},    {10, 200, 30, 124},   {128, 128, 128, 128}, {200, 100, 50, 124},
};

TEST(ImageIoTest, RgbPngBecomesBt601Luma) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  std::vector<std::uint8_t> rgb;
  for (const Rgb& c : kColours) rgb.insert(rgb.end(), {c.r, c.g, c.b});
  const int n = static_cast<int>(std::size(kColours));
  ASSERT_TRUE(write_png_rgb(dir + "/c.png", rgb.data(), n, 1, 3 * n).ok());
  const Result<ImageFileInfo> info = probe_image(dir + "/c.png");
  ASSERT_TRUE(info.ok());
  EXPECT_EQ(info->channels, 3);
  GrayImage g;
  ASSERT_TRUE(read_gray(dir + "/c.png", g).ok());
  for (int i = 0; i < n; ++i) EXPECT_EQ(g.pixels[static_cast<std::size_t>(i)], kColours[i].expected_gray) << i;
}

TEST(ImageIoTest, RgbaAndInterlacedRgbIgnoreAlphaAndGiveLuma) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  const int n = static_cast<int>(std::size(kColours));
  // Two rows: each colour twice over, so Adam7 has several passes to assemble.
  std::vector<std::uint8_t> rgba, rgb;
  for (int y = 0; y < 2; ++y)
    for (int rep = 0; rep < 2; ++rep)
      for (const Rgb& c : kColours) {
        rgba.insert(rgba.end(), {c.r, c.g, c.b, static_cast<std::uint8_t>(y == 0 ? 0 : 255)});
        rgb.insert(rgb.end(), {c.r, c.g, c.b});
      }
  ASSERT_TRUE(write_png_raw(dir + "/rgba.png", 2 * n, 2, PNG_COLOR_TYPE_RGB_ALPHA, 8, false, rgba));
  ASSERT_TRUE(write_png_raw(dir + "/adam7.png", 2 * n, 2, PNG_COLOR_TYPE_RGB, 8, true, rgb));
  for (const char* name : {"/rgba.png", "/adam7.png"}) {
    GrayImage g;
    ASSERT_TRUE(read_gray(dir + name, g).ok()) << name;
    ASSERT_EQ(g.width, 2 * n);
    for (int y = 0; y < 2; ++y)
      for (int x = 0; x < 2 * n; ++x) EXPECT_EQ(g.view().at(x, y), kColours[x % n].expected_gray) << name << x << "," << y;
  }
  const Result<ImageFileInfo> info = probe_image(dir + "/rgba.png");
  ASSERT_TRUE(info.ok());
  EXPECT_EQ(info->channels, 4);
}

TEST(ImageIoTest, PaletteGreyAlphaSixteenBitAndOneBitInputs) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  // Palette: indices 0..3 into four of the colours.
  const std::vector<std::uint8_t> palette = {255, 0, 0, 0, 255, 0, 10, 200, 30, 255, 255, 255};
  ASSERT_TRUE(write_png_raw(dir + "/pal.png", 4, 1, PNG_COLOR_TYPE_PALETTE, 8, false, {3, 2, 1, 0}, palette));
  // Grey + alpha: grey is kept, alpha dropped.
  ASSERT_TRUE(write_png_raw(dir + "/ga.png", 3, 1, PNG_COLOR_TYPE_GRAY_ALPHA, 8, false, {7, 0, 100, 128, 250, 255}));
  // 16-bit grey, big-endian samples: 0x0000, 0x8080 (= 128 * 257), 0xffff, 0x1234 (4660 -> 18.13 -> 18).
  ASSERT_TRUE(write_png_raw(dir + "/g16.png", 4, 1, PNG_COLOR_TYPE_GRAY, 16, false,
                            {0x00, 0x00, 0x80, 0x80, 0xff, 0xff, 0x12, 0x34}));
  // 16-bit RGB: (0xffff, 0, 0) is pure red.
  ASSERT_TRUE(write_png_raw(dir + "/rgb16.png", 1, 1, PNG_COLOR_TYPE_RGB, 16, false, {0xff, 0xff, 0, 0, 0, 0}));
  // 1-bit grey, 10 pixels 1011001110 padded to two bytes.
  ASSERT_TRUE(write_png_raw(dir + "/g1.png", 10, 1, PNG_COLOR_TYPE_GRAY, 1, false, {0xb3, 0x80}));

  struct Case {
    const char* name;
    std::vector<std::uint8_t> expected;
    int channels;
  };
  const Case cases[] = {
      {"/pal.png", {255, 124, 150, 76}, 3},
      {"/ga.png", {7, 100, 250}, 2},
      {"/g16.png", {0, 128, 255, 18}, 1},
      {"/rgb16.png", {76}, 3},
      {"/g1.png", {255, 0, 255, 255, 0, 0, 255, 255, 255, 0}, 1},
  };
  for (const Case& c : cases) {
    GrayImage g;
    const Status st = read_gray(dir + c.name, g);
    ASSERT_TRUE(st.ok()) << c.name << ": " << st.to_string();
    EXPECT_EQ(g.pixels, c.expected) << c.name;
    const Result<ImageFileInfo> info = probe_image(dir + c.name);
    ASSERT_TRUE(info.ok());
    EXPECT_EQ(info->channels, c.channels) << c.name;
  }
}

TEST(ImageIoTest, ContentDecidesTheFormatNotTheExtension) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  const GrayImage src = fixtures::pattern_frame(16, 4, 2);
  ASSERT_TRUE(write_png(dir + "/really_a_png.jpg", src.view()).ok());
  GrayImage back;
  ASSERT_TRUE(read_gray(dir + "/really_a_png.jpg", back).ok());
  EXPECT_EQ(back.pixels, src.pixels);
}

TEST(ImageIoTest, RgbJpegBecomesLuma) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  // Flat 16x16 blocks of one colour survive JPEG almost exactly.
  std::vector<std::uint8_t> rgb;
  for (int i = 0; i < 16 * 16; ++i) rgb.insert(rgb.end(), {200, 100, 50});
  ASSERT_TRUE(fixtures::write_jpeg_rgb(dir + "/c.jpg", 16, 16, rgb, 100));
  const Result<ImageFileInfo> info = probe_image(dir + "/c.jpg");
  ASSERT_TRUE(info.ok()) << info.status().to_string();
  EXPECT_EQ(info->channels, 3);
  GrayImage g;
  ASSERT_TRUE(read_gray(dir + "/c.jpg", g).ok());
  ASSERT_EQ(g.width, 16);
  for (std::uint8_t v : g.pixels) EXPECT_NEAR(v, 124, 1);  // chroma quantisation moves luma by <= 1
}

TEST(ImageIoTest, RealEurocJpegMatchesTheOriginalPng) {
  ALE_REQUIRE_DATA(jpeg, "euroc_v101_keyframes/cam0/1403715273262142976_0.jpg");
  ALE_REQUIRE_DATA(png, "euroc_v101_micro/mav0/cam0/data/1403715273262142976.png");
  const Result<ImageFileInfo> info = probe_image(jpeg);
  ASSERT_TRUE(info.ok()) << info.status().to_string();
  EXPECT_EQ(info->width, 752);
  EXPECT_EQ(info->height, 480);
  EXPECT_EQ(info->channels, 1);
  GrayImage from_jpeg, from_png;
  ASSERT_TRUE(read_gray(jpeg, from_jpeg).ok());
  ASSERT_TRUE(read_gray(png, from_png).ok());
  ASSERT_EQ(from_jpeg.width, 752);
  ASSERT_EQ(from_jpeg.height, 480);
  // The keyframe is the same exposure re-compressed: close to the PNG, but not equal.
  const double mad = fixtures::mean_abs_diff(from_jpeg.view(), from_png.view());
  EXPECT_LT(mad, 2.0);
  EXPECT_GT(mad, 0.0);
}

// ---- bad files: every error names the file --------------------------------------------------

TEST(ImageIoTest, MissingFileIsNotFound) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  GrayImage g;
  EXPECT_TRUE(fails_naming(read_gray(dir + "/nope.png", g), StatusCode::kNotFound, dir + "/nope.png"));
  EXPECT_TRUE(fails_naming(probe_image(dir + "/nope.png").status(), StatusCode::kNotFound, dir + "/nope.png"));
}

TEST(ImageIoTest, TruncatedPngIsCorruptAtEveryCut) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  ASSERT_TRUE(write_png(dir + "/full.png", fixtures::pattern_frame(64, 48, 3).view()).ok());
  const std::string bytes = ale::test::read_file(dir + "/full.png");
  ASSERT_GT(bytes.size(), 100u);
  // Inside the signature, inside IHDR, inside IDAT, and only IEND missing.
  for (std::size_t cut : {std::size_t{5}, std::size_t{20}, bytes.size() / 2, bytes.size() - 12}) {
    const std::string path = dir + "/cut" + std::to_string(cut) + ".png";
    ASSERT_TRUE(ale::test::write_file(path, bytes.substr(0, cut)));
    GrayImage g;
    EXPECT_TRUE(fails_naming(read_gray(path, g), StatusCode::kCorruptData, path)) << "cut at " << cut;
  }
}

TEST(ImageIoTest, PngWithDamagedPixelDataIsCorrupt) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  ASSERT_TRUE(write_png(dir + "/full.png", fixtures::pattern_frame(64, 48, 3).view()).ok());
  std::string bytes = ale::test::read_file(dir + "/full.png");
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x5a);  // the IDAT CRC no longer matches
  ASSERT_TRUE(ale::test::write_file(dir + "/bad.png", bytes));
  GrayImage g;
  EXPECT_TRUE(fails_naming(read_gray(dir + "/bad.png", g), StatusCode::kCorruptData, dir + "/bad.png"));
}

TEST(ImageIoTest, GarbageAndEmptyFilesAreCorrupt) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  ASSERT_TRUE(ale::test::write_file(dir + "/garbage.png", "this is not an image at all, just text\n"));
  ASSERT_TRUE(ale::test::write_file(dir + "/empty.png", ""));
  for (const char* name : {"/garbage.png", "/empty.png"}) {
    GrayImage g;
    EXPECT_TRUE(fails_naming(read_gray(dir + name, g), StatusCode::kCorruptData, dir + name));
    EXPECT_TRUE(fails_naming(probe_image(dir + name).status(), StatusCode::kCorruptData, dir + name));
  }
}

TEST(ImageIoTest, CorruptJpegIsCorruptNeverAnExit) {
  ALE_REQUIRE_DATA(jpeg, "euroc_v101_keyframes/cam0/1403715273262142976_0.jpg");
  const std::string dir = ale::test::make_temp_dir("imageio");
  const std::string bytes = ale::test::read_file(jpeg);
  ASSERT_GT(bytes.size(), 1000u);
  // Truncated (libjpeg would pad with grey and only warn), cut inside the header, and the
  // header's markers overwritten.
  std::string smashed = bytes;
  for (std::size_t i = 3; i < 400; ++i) smashed[i] = static_cast<char>(0x11 * (i % 7));
  const std::vector<std::pair<std::string, std::string>> files = {
      {"/half.jpg", bytes.substr(0, bytes.size() / 2)},
      {"/header.jpg", bytes.substr(0, 100)},
      {"/smashed.jpg", smashed},
  };
  for (const auto& [name, content] : files) {
    ASSERT_TRUE(ale::test::write_file(dir + name, content));
    GrayImage g;
    EXPECT_TRUE(fails_naming(read_gray(dir + name, g), StatusCode::kCorruptData, dir + name)) << name;
  }
}

TEST(ImageIoTest, WriteErrorsNameTheFile) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  const GrayImage src = fixtures::pattern_frame(4, 4, 0);
  EXPECT_TRUE(fails_naming(write_png(dir + "/no/such/dir/a.png", src.view()), StatusCode::kIoError,
                           dir + "/no/such/dir/a.png"));
  EXPECT_TRUE(fails_naming(write_png(dir + "/a.png", GrayView{}), StatusCode::kInvalidArgument, dir + "/a.png"));
  EXPECT_TRUE(fails_naming(write_png_rgb(dir + "/b.png", src.pixels.data(), 4, 4, 4), StatusCode::kInvalidArgument,
                           dir + "/b.png"));
}

// The recorder's fast settings are lossless too, at every level and both filters, on a strided view.
TEST(ImageIoTest, FastPngSettingsRoundTripExactly) {
  const std::string dir = ale::test::make_temp_dir("imageio");
  const GrayImage src = fixtures::pattern_frame(41, 19, 3);
  GrayImage padded(48, 19, 7);
  for (int y = 0; y < 19; ++y)
    for (int x = 0; x < 41; ++x) padded.view().at(x, y) = src.view().at(x, y);
  const GrayView strided{padded.pixels.data(), 41, 19, 48};
  for (const PngWriteOptions& o : {PngWriteOptions{0, false}, PngWriteOptions{1, false}, PngWriteOptions{1, true},
                                   PngWriteOptions{9, false}}) {
    const std::string path = dir + "/fast.png";
    ASSERT_TRUE(write_png(path, strided, o).ok()) << o.compression_level;
    GrayImage back;
    ASSERT_TRUE(read_gray(path, back).ok());
    EXPECT_EQ(back.pixels, src.pixels) << "level " << o.compression_level << " adaptive " << o.adaptive_filter;
  }
}

// A full disk: /dev/full takes the open and fails the writes with ENOSPC, which the error names.
TEST(ImageIoTest, AFullDiskIsAnIoErrorSayingSo) {
  if (::access("/dev/full", W_OK) != 0) GTEST_SKIP() << "no /dev/full";
  const GrayImage src = fixtures::pattern_frame(64, 48, 1);
  const Status s = write_png("/dev/full", src.view(), PngWriteOptions{1, false});
  EXPECT_EQ(s.code(), StatusCode::kIoError);
  EXPECT_NE(s.message().find("/dev/full"), std::string::npos) << s.message();
  EXPECT_NE(s.message().find(std::strerror(ENOSPC)), std::string::npos) << s.message();
}

}  // namespace
}  // namespace ale::io
