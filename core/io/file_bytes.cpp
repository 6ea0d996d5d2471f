#include "core/io/file_bytes.h"

#include <fstream>
#include <iterator>

namespace ale::io {

Status read_file_bytes(const std::string& path, std::vector<std::uint8_t>& out) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return not_found(path + ": cannot open");
  out.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  if (f.bad()) return io_error(path + ": read failed");
  return {};
}

}  // namespace ale::io
