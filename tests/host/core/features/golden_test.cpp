// Golden values of the ORB front end on real frames (../shared/data): for each frame and mode the
// keypoint count and a 64-bit FNV-1a hash of every keypoint (x, y, level, angle, score, as bytes)
// and descriptor. A refactor that changes the extractor's output in any bit fails here. The
// values are the same on every kernel path (SSE2 and scalar on x86_64, NEON on ARM, and with
// ALE_FORCE_REF=1), which is the kernels' bit-exactness contract; a change that is meant to alter
// the output updates them in the same commit (the failure message prints the new table row).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "core/features/orb.h"
#include "core/frontend/frame_path.h"
#include "core/io/image_io.h"
#include "tests/host/support/test_data.h"

namespace ale::features {
namespace {

// FNV-1a, 64 bits: small, fixed, and the same on every platform (bytes in, little-endian values).
class Fnv1a64 {
 public:
  void add_bytes(const void* data, std::size_t n) {
    const auto* p = static_cast<const std::uint8_t*>(data);
    for (std::size_t i = 0; i < n; ++i) {
      hash_ ^= p[i];
      hash_ *= 0x100000001b3ULL;
    }
  }
  void add_u32(std::uint32_t v) {
    const std::uint8_t b[4] = {static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8),
                               static_cast<std::uint8_t>(v >> 16), static_cast<std::uint8_t>(v >> 24)};
    add_bytes(b, sizeof b);
  }
  void add_float(float f) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &f, sizeof bits);
    add_u32(bits);
  }
  std::uint64_t value() const { return hash_; }

 private:
  std::uint64_t hash_ = 0xcbf29ce484222325ULL;
};

std::uint64_t hash_output(const std::vector<Keypoint>& kps, const std::vector<Descriptor>& desc) {
  Fnv1a64 h;
  for (const Keypoint& k : kps) {
    h.add_float(k.x);
    h.add_float(k.y);
    h.add_u32(static_cast<std::uint32_t>(k.level));
    h.add_float(k.angle_deg);
    h.add_u32(static_cast<std::uint32_t>(k.score));
  }
  for (const Descriptor& d : desc) h.add_bytes(d.bytes.data(), d.bytes.size());
  return h.value();
}

// The frames: real ones as recorded, and relit copies of the normal EuRoC frame (integer maths,
// rounded, clipped) so that ALE's grading sees every class.
enum class Relit { kNone, kQuarter, kDim, kWashed, kFifteenPercent, kFaded };

struct Frame {
  const char* name;
  const char* path;  // under ../shared/data
  Relit relit;
  BrightnessClass ale_class;  // what ALE's grader must say (fresh grader, no hysteresis)
};

constexpr const char* kEurocNormal = "euroc_v101_micro/mav0/cam0/data/1403715273262142976.png";

constexpr Frame kFrames[] = {
    {"euroc", kEurocNormal, Relit::kNone, BrightnessClass::kNormal},
    {"euroc_dark", "lighting/dark_frame/euroc_dark.png", Relit::kNone, BrightnessClass::kExtremelyDark},
    {"euroc_x0.25", kEurocNormal, Relit::kQuarter, BrightnessClass::kExtremelyDark},
    {"euroc_x0.45", kEurocNormal, Relit::kDim, BrightnessClass::kDark},
    // Washed out but with its contrast (sigma >= bright_min_sigma): treated as normal (issue 13).
    {"euroc_washed", kEurocNormal, Relit::kWashed, BrightnessClass::kNormal},
    // Bright and flat (sigma about 21): the negative path.
    {"euroc_faded", kEurocNormal, Relit::kFaded, BrightnessClass::kBright},
    // Dark enough that the baseline falls short of its budget (features_real_test.cpp).
    {"euroc_dark_x0.15", "lighting/dark_frame/euroc_dark.png", Relit::kFifteenPercent, BrightnessClass::kExtremelyDark},
    {"tum", "tum_fr2_desk_20/rgb/1311868169.163498.png", Relit::kNone, BrightnessClass::kNormal},
};

