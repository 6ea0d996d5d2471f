// Writes the generated seeds of the fuzz targets (the rest of tests/fuzz/corpus/ is written by
// hand): `fuzz_make_seeds DIR` (scripts/fuzz.sh --seeds) fills DIR/vocabulary/, DIR/command/,
// DIR/image/, DIR/map_file/ and DIR/config/defaults.conf. Everything is made here from the code itself (a
// vocabulary trained on seeded random descriptors, commands encoded by lcm-gen's encode(), small
// images written by our PNG writer and libjpeg, the default configuration as print_config writes
// it), so the same build writes the same bytes.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <jpeglib.h>

#include "ale_lcm/command_t.hpp"
#include "app/config.h"
#include "core/base/rng.h"
#include "core/io/image_io.h"
#include "core/io/file_bytes.h"
#include "core/io/map_file.h"
#include "core/place/vocabulary.h"
#include "map_file_context.h"

namespace {

namespace fs = std::filesystem;

void fail(const std::string& why) {
  std::fprintf(stderr, "fuzz_make_seeds: %s\n", why.c_str());
  std::exit(1);
}

void write_bytes(const fs::path& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) fail("cannot write " + path.string());
}

// A vocabulary of branching k and depth `levels` trained on 40 images of 30 random descriptors,
// with the fuzz target's switch byte in front (1: the target fixes the checksum, 0: as is).
void vocabulary(const fs::path& dir, int k, int levels) {
  ale::SplitMix64 rng(7);
  std::vector<std::vector<ale::features::Descriptor>> images(40, std::vector<ale::features::Descriptor>(30));
  for (auto& image : images)
    for (auto& d : image)
      for (auto& b : d.bytes) b = static_cast<std::uint8_t>(rng.next());
  ale::place::VocabularyTrainParams params;
  params.k = k;
  params.levels = levels;
  ale::Result<ale::place::Vocabulary> v = ale::place::Vocabulary::train(images, params);
  if (!v.ok()) fail("training: " + v.status().to_string());
  const std::vector<std::uint8_t> file = v->serialize();
  const std::string name = "k" + std::to_string(k) + "_l" + std::to_string(levels);
  for (const std::uint8_t fix : {std::uint8_t{0}, std::uint8_t{1}}) {
    std::vector<std::uint8_t> seed{fix};
    seed.insert(seed.end(), file.begin(), file.end());
    write_bytes(dir / (name + (fix ? "_fix_checksum" : "_as_is")), seed);
  }
}

void command(const fs::path& dir, const std::string& name, std::int8_t kind, const std::string& argument,
             std::size_t cut = 0) {
  ale_lcm::command_t c;
  c.command_id = 42;
  c.command = kind;
  c.argument = argument;
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(c.getEncodedSize()));
  if (c.encode(bytes.data(), 0, static_cast<int>(bytes.size())) < 0) fail("encoding " + name);
  bytes.resize(bytes.size() - cut);
  write_bytes(dir / name, bytes);
}

// An 8x6 JPEG of `components` (1 grey, 3 YCbCr from RGB) at quality 50, through libjpeg.
void jpeg(const fs::path& path, int components) {
  constexpr int kW = 8, kH = 6;
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(kW * kH * components));
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<std::uint8_t>(i * 37);
  jpeg_compress_struct cinfo{};
  jpeg_error_mgr err{};
  cinfo.err = jpeg_std_error(&err);
  jpeg_create_compress(&cinfo);
  unsigned char* out = nullptr;
  unsigned long size = 0;
  jpeg_mem_dest(&cinfo, &out, &size);
  cinfo.image_width = kW;
  cinfo.image_height = kH;
  cinfo.input_components = components;
  cinfo.in_color_space = components == 1 ? JCS_GRAYSCALE : JCS_RGB;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, 50, TRUE);
  jpeg_start_compress(&cinfo, TRUE);
  while (cinfo.next_scanline < cinfo.image_height) {
    JSAMPROW row = pixels.data() + static_cast<std::size_t>(cinfo.next_scanline) * kW * components;
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  jpeg_destroy_compress(&cinfo);
  write_bytes(path, std::vector<std::uint8_t>(out, out + size));
  std::free(out);
}

void images(const fs::path& dir) {
  ale::GrayImage grey(8, 6);
  for (int y = 0; y < 6; ++y)
    for (int x = 0; x < 8; ++x) grey.view().row(y)[x] = static_cast<std::uint8_t>(30 * x + 7 * y);
  ale::io::PngWriteOptions up;
  up.compression_level = 1;
  up.adaptive_filter = false;
  std::vector<std::uint8_t> rgb(8 * 6 * 3);
  for (std::size_t i = 0; i < rgb.size(); ++i) rgb[i] = static_cast<std::uint8_t>(i * 11);
  if (!ale::io::write_png((dir / "grey.png").string(), grey.view()).ok() ||
      !ale::io::write_png((dir / "grey_up_filter.png").string(), grey.view(), up).ok() ||
      !ale::io::write_png_rgb((dir / "rgb.png").string(), rgb.data(), 8, 6, 8 * 3).ok())
    fail("writing the PNG seeds");
  jpeg(dir / "grey.jpg", 1);
  jpeg(dir / "colour.jpg", 3);
}

}  // namespace

