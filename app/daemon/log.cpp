#include "app/daemon/log.h"

#include <syslog.h>

#include <cstdarg>
#include <cstdio>

namespace ale::app {
namespace {

struct LogState {
  LogLevel level = LogLevel::kInfo;
  LogTarget target = LogTarget::kStderr;
  std::string last_error;
};

LogState& state() {
  static LogState s;
  return s;
}

int syslog_priority(LogLevel level) {
  switch (level) {
    case LogLevel::kError: return LOG_ERR;
    case LogLevel::kWarning: return LOG_WARNING;
    case LogLevel::kInfo: return LOG_INFO;
    case LogLevel::kDebug: return LOG_DEBUG;
  }
  return LOG_INFO;
}

}  // namespace

const char* to_string(LogLevel level) {
  switch (level) {
    case LogLevel::kError: return "error";
    case LogLevel::kWarning: return "warning";
    case LogLevel::kInfo: return "info";
    case LogLevel::kDebug: return "debug";
  }
  return "unknown";
}

Result<LogLevel> parse_log_level(const std::string& name) {
  for (LogLevel l : {LogLevel::kError, LogLevel::kWarning, LogLevel::kInfo, LogLevel::kDebug})
    if (name == to_string(l)) return l;
  return invalid_argument("log level '" + name + "' is none of error, warning, info, debug");
}

void set_log_level(LogLevel level) { state().level = level; }
LogLevel log_level() { return state().level; }

void set_log_target(LogTarget target) {
  if (target == LogTarget::kSyslog && state().target != LogTarget::kSyslog)
    openlog("ale-slamd", LOG_PID | LOG_NDELAY, LOG_DAEMON);
  if (target == LogTarget::kStderr && state().target == LogTarget::kSyslog) closelog();
  state().target = target;
}

Status configure_log(const std::string& level, const std::string& target) {
  auto l = parse_log_level(level);
  if (!l.ok()) return l.status();
  if (target != "stderr" && target != "syslog") return invalid_argument("log.target '" + target + "' is not stderr or syslog");
  set_log_level(*l);
  set_log_target(target == "syslog" ? LogTarget::kSyslog : LogTarget::kStderr);
  return {};
}

void log_message(LogLevel level, const char* format, ...) {
  LogState& s = state();
  if (level > s.level) return;  // errors never are: kError is the lowest level there is
  char text[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(text, sizeof text, format, args);
  va_end(args);
  if (level == LogLevel::kError) s.last_error = text;
  if (s.target == LogTarget::kSyslog)
    syslog(syslog_priority(level), "%s", text);
  else
    std::fprintf(stderr, "ale-slamd: %s%s%s\n", level <= LogLevel::kWarning ? to_string(level) : "",
                 level <= LogLevel::kWarning ? ": " : "", text);
}

const std::string& last_error() { return state().last_error; }

}  // namespace ale::app
