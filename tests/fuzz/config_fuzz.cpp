// The daemon's configuration parser, parse_config() (app/config.h), on arbitrary text: it either
// refuses the text with a message or gives a configuration that passes validate_config(), and
// then print_config() of that configuration parses back to a configuration that prints the same
// (print_config's promise, which --print-config and the reload rely on). parse_T_bc() (the
// odometry's camera-to-body matrix, also read from the file) gets the same text.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "app/config.h"

namespace {

void check(bool ok) {
  if (!ok) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace ale::app;
  const std::string text(reinterpret_cast<const char*>(data), size);
  (void)parse_T_bc(text);

  DaemonConfig config;
  if (!parse_config(text, "fuzz.conf", config).ok()) return 0;
  check(validate_config(config).ok());
  const std::string printed = print_config(config);
  DaemonConfig again;
  check(parse_config(printed, "printed.conf", again).ok());
  check(print_config(again) == printed);
  return 0;
}
