#include "app/daemon/indicators.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace ale::app {
namespace {

constexpr std::int64_t kFrameNs = 100000000;  // 10 fps of camera time

GpioConfig ir_config(int on_after, int off_after, int min_toggle_ms) {
  GpioConfig c;
  c.ir_on_dark_frames = on_after;
  c.ir_off_normal_frames = off_after;
  c.ir_min_toggle_ms = min_toggle_ms;
  return c;
}

// One character per frame: 'X' extremely dark, 'd' dark, 'n' normal, 'b' bright; returns the
// illuminator's state after each, as '1' / '0'.
std::string run(IrIlluminatorControl& ir, const std::string& classes, std::int64_t& t_ns) {
  std::string out;
  for (char ch : classes) {
    const BrightnessClass c = ch == 'X'   ? BrightnessClass::kExtremelyDark
                              : ch == 'd' ? BrightnessClass::kDark
                              : ch == 'n' ? BrightnessClass::kNormal
                                          : BrightnessClass::kBright;
    out += ir.update(c, t_ns) ? '1' : '0';
    t_ns += kFrameNs;
  }
  return out;
}

TEST(IrIlluminatorTest, OnAfterNDarkFramesOffAfterMNormalOnes) {
  IrIlluminatorControl ir(ir_config(3, 4, 0));
  std::int64_t t = 0;
  EXPECT_EQ(run(ir, "XXnXXXnnnbXX", t), "000001111000");
  EXPECT_EQ(ir.toggles(), 2);
}

TEST(IrIlluminatorTest, DarkFramesBreakBothRunsAndKeepTheState) {
  IrIlluminatorControl ir(ir_config(2, 2, 0));
  std::int64_t t = 0;
  EXPECT_EQ(run(ir, "XdXdXX", t), "000001");
  EXPECT_EQ(run(ir, "ndndnn", t), "111110");
}

TEST(IrIlluminatorTest, NeverTogglesFasterThanTheConfiguredPeriod) {
  // Runs complete after 1 frame, but 1 s (10 frames) must pass between switches.
  IrIlluminatorControl ir(ir_config(1, 1, 1000));
  std::int64_t t = 0;
  const std::string states = run(ir, "XnXnXnXnXnXnXnXnXnXnXnXnXnXnXnXnXnXnXnXnXn", t);
  // On at frame 0; frame 10 (1 s later) is dark again, so the first allowed switch is frame 11.
  EXPECT_EQ(states.substr(0, 13), "1111111111100");
  std::size_t last = 0;
  for (std::size_t i = 1; i < states.size(); ++i) {
    if (states[i] == states[i - 1]) continue;
    EXPECT_GE(i - last, 10u) << "toggled after " << (i - last) << " frames in " << states;
    last = i;
  }
  EXPECT_GE(ir.toggles(), 4);
}

TEST(LedPatternTest, EachStateHasItsPattern) {
  EXPECT_EQ(led_pattern_for(TrackingState::kTracking), LedPattern::kTracking);
  EXPECT_EQ(led_pattern_for(TrackingState::kRelocalized), LedPattern::kTracking);
  EXPECT_EQ(led_pattern_for(TrackingState::kInitializing), LedPattern::kInitializing);
  EXPECT_EQ(led_pattern_for(TrackingState::kNotInitialized), LedPattern::kInitializing);
  EXPECT_EQ(led_pattern_for(TrackingState::kLost), LedPattern::kLost);
  // Lit milliseconds out of one second, sampled every ms, and the number of flashes.
  auto lit_ms = [](LedPattern p, int& flashes) {
    int lit = 0;
    flashes = 0;
    bool was = false;
    for (int ms = 0; ms < 1000; ++ms) {
      const bool on = led_lit(p, 5000000000LL + ms * 1000000LL);
      lit += on;
      flashes += on && !was;
      was = on;
    }
    return lit;
  };
  int flashes = 0;
  EXPECT_EQ(lit_ms(LedPattern::kTracking, flashes), 1000);
  EXPECT_EQ(lit_ms(LedPattern::kInitializing, flashes), 500);
  EXPECT_EQ(flashes, 1);
  EXPECT_EQ(lit_ms(LedPattern::kLost, flashes), 500);
  EXPECT_EQ(flashes, 4);
  EXPECT_EQ(lit_ms(LedPattern::kError, flashes), 200);
  EXPECT_EQ(flashes, 2);
  EXPECT_EQ(lit_ms(LedPattern::kOff, flashes), 0);
}

// The lines on the fake backend: written only on change, IR following the brightness classes.
TEST(IndicatorsTest, DrivesTheFakeLinesFromStateAndBrightness) {
  hal::FakeGpio gpio;
  Indicators ind(gpio, ir_config(2, 2, 0));
  std::int64_t t = 0;
  ASSERT_TRUE(ind.on_frame(TrackingState::kTracking, BrightnessClass::kNormal, t).ok());
  EXPECT_TRUE(gpio.state(hal::GpioLine::kStatusLed));
  EXPECT_FALSE(gpio.state(hal::GpioLine::kIrIlluminator));
  const int writes = gpio.writes();
  ASSERT_TRUE(ind.on_frame(TrackingState::kTracking, BrightnessClass::kExtremelyDark, t += kFrameNs).ok());
  EXPECT_EQ(gpio.writes(), writes) << "nothing changed: nothing written";
  ASSERT_TRUE(ind.on_frame(TrackingState::kTracking, BrightnessClass::kExtremelyDark, t += kFrameNs).ok());
  EXPECT_TRUE(gpio.state(hal::GpioLine::kIrIlluminator));
  EXPECT_EQ(gpio.writes(), writes + 1);
  ASSERT_TRUE(ind.on_error(0).ok());  // the first flash of the error pattern
  EXPECT_EQ(ind.pattern(), LedPattern::kError);
  EXPECT_TRUE(gpio.state(hal::GpioLine::kStatusLed));
  ASSERT_TRUE(ind.on_error(150000000).ok());  // between the two flashes
  EXPECT_FALSE(gpio.state(hal::GpioLine::kStatusLed));
  ASSERT_TRUE(ind.off().ok());
  EXPECT_FALSE(gpio.state(hal::GpioLine::kIrIlluminator));
  EXPECT_FALSE(gpio.state(hal::GpioLine::kStatusLed));
}

}  // namespace
}  // namespace ale::app