// A map file of `maps` small maps (4 keyframes of 12 keypoints, 20 landmarks seen by 2 or 3 of
// them, a chain for the tree, covisibility from the observations, a loop edge), saved with the
// fuzz target's context, the switch byte in front (0: as is, 1: the target fixes the checksums).
void map_file(const fs::path& dir, int maps) {
  ale::map::MapStore store(ale::fuzz::kMapFileCapacity);
  for (int m = 0; m < maps; ++m) {
    if (m > 0) store.start_map();
    std::vector<ale::map::KeyframeId> kfs;
    for (int k = 0; k < 4; ++k) {
      std::vector<ale::map::KeyframeFeature> f(12);
      for (int i = 0; i < 12; ++i) {
        f[static_cast<std::size_t>(i)].u = 10.0f + 20.0f * static_cast<float>(i);
        f[static_cast<std::size_t>(i)].v = 30.0f + 5.0f * static_cast<float>(k);
        f[static_cast<std::size_t>(i)].level = static_cast<std::int16_t>(i % 3);
        f[static_cast<std::size_t>(i)].descriptor.bytes[0] = static_cast<std::uint8_t>(i + 16 * k);
      }
      const ale::geometry::SE3 T(ale::geometry::SO3(), ale::geometry::Vec3(-0.1 * k, 0.0, 0.0));
      ale::Result<ale::map::KeyframeId> id = store.add_keyframe(0.5 * k + 10.0 * m, static_cast<std::uint64_t>(k + 10 * m), T, f.data(), 12);
      if (!id.ok()) fail("map seed: " + id.status().to_string());
      kfs.push_back(*id);
      if (k > 0 && !store.restore_parent(*id, kfs[static_cast<std::size_t>(k - 1)]).ok()) fail("map seed: parent");
    }
    for (int l = 0; l < 20; ++l) {
      ale::Result<ale::map::LandmarkId> lm = store.add_landmark(ale::geometry::Vec3(0.1 * l, 0.05 * l, 2.0),
                                                                ale::features::Descriptor{}, kfs[static_cast<std::size_t>(l % 4)]);
      if (!lm.ok()) fail("map seed: " + lm.status().to_string());
      for (int j = 0; j < 2 + l % 2; ++j) {
        if (!store.add_observation(*lm, kfs[static_cast<std::size_t>((l + j) % 4)], l % 12).ok()) break;
      }
    }
    for (ale::map::KeyframeId k : kfs) store.update_connections(k, 1);
    if (!store.add_loop_edge(kfs[0], kfs[3]).ok()) fail("map seed: loop edge");
  }
  const fs::path tmp = dir / ".seed.alemap";
  if (!ale::io::save_map_file(store, ale::fuzz::map_file_context(), tmp.string()).ok()) fail("map seed: save");
  std::vector<std::uint8_t> file;
  if (!ale::io::read_file_bytes(tmp.string(), file).ok()) fail("map seed: read back");
  fs::remove(tmp);
  fs::remove(tmp.string() + ".bak");
  for (const std::uint8_t fix : {std::uint8_t{0}, std::uint8_t{1}}) {
    std::vector<std::uint8_t> seed{fix};
    seed.insert(seed.end(), file.begin(), file.end());
    write_bytes(dir / ("maps" + std::to_string(maps) + (fix ? "_fix_checksums" : "_as_is")), seed);
  }
}

int main(int argc, char** argv) {
  if (argc != 2) fail("usage: fuzz_make_seeds CORPUS_DIR (tests/fuzz/corpus)");
  const fs::path root = argv[1];
  for (const char* d : {"vocabulary", "command", "image", "config", "map_file"}) fs::create_directories(root / d);

  vocabulary(root / "vocabulary", 2, 1);
  vocabulary(root / "vocabulary", 3, 2);

  using ale_lcm::command_t;
  const fs::path c = root / "command";
  command(c, "reset_map", command_t::RESET_MAP, "");
  command(c, "save_map", command_t::SAVE_MAP, "/tmp/map.alemap");
  command(c, "pause", command_t::PAUSE, "");
  command(c, "resume", command_t::RESUME, "");
  command(c, "set_log_level_debug", command_t::SET_LOG_LEVEL, "debug");
  command(c, "set_log_level_unknown", command_t::SET_LOG_LEVEL, "loud");
  command(c, "unknown_kind", 9, "x");
  command(c, "truncated", command_t::SET_LOG_LEVEL, "warning", 3);

  images(root / "image");

  map_file(root / "map_file", 1);
  map_file(root / "map_file", 2);

  std::ofstream conf(root / "config" / "defaults.conf", std::ios::trunc);
  conf << ale::app::print_config(ale::app::DaemonConfig{});
  if (!conf) fail("cannot write config/defaults.conf");
  return 0;
}
