// The rendered room gives a corner detector something real: FAST-9 (the features module's) finds
// plenty of corners spread over normal frames.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "core/features/fast.h"
#include "app/tools/lib/render/renderer.h"
#include "render_fixture.h"

namespace ale::render {
namespace {

struct CornerCount {
  std::size_t total = 0;
  int cells_with_corners = 0;  // of a 4 x 3 grid
};

CornerCount corners_at(LightProfile light, double start_s, int threshold) {
  SequenceConfig c;
  c.camera = PinholeCamera::wide(320, 240);
  c.frames = 1;
  c.light = light;
  c.start_s = start_s;
  const Trajectory traj = make_loop(test::small_scene(), DriveOptions{}, start_s + 0.1);
  Result<SequenceRenderer> seq = SequenceRenderer::create(test::small_scene(), traj, sweeper_rig(12.0), c);
  EXPECT_TRUE(seq.ok()) << seq.status().to_string();
  CornerCount out;
  if (!seq.ok()) return out;
  GrayImage img(320, 240);
  GrayImage scores(320, 240);
  FrameRecord rec;
  EXPECT_TRUE(seq->render_next(img.view(), rec).ok());
  std::vector<features::FastCorner> raw, kept;
  const int b = features::kFastRadius + 1;
  EXPECT_TRUE(features::fast9_detect(img.view(), {b, b, 320 - 2 * b, 240 - 2 * b}, threshold, scores.view(), raw).ok());
  features::fast9_nonmax(scores.view(), raw, kept);
  std::array<int, 12> cells{};
  for (const features::FastCorner& k : kept) ++cells[static_cast<std::size_t>((k.y / 80) * 4 + k.x / 80)];
  out.total = kept.size();
  for (int n : cells) out.cells_with_corners += n > 0;
  return out;
}

TEST(RenderCorners, NormalFramesHaveCornersAllOver) {
  for (double t : {0.0, 9.0, 14.0}) {
    const CornerCount n = corners_at(LightProfile::kNormal, t, 20);
    std::printf("normal, %.0f s into the loop: %zu FAST-9 corners at threshold 20, %d of 12 cells\n", t, n.total,
                n.cells_with_corners);
    EXPECT_GE(n.total, 100u) << t;
    EXPECT_GE(n.cells_with_corners, 6) << t;
  }
}

}  // namespace
}  // namespace ale::render
