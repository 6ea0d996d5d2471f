#include "hal/linux/gpiod_lines.h"

#include <gpiod.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <utility>

namespace ale::linux_hal {

namespace {

std::string where(hal::GpioLine line, const GpioLineMapping& m) {
  return std::string("gpio ") + hal::to_string(line) + " (chip '" + m.chip + "', offset " + std::to_string(m.offset) +
         ")";
}

bool all_digits(const std::string& s) {
  return !s.empty() && s.size() <= 6 && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// The chip by path, number, name or label, in the way the configuration spells it.
gpiod_chip* open_chip(const std::string& chip) {
  if (chip.front() == '/') return gpiod_chip_open(chip.c_str());
  if (all_digits(chip)) return gpiod_chip_open_by_number(static_cast<unsigned>(std::strtoul(chip.c_str(), nullptr, 10)));
  if (chip.rfind("gpiochip", 0) == 0) return gpiod_chip_open_by_name(chip.c_str());
  return gpiod_chip_open_by_label(chip.c_str());
}

}  // namespace

Result<std::unique_ptr<GpiodLines>> GpiodLines::open(const GpiodLinesOptions& options) {
  std::vector<std::pair<hal::GpioLine, GpioLineMapping>> wanted;
  if (options.status_led) wanted.emplace_back(hal::GpioLine::kStatusLed, *options.status_led);
  if (options.ir_illuminator) wanted.emplace_back(hal::GpioLine::kIrIlluminator, *options.ir_illuminator);
  // The whole mapping is checked before any chip is touched.
  for (std::size_t i = 0; i < wanted.size(); ++i) {
    const auto& [line, mapping] = wanted[i];
    if (mapping.chip.empty()) return invalid_argument(where(line, mapping) + ": no chip given");
    for (std::size_t j = 0; j < i; ++j)
      if (wanted[j].second.chip == mapping.chip && wanted[j].second.offset == mapping.offset)
        return invalid_argument(where(line, mapping) + ": the same pin as " + hal::to_string(wanted[j].first));
  }
  std::unique_ptr<GpiodLines> lines(new GpiodLines());
  for (const auto& [line, mapping] : wanted) ALE_RETURN_IF_ERROR(lines->request(line, mapping, options.consumer));
  return Result<std::unique_ptr<GpiodLines>>(std::move(lines));
}

Status GpiodLines::request(hal::GpioLine line, const GpioLineMapping& mapping, const std::string& consumer) {
  const std::string what = where(line, mapping);

  gpiod_chip* chip = open_chip(mapping.chip);
  if (chip == nullptr) {
    const int err = errno;
    if (err == ENOENT || err == ENODEV)
      return not_found(what + ": no such GPIO chip (gpiodetect lists the chips)");
    if (err == ENOTTY || err == EINVAL) return invalid_argument(what + ": not a GPIO chip (" + std::strerror(err) + ")");
    if (err == EACCES || err == EPERM) return io_error(what + ": permission denied on the GPIO chip");
    return io_error(what + ": cannot open the GPIO chip: " + std::strerror(err));
  }
  const unsigned count = gpiod_chip_num_lines(chip);
  if (mapping.offset >= count) {
    const std::string label = gpiod_chip_label(chip);
    gpiod_chip_close(chip);
    return invalid_argument(what + ": offset out of range, chip '" + label + "' has " + std::to_string(count) +
                            " lines");
  }
  gpiod_line* handle = gpiod_chip_get_line(chip, mapping.offset);
  if (handle == nullptr) {
    const int err = errno;
    gpiod_chip_close(chip);
    return io_error(what + ": cannot get the line: " + std::strerror(err));
  }
  const int flags = mapping.active_low ? GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW : 0;
  if (gpiod_line_request_output_flags(handle, consumer.c_str(), flags, 0) < 0) {
    const int err = errno;
    const char* holder = gpiod_line_consumer(handle);
    gpiod_chip_close(chip);
    if (err == EBUSY)
      return unavailable(what + ": the line is in use by '" + (holder ? holder : "another process") + "'");
    return io_error(what + ": cannot request the line as an output: " + std::strerror(err));
  }
  held_.push_back({line, mapping, chip, handle});
  return {};
}

GpiodLines::~GpiodLines() {
  for (Held& h : held_) {
    // Released lines keep their level: an IR illuminator left on would heat and drain the battery.
    gpiod_line_set_value(h.handle, 0);
    gpiod_line_release(h.handle);
    gpiod_chip_close(h.chip);
  }
}

Status GpiodLines::set(hal::GpioLine line, bool on) {
  for (Held& h : held_) {
    if (h.line != line) continue;
    if (gpiod_line_set_value(h.handle, on ? 1 : 0) < 0)
      return io_error(where(line, h.mapping) + ": setting " + (on ? "on" : "off") + " failed: " + std::strerror(errno));
    return {};
  }
  return unsupported(std::string("gpio ") + hal::to_string(line) + " is not mapped to a chip and offset on this board");
}

std::string GpiodLines::describe() const {
  if (held_.empty()) return "gpiod: no lines mapped";
  std::string s = "gpiod:";
  for (const Held& h : held_)
    s += std::string(" ") + hal::to_string(h.line) + "=" + h.mapping.chip + ":" + std::to_string(h.mapping.offset) +
         (h.mapping.active_low ? " (active low)" : "");
  return s;
}

}  // namespace ale::linux_hal
