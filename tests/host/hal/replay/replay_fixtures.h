// Small datasets and image files written by the replay tests into their temp folders.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/base/image.h"
#include "core/base/status.h"

namespace ale::replay::test {

// The status failed with `code` and its message contains `what` (a file name, "file:line:").
::testing::AssertionResult fails_naming(const Status& st, StatusCode code, const std::string& what);

// A frame whose pixels depend on x, y and `index`, so frames differ from each other.
GrayImage pattern_frame(int width, int height, int index);

// Timestamp of fixture frame `index`: 20 Hz from 1 s.
std::int64_t fixture_timestamp_ns(int index);

// A EuRoC sensor.yaml for a width x height camera (fx 400.5, fy 401.25, cx 160.125, cy 120.5,
// radtan -0.25 0.0625 0.001 -0.0005, T_BS over several lines like EuRoC's).
std::string euroc_yaml(int width, int height);

// Writes <root>/mav0/cam0/{data.csv, data/<ts>.png, sensor.yaml} with `count` pattern frames and
// returns <root>/mav0/cam0. Fails the calling test (ADD_FAILURE) when a file cannot be written.
std::string write_euroc(const std::string& root, int count, int width, int height);

// An odometry0/sensor.yaml: rate_hz 50 and T_BC (the camera 0.1 m ahead of the base's centre and
// 0.08 m up, looking forward: x_camera right, y down, z forward; p_base = T_BC * p_camera).
std::string odometry_yaml();
// Rows "t,x,y,theta,gyro_z,v_left,v_right" (the 7 columns ale-render writes, with their header),
// one every 20 ms from fixture_timestamp_ns(0) - 40 ms to fixture_timestamp_ns(frames) (the
// frames' 20 Hz span), the base driving forward at 0.2 m/s.
std::string odometry_csv(int frames);
// Writes <root>/mav0/odometry0/{data.csv, sensor.yaml} (an empty `yaml` writes no sensor.yaml)
// and returns <root>/mav0/odometry0.
std::string write_odometry(const std::string& root, const std::string& csv, const std::string& yaml);

// Mean absolute difference of two views of the same size.
double mean_abs_diff(GrayView a, GrayView b);

// A PNG of any colour type and bit depth, written with libpng directly (the library under test
// only writes 8-bit grey and RGB). `rows` holds height rows of packed samples as PNG stores them
// (16-bit samples big-endian); `palette` is RGB triplets for PNG_COLOR_TYPE_PALETTE.
bool write_png_raw(const std::string& path, int width, int height, int color_type, int bit_depth, bool interlaced,
                   const std::vector<std::uint8_t>& rows, const std::vector<std::uint8_t>& palette = {});

// An RGB JPEG at the given quality, written with libjpeg directly.
bool write_jpeg_rgb(const std::string& path, int width, int height, const std::vector<std::uint8_t>& rgb, int quality);

}  // namespace ale::replay::test
