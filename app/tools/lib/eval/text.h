// Line and field helpers shared by the eval readers (trajectories, frame logs), so that every
// reader reports problems the same way: "file:line: problem".
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "core/base/status.h"

namespace ale::eval {

std::string_view trim(std::string_view s);
std::vector<std::string_view> split_whitespace(std::string_view line);
// Comma-separated fields, each trimmed; an empty line gives one empty field.
std::vector<std::string_view> split_commas(std::string_view line);

// Parses the whole token as a double; false for empty tokens or trailing garbage.
bool parse_double(std::string_view token, double* value);

// Text safe inside HTML elements and attribute values (& < > " escaped).
std::string html_escape(const std::string& s);

// "name:line: ", the prefix of every message about a line.
std::string where(const std::string& name, std::size_t line_no);

// The whole file; not_found when it cannot be opened, `what` names the kind of file.
Result<std::string> read_text_file(const std::string& path, const char* what);

// Splits `text` into lines (without '\n' or a trailing '\r'), calling visit(line_no, line) for
// each, line numbers from 1; stops at the first error.
template <class Visit>
Status for_each_line(std::string_view text, Visit&& visit) {
  std::size_t line_no = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    ++line_no;
    std::string_view line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    ALE_RETURN_IF_ERROR(visit(line_no, line));
    start = end + 1;
  }
  return Status::ok_status();
}

}  // namespace ale::eval