void relight(Relit r, GrayImage& img) {
  for (auto& v : img.pixels) {
    int out = v;
    switch (r) {
      case Relit::kNone: break;
      case Relit::kQuarter: out = (v * 25 + 50) / 100; break;
      case Relit::kDim: out = (v * 45 + 50) / 100; break;
      case Relit::kFifteenPercent: out = (v * 15 + 50) / 100; break;
      case Relit::kWashed: out = std::min(255, (v * 130 + 50) / 100 + 70); break;
      case Relit::kFaded: out = (v * 40 + 50) / 100 + 150; break;
    }
    v = static_cast<std::uint8_t>(out);
  }
}

struct Golden {
  const char* frame;
  ExtractorMode mode;
  int count;
  std::uint64_t hash;
};

// Re-measured for issue 13 (normal and contrasty washed frames now give the baseline's output;
// modes he and gamma added; session 11: the 3x3 denoise of extremely dark frames changes ALE's
// rows of the dark frames). Measured at the commit that added this test (host SSE2, host ALE_FORCE_REF=1 and armhf NEON
// under qemu-arm agree).
constexpr Golden kGolden[] = {
    {"euroc", ExtractorMode::kBaseline, 1000, 0x01d8eb44fb7e3f9dULL},
    {"euroc", ExtractorMode::kClahe, 1000, 0x5197e4094fcebc3fULL},
    {"euroc", ExtractorMode::kAle, 1000, 0x01d8eb44fb7e3f9dULL},
    {"euroc", ExtractorMode::kHe, 1000, 0xcdb86a9f78f5d956ULL},
    {"euroc", ExtractorMode::kGamma, 1000, 0x01d8eb44fb7e3f9dULL},
    {"euroc_dark", ExtractorMode::kBaseline, 1000, 0x51f5ded5a52c830eULL},
    {"euroc_dark", ExtractorMode::kClahe, 1000, 0xae0c735f1eab093cULL},
    {"euroc_dark", ExtractorMode::kAle, 1000, 0xf3fd7587a9ae00c0ULL},
    {"euroc_dark", ExtractorMode::kHe, 1000, 0x8ee0cf5d99acff45ULL},
    {"euroc_dark", ExtractorMode::kGamma, 1000, 0x37d5d4a413efbf09ULL},
    {"euroc_x0.25", ExtractorMode::kBaseline, 1000, 0x9b52249e809f5df7ULL},
    {"euroc_x0.25", ExtractorMode::kClahe, 1000, 0x6b90c016ce40ea41ULL},
    {"euroc_x0.25", ExtractorMode::kAle, 1000, 0xc1eb74e629f8e434ULL},
    {"euroc_x0.25", ExtractorMode::kHe, 1000, 0x128e86d58b4694a5ULL},
    {"euroc_x0.25", ExtractorMode::kGamma, 1000, 0xe6318317da0d118cULL},
    {"euroc_x0.45", ExtractorMode::kBaseline, 1000, 0xf87dae0d56fe6744ULL},
    {"euroc_x0.45", ExtractorMode::kClahe, 1000, 0xeb22e199394ed33fULL},
    {"euroc_x0.45", ExtractorMode::kAle, 1000, 0xee3bdc7e38955fa1ULL},
    {"euroc_x0.45", ExtractorMode::kHe, 1000, 0x5836e129a19d914eULL},
    {"euroc_x0.45", ExtractorMode::kGamma, 1000, 0x60364cb12bb1f85cULL},
    {"euroc_washed", ExtractorMode::kBaseline, 1000, 0x4050b2cdfc5753e8ULL},
    {"euroc_washed", ExtractorMode::kClahe, 1000, 0x5bd4ab6a8d2b431eULL},
    {"euroc_washed", ExtractorMode::kAle, 1000, 0x4050b2cdfc5753e8ULL},
    {"euroc_washed", ExtractorMode::kHe, 1000, 0xe29bb7221d875e5cULL},
    {"euroc_washed", ExtractorMode::kGamma, 1000, 0x4050b2cdfc5753e8ULL},
    {"euroc_faded", ExtractorMode::kBaseline, 1000, 0x7f5db746eadcd8a1ULL},
    {"euroc_faded", ExtractorMode::kClahe, 1000, 0x475e81ae590fd044ULL},
    {"euroc_faded", ExtractorMode::kAle, 1000, 0x988e113b67869ed8ULL},
    {"euroc_faded", ExtractorMode::kHe, 1000, 0x2a2d225cb504ae9aULL},
    {"euroc_faded", ExtractorMode::kGamma, 1000, 0x7f5db746eadcd8a1ULL},
    {"euroc_dark_x0.15", ExtractorMode::kBaseline, 307, 0xe02875e89e5104dbULL},
    {"euroc_dark_x0.15", ExtractorMode::kClahe, 874, 0x59cf626f7d5394b1ULL},
    {"euroc_dark_x0.15", ExtractorMode::kAle, 1000, 0x5d1eecb60203b072ULL},
    {"euroc_dark_x0.15", ExtractorMode::kHe, 1000, 0x430d1309136832c8ULL},
    {"euroc_dark_x0.15", ExtractorMode::kGamma, 963, 0x5e29380efefc17c9ULL},
    {"tum", ExtractorMode::kBaseline, 1000, 0x53c2ad07c61ec0c0ULL},
    {"tum", ExtractorMode::kClahe, 1000, 0x408101f9affb6707ULL},
    {"tum", ExtractorMode::kAle, 1000, 0x53c2ad07c61ec0c0ULL},
    {"tum", ExtractorMode::kHe, 1000, 0xb632eaca1d99299eULL},
    {"tum", ExtractorMode::kGamma, 1000, 0xf30b7cc9d6055c03ULL},
};

