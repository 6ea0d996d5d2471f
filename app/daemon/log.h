// The daemon's log: levelled messages to stderr or syslog (log.level, log.target), and the last
// error kept for the status message. One per process: the loop, the board and main log through it.
#pragma once

#include <string>

#include "core/base/status.h"

namespace ale::app {

enum class LogLevel { kError, kWarning, kInfo, kDebug };
// "error", "warning", "info", "debug"
const char* to_string(LogLevel level);
// kInvalidArgument naming the accepted names otherwise.
Result<LogLevel> parse_log_level(const std::string& name);

enum class LogTarget { kStderr, kSyslog };

void set_log_level(LogLevel level);
LogLevel log_level();
// Opens syslog (ident ale-slamd, facility daemon) for kSyslog.
void set_log_target(LogTarget target);
// Applies log.level and log.target (names as validated by the configuration).
Status configure_log(const std::string& level, const std::string& target);

// printf-style; dropped when above the current level. Errors are also kept as last_error().
void log_message(LogLevel level, const char* format, ...) __attribute__((format(printf, 2, 3)));
const std::string& last_error();

}  // namespace ale::app
