#include "core/base/text_file.h"

#include <cerrno>
#include <cstring>

namespace ale {

TextFileWriter::~TextFileWriter() { (void)close(); }

Status TextFileWriter::open(const std::string& path, const std::string& what) {
  (void)close();
  path_ = path;
  what_ = what;
  file_ = std::fopen(path.c_str(), "w");
  if (file_ == nullptr) return io_error(name() + ": " + std::strerror(errno));
  return {};
}

Status TextFileWriter::write(const char* text, std::size_t size) {
  if (file_ == nullptr) return {};
  if (std::fwrite(text, 1, size, file_) != size) return io_error(name() + ": write failed: " + std::strerror(errno));
  return {};
}

Status TextFileWriter::close() {
  if (file_ == nullptr) return {};
  const bool write_error = std::ferror(file_) != 0;
  const bool close_error = std::fclose(file_) != 0;
  file_ = nullptr;
  if (write_error || close_error) return io_error(name() + ": data lost on write or close");
  return {};
}

}  // namespace ale