// "Ale" for kAle, ...: the enumerator's name without its k.
const char* enum_suffix(ExtractorMode m) {
  switch (m) {
    case ExtractorMode::kAle: return "Ale";
    case ExtractorMode::kBaseline: return "Baseline";
    case ExtractorMode::kClahe: return "Clahe";
    case ExtractorMode::kHe: return "He";
    case ExtractorMode::kGamma: return "Gamma";
  }
  return "?";
}

const Golden* find_golden(const char* frame, ExtractorMode mode) {
  for (const Golden& g : kGolden)
    if (std::strcmp(g.frame, frame) == 0 && g.mode == mode) return &g;
  return nullptr;
}

TEST(ExtractorGolden, EveryFrameAndModeGivesThePinnedOutput) {
  int checked = 0;
  std::string table;  // the rows as they should read, printed on a mismatch
  for (const Frame& f : kFrames) {
    ALE_REQUIRE_DATA(path, f.path);
    GrayImage img;
    ASSERT_TRUE(io::read_gray(path, img).ok()) << path;
    relight(f.relit, img);
    for (ExtractorMode mode : {ExtractorMode::kBaseline, ExtractorMode::kClahe, ExtractorMode::kAle, ExtractorMode::kHe,
                               ExtractorMode::kGamma}) {
      ExtractorConfig cfg;
      cfg.mode = mode;
      frontend::FramePath ex;
      ASSERT_TRUE(ex.configure(cfg).ok());
      std::vector<Keypoint> kps;
      std::vector<Descriptor> desc;
      const Status st = ex.extract(img.view(), kps, desc);
      ASSERT_TRUE(st.ok()) << st.to_string();
      ASSERT_EQ(kps.size(), desc.size());
      if (mode == ExtractorMode::kAle) {
        EXPECT_EQ(ex.stats().brightness, f.ale_class) << f.name << ": got " << to_string(ex.stats().brightness) << " at mean " << ex.stats().mean;
      }
      const int count = static_cast<int>(kps.size());
      const std::uint64_t hash = hash_output(kps, desc);
      char row[160];
      std::snprintf(row, sizeof row, "    {\"%s\", ExtractorMode::k%s, %d, 0x%016llxULL},\n", f.name,
                    enum_suffix(mode), count,
                    static_cast<unsigned long long>(hash));
      table += row;
      const Golden* g = find_golden(f.name, mode);
      if (g == nullptr) {
        ADD_FAILURE() << "no golden value for " << f.name << " " << to_string(mode);
        continue;
      }
      EXPECT_EQ(count, g->count) << f.name << " " << to_string(mode);
      EXPECT_EQ(hash, g->hash) << f.name << " " << to_string(mode);
      ++checked;
    }
  }
  EXPECT_EQ(checked, static_cast<int>(std::size(kGolden)));
  if (HasFailure()) std::printf("The output as it is now:\n%s", table.c_str());
}

}  // namespace
}  // namespace ale::features
