// The IR illuminator over a rendered light-off / light-on sequence (ale-render --light off_on:
// lamps off from 30 % to 60 % of the sequence), replayed through the daemon's loop onto a GPIO
// backend that records every write with the frame it followed.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include "app/daemon/frame_loop.h"
#include "tests/host/app/rendered_sequence.h"
#include "tests/host/support/test_data.h"

namespace ale::app {
namespace {

struct Write {
  hal::GpioLine line;
  bool on;
  std::size_t frame;  // index of the frame whose status was the last published before the write
};

class RecordingGpio final : public hal::Gpio {
 public:
  explicit RecordingGpio(const hal::FakePoseSink& sink) : sink_(sink) {}
  Status set(hal::GpioLine line, bool on) override {
    writes.push_back({line, on, sink_.reports.empty() ? 0 : sink_.reports.size() - 1});
    return {};
  }
  std::string describe() const override { return "recording gpio"; }
  std::vector<Write> writes;

 private:
  const hal::FakePoseSink& sink_;
};

// First index i such that classes[i - n + 1 .. i] all satisfy `pred`, searching from `from`.
template <class Pred>
std::size_t end_of_first_run(const std::vector<BrightnessClass>& classes, std::size_t from, int n, Pred pred) {
  int run = 0;
  for (std::size_t i = from; i < classes.size(); ++i) {
    run = pred(classes[i]) ? run + 1 : 0;
    if (run == n) return i;
  }
  return classes.size();
}

TEST(IrRenderedTest, IlluminatorFollowsTheLightsOffAndOnAgain) {
  const std::string dir = test::make_temp_dir("ir-off-on") + "/seq";
  ASSERT_TRUE(test::render_sequence(dir, "--frames 40 --fps 15 --width 160 --height 120 --supersample 1 --light off_on"));
  hal::FakePoseSink sink;
  RecordingGpio gpio(sink);
  test::RenderedReplay replay;
  ASSERT_TRUE(replay.open(dir, sink, gpio));
  DaemonConfig config;
  config.gpio.ir_on_dark_frames = 3;
  config.gpio.ir_off_normal_frames = 4;
  config.gpio.ir_min_toggle_ms = 0;
  RunSummary summary;
  Status s = run_frame_loop(config, *replay.deps, summary);
  ASSERT_TRUE(s.ok()) << s.to_string();
  ASSERT_EQ(sink.reports.size(), 40u);

  std::vector<BrightnessClass> classes;
  for (const hal::StatusReport& r : sink.reports) classes.push_back(r.brightness);
  auto dark = [](BrightnessClass c) { return c == BrightnessClass::kExtremelyDark; };
  auto lit = [](BrightnessClass c) { return c == BrightnessClass::kNormal || c == BrightnessClass::kBright; };
  const std::size_t on_at = end_of_first_run(classes, 0, 3, dark);
  ASSERT_LT(on_at, classes.size()) << "the rendered lights-off part must grade extremely dark";
  EXPECT_GE(on_at, 12u) << "lamps go off at 30 % of 40 frames";
  const std::size_t off_at = end_of_first_run(classes, on_at + 1, 4, lit);
  ASSERT_LT(off_at, classes.size()) << "the lamps come on again";

  std::vector<std::pair<bool, std::size_t>> ir;
  for (const Write& w : gpio.writes)
    if (w.line == hal::GpioLine::kIrIlluminator) ir.emplace_back(w.on, w.frame);
  // Off at the first frame, on after the third dark frame, off after the fourth lit one, and the
  // final off when the loop ends is not a change (already off).
  ASSERT_EQ(ir.size(), 3u);
  EXPECT_EQ(ir[0], std::make_pair(false, std::size_t{0}));
  EXPECT_EQ(ir[1], std::make_pair(true, on_at));
  EXPECT_EQ(ir[2], std::make_pair(false, off_at));
}

}  // namespace
}  // namespace ale::app
