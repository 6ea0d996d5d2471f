// libgpiod backend without GPIO hardware: every error path a wrong configuration takes.
#include "hal/linux/gpiod_lines.h"

#include <gtest/gtest.h>

#include <string>

#include "tests/host/support/test_data.h"

namespace ale::linux_hal {
namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

Result<std::unique_ptr<GpiodLines>> open_led(const std::string& chip, unsigned offset) {
  GpiodLinesOptions o;
  o.status_led = GpioLineMapping{chip, offset, false};
  return GpiodLines::open(o);
}

TEST(GpiodLines, NonexistentChipPathIsNotFoundNamingChipAndOffset) {
  auto lines = open_led("/dev/gpiochip97", 5);
  ASSERT_FALSE(lines.ok());
  EXPECT_EQ(lines.status().code(), StatusCode::kNotFound) << lines.status().to_string();
  EXPECT_TRUE(contains(lines.status().message(), "/dev/gpiochip97")) << lines.status().message();
  EXPECT_TRUE(contains(lines.status().message(), "offset 5")) << lines.status().message();
  EXPECT_TRUE(contains(lines.status().message(), "status_led")) << lines.status().message();
}

TEST(GpiodLines, NonexistentChipNameNumberOrLabelIsNotFound) {
  for (const char* chip : {"gpiochip97", "97", "no-such-pinctrl"}) {
    auto lines = open_led(chip, 0);
    ASSERT_FALSE(lines.ok()) << chip;
    EXPECT_EQ(lines.status().code(), StatusCode::kNotFound) << chip << ": " << lines.status().to_string();
    EXPECT_TRUE(contains(lines.status().message(), chip)) << lines.status().message();
  }
}

TEST(GpiodLines, FileThatIsNotAChipIsRejected) {
  const std::string dir = test::make_temp_dir("gpiod_lines");
  const std::string path = dir + "/not_a_chip";
  ASSERT_TRUE(test::write_file(path, "x"));
  for (const std::string& chip : {path, std::string("/dev/null")}) {
    auto lines = open_led(chip, 1);
    ASSERT_FALSE(lines.ok()) << chip;
    EXPECT_EQ(lines.status().code(), StatusCode::kInvalidArgument) << lines.status().to_string();
    EXPECT_TRUE(contains(lines.status().message(), "not a GPIO chip")) << lines.status().message();
    EXPECT_TRUE(contains(lines.status().message(), chip)) << lines.status().message();
  }
}

TEST(GpiodLines, UnmappedLineIsUnsupported) {
  auto lines = GpiodLines::open(GpiodLinesOptions{});
  ASSERT_TRUE(lines.ok()) << lines.status().to_string();
  Status s = (*lines)->set(hal::GpioLine::kIrIlluminator, true);
  EXPECT_EQ(s.code(), StatusCode::kUnsupported);
  EXPECT_TRUE(contains(s.message(), "ir_illuminator")) << s.message();
  EXPECT_EQ((*lines)->set(hal::GpioLine::kStatusLed, false).code(), StatusCode::kUnsupported);
  EXPECT_EQ((*lines)->describe(), "gpiod: no lines mapped");
}

TEST(GpiodLines, MappingErrorsAreFoundBeforeAnyChipIsOpened) {
  GpiodLinesOptions o;
  o.status_led = GpioLineMapping{"gpiochip97", 3, false};
  o.ir_illuminator = GpioLineMapping{"gpiochip97", 3, true};
  auto same_pin = GpiodLines::open(o);
  ASSERT_FALSE(same_pin.ok());
  EXPECT_EQ(same_pin.status().code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(contains(same_pin.status().message(), "same pin as status_led")) << same_pin.status().message();

  o.ir_illuminator = GpioLineMapping{"", 4, false};
  auto no_chip = GpiodLines::open(o);
  ASSERT_FALSE(no_chip.ok());
  EXPECT_EQ(no_chip.status().code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(contains(no_chip.status().message(), "ir_illuminator")) << no_chip.status().message();
}

}  // namespace
}  // namespace ale::linux_hal
