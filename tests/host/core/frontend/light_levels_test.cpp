// Frame-to-frame matching at each light level (issue 13): short sweeper sequences rendered in the
// test (core/render, the renderer behind ale-render) in two rooms (texture seeds) with their own
// sensor-noise seeds, at normal, normal_dark, dark (normal_dark with the analogue gain capped at
// 3), extremely dark (the `dark` profile, mean grey about 28) and lights switching (off_on);
// pairs 1, 3 and 5 frames apart (15 fps), matched as `ale-features --match` does. Prints the mean
// inliers per mode and level (the table of docs/features.md) and checks ALE against the
// baseline: at least as many inliers 3 frames apart at every level, 15 % more when extremely
// dark. A third room is papered with photographs (the stlouis webcam frames of ../shared/data):
// fine, low-contrast texture instead of the procedural patterns, where lifting a noisy dark frame
// had cost ALE its lead (docs/features.md). Reduced form (ALE_TEST_REDUCED=1, set in the
// sanitizer build where the full form takes about 9 minutes): the first procedural room only and
// 6 frames a sequence (gaps 1, 3 and 5 still have pairs), every level, variant and check kept.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "core/features/orb.h"
#include "core/frontend/frame_path.h"
#include "core/frontend/sequence_match.h"
#include "core/io/image_io.h"
#include "tests/host/core/enhance/real_frames.h"
#include "tests/host/support/test_data.h"
#include "app/tools/lib/render/renderer.h"
#include "app/tools/lib/render/scene.h"
#include "app/tools/lib/render/trajectory.h"

namespace ale::frontend {
namespace {

using features::ExtractorConfig;
using features::ExtractorMode;

struct Level {
  const char* name;
  render::LightProfile light;
  double max_gain;
};

constexpr Level kLevels[] = {
    {"normal", render::LightProfile::kNormal, 8.0},
    {"normal_dark", render::LightProfile::kNormalDark, 8.0},
    {"dark", render::LightProfile::kNormalDark, 3.0},
    {"extremely_dark", render::LightProfile::kDark, 8.0},
    {"lights_switching", render::LightProfile::kOffOn, 8.0},
};

struct Room {
  std::uint32_t texture_seed;  // procedural textures (0: photographs)
  std::uint64_t noise_seed;
  double start_s;  // where on the loop the sequence starts
};

constexpr Room kRooms[] = {{0x5CE4E, 1, 3.0}, {0xA11CE, 7, 12.0}};
// The photo-textured room (one sequence per level, to keep the test short under sanitizers).
constexpr Room kPhotoRoom{0, 5, 20.0};
constexpr const char* kPhotoFolder = "lighting/webcam/stlouis";
// Frames per sequence: 11, or 6 in the reduced form.
int frames_per_sequence() {
  static const int frames = [] {
    if (!test::reduced_run()) return 11;
    std::printf("reduced form (ALE_TEST_REDUCED=1): 1 procedural room, 6 frames per sequence\n");
    return 6;
  }();
  return frames;
}

// The procedural rooms: both, or the first in the reduced form.
std::vector<Room> procedural_rooms() {
  if (test::reduced_run()) return {kRooms[0]};
  return {std::begin(kRooms), std::end(kRooms)};
}
constexpr double kFps = 15.0;
const std::vector<int> kGaps{1, 3, 5};

const render::Scene& scene_of(std::uint32_t seed) {
  static std::map<std::uint32_t, render::Scene> scenes;
  auto it = scenes.find(seed);
  if (it == scenes.end()) {
    render::SceneOptions o;
    o.seed = seed;
    if (seed == 0) {  // the photographs, as ale-render --textures reads them (sorted by name)
      for (const std::string& f : test::image_files(test::data_path(kPhotoFolder))) {
        GrayImage photo;
        const Status st = io::read_gray(f, photo);
        EXPECT_TRUE(st.ok()) << st.to_string();
        if (st.ok()) o.photos.push_back(std::move(photo));
      }
    }
    Result<render::Scene> s = render::build_default_scene(o);
    EXPECT_TRUE(s.ok()) << s.status().to_string();
    it = scenes.emplace(seed, s.ok() ? std::move(*s) : render::Scene{}).first;
  }
  return it->second;
}

std::vector<GrayImage> render_sequence(const Level& level, const Room& room, std::vector<double>* means) {
  render::SequenceConfig c;
  c.light = level.light;
  c.sensor.max_gain = level.max_gain;
  c.fps = kFps;
  const int frames_wanted = frames_per_sequence();
  c.frames = frames_wanted;
  c.seed = room.noise_seed;
  c.supersample = 1;
  c.start_s = room.start_s;
  const render::Scene& scene = scene_of(room.texture_seed);
  const render::Trajectory traj =
      render::make_loop(scene, render::DriveOptions{}, room.start_s + (frames_wanted - 1) / kFps + 0.1);
  Result<render::SequenceRenderer> seq = render::SequenceRenderer::create(scene, traj, render::sweeper_rig(12.0), c);
  EXPECT_TRUE(seq.ok()) << seq.status().to_string();
  std::vector<GrayImage> frames;
  if (!seq.ok()) return frames;
  for (int k = 0; k < frames_wanted; ++k) {
    GrayImage f(c.camera.width, c.camera.height);
    render::FrameRecord rec;
    const Status st = seq->render_next(f.view(), rec);
    EXPECT_TRUE(st.ok()) << st.to_string();
    if (means) means->push_back(rec.mean_grey);
    frames.push_back(std::move(f));
  }
  return frames;
}

struct Variant {
  const char* name;
  ExtractorConfig config;
};

std::vector<Variant> variants() {
  ExtractorConfig baseline;
  baseline.mode = ExtractorMode::kBaseline;
  return {{"baseline", baseline}, {"article", features::article_config()}, {"ale", ExtractorConfig{}}};
}

// Mean inliers [level][variant][gap index] over every pair of `rooms`; prints the table.
std::vector<std::vector<std::vector<double>>> measure(const std::vector<Room>& rooms, const std::vector<Variant>& vs,
                                                      const char* title) {
  std::vector<std::vector<std::vector<double>>> inliers(
      std::size(kLevels), std::vector<std::vector<double>>(vs.size(), std::vector<double>(kGaps.size(), 0.0)));
  std::vector<double> mean_grey(std::size(kLevels), 0.0);
  for (std::size_t l = 0; l < std::size(kLevels); ++l) {
    std::vector<std::vector<std::size_t>> pairs(vs.size(), std::vector<std::size_t>(kGaps.size(), 0));
    std::vector<double> means;
    for (const Room& room : rooms) {
      const std::vector<GrayImage> frames = render_sequence(kLevels[l], room, &means);
      EXPECT_EQ(frames.size(), static_cast<std::size_t>(frames_per_sequence()));
      if (frames.size() != static_cast<std::size_t>(frames_per_sequence())) return inliers;
      for (std::size_t v = 0; v < vs.size(); ++v) {
        Result<std::vector<GapFigures>> r = match_sequence(frames, vs[v].config, kGaps, features::PairMatchParams{});
        EXPECT_TRUE(r.ok()) << r.status().to_string();
        if (!r.ok()) return inliers;
        for (std::size_t g = 0; g < kGaps.size(); ++g) {
          for (const features::PairMatchFigures& p : (*r)[g].pairs) inliers[l][v][g] += p.inliers;
          pairs[v][g] += (*r)[g].pairs.size();
        }
      }
    }
    for (double m : means) mean_grey[l] += m / static_cast<double>(means.size());
    for (std::size_t v = 0; v < vs.size(); ++v)
      for (std::size_t g = 0; g < kGaps.size(); ++g)
        inliers[l][v][g] /= static_cast<double>(std::max<std::size_t>(pairs[v][g], 1));
  }
  std::printf("%s: mean inliers (pairs 1 / 3 / 5 frames apart, %zu sequence(s) a level, %d frames at %g fps, 640x480):\n",
              title, rooms.size(), frames_per_sequence(), kFps);
  std::printf("  %-17s %5s", "level", "grey");
  for (const Variant& v : vs) std::printf(" | %-19s", v.name);
  std::printf("\n");
  for (std::size_t l = 0; l < std::size(kLevels); ++l) {
    std::printf("  %-17s %5.1f", kLevels[l].name, mean_grey[l]);
    for (std::size_t v = 0; v < vs.size(); ++v)
      std::printf(" | %5.1f %5.1f %5.1f  ", inliers[l][v][0], inliers[l][v][1], inliers[l][v][2]);
    std::printf("\n");
  }
  return inliers;
}

// The issue's figures: ALE (variant `ale`) at least the baseline's (variant 0) 3 frames apart at
// every level, and `dark_margin` times it extremely dark.
void expect_issue_figures(const std::vector<std::vector<std::vector<double>>>& inliers, std::size_t ale,
                          double dark_margin) {
  constexpr std::size_t kBase = 0, kGap3 = 1;
  for (std::size_t l = 0; l < std::size(kLevels); ++l) {
    EXPECT_GT(inliers[l][kBase][kGap3], 10.0) << kLevels[l].name << ": the rendered frames must be matchable";
    EXPECT_GE(inliers[l][ale][kGap3], inliers[l][kBase][kGap3]) << kLevels[l].name;
  }
  EXPECT_GE(inliers[3][ale][kGap3], dark_margin * inliers[3][kBase][kGap3]) << "extremely dark: x" << dark_margin;
  std::printf("extremely dark, 3 apart: ale / baseline = %.3f\n", inliers[3][ale][kGap3] / inliers[3][kBase][kGap3]);
}

TEST(LightLevels, AleMatchesAtLeastTheBaselineAtEveryLevel) {
  expect_issue_figures(measure(procedural_rooms(), variants(), "procedural rooms"), 2, 1.15);
}

TEST(LightLevels, AleMatchesAtLeastTheBaselineInAPhotoTexturedRoom) {
  ALE_REQUIRE_DATA(photos, kPhotoFolder);
  const std::vector<Variant> all = variants();
  const std::vector<Variant> vs{all[0], all[2]};  // baseline, ale: the article's recipe only in the table above
  // At least the baseline at every level, extremely dark too; the issue's 15 % more is not met on
  // photo textures (here x1.107; docs/features.md has the figures per room and why).
  expect_issue_figures(measure({kPhotoRoom}, vs, "photo-textured room (stlouis)"), 1, 1.0);
}

// A frame graded normal gets exactly the baseline's keypoints and descriptors.
TEST(LightLevels, NormalFramesGiveTheBaselineOutput) {
  const std::vector<GrayImage> frames = render_sequence(kLevels[0], kRooms[0], nullptr);
  ExtractorConfig base;
  base.mode = ExtractorMode::kBaseline;
  FramePath a, b;
  ASSERT_TRUE(a.configure(ExtractorConfig{}).ok());
  ASSERT_TRUE(b.configure(base).ok());
  for (const GrayImage& f : frames) {
    std::vector<features::Keypoint> ka, kb;
    std::vector<features::Descriptor> da, db;
    ASSERT_TRUE(a.extract(f.view(), ka, da).ok());
    ASSERT_TRUE(b.extract(f.view(), kb, db).ok());
    ASSERT_EQ(a.stats().brightness, BrightnessClass::kNormal);
    ASSERT_EQ(ka.size(), kb.size());
    for (std::size_t i = 0; i < ka.size(); ++i) {
      EXPECT_EQ(ka[i].x, kb[i].x);
      EXPECT_EQ(ka[i].y, kb[i].y);
      EXPECT_EQ(ka[i].angle_deg, kb[i].angle_deg);
      EXPECT_EQ(da[i].bytes, db[i].bytes);
    }
  }
}

}  // namespace
}  // namespace ale::frontend
