// A text file written line by line where losing a line must not pass unnoticed (frame logs,
// trajectories): every write is checked, and close() reports what the buffered writes and the
// close itself lost. Errors name the file and what it is ("frame log /tmp/f.csv: ...").
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>

#include "core/base/status.h"

namespace ale {

class TextFileWriter {
 public:
  TextFileWriter() = default;
  ~TextFileWriter();
  TextFileWriter(const TextFileWriter&) = delete;
  TextFileWriter& operator=(const TextFileWriter&) = delete;
  // what: how errors name the file ("frame log"). kIoError when it cannot be created.
  Status open(const std::string& path, const std::string& what);
  // Writes `size` bytes; nothing when not open.
  Status write(const char* text, std::size_t size);
  Status write(const std::string& text) { return write(text.data(), text.size()); }
  // Flushes and closes; kIoError if anything written was lost. Nothing when not open.
  Status close();
  bool is_open() const { return file_ != nullptr; }
  // "frame log /tmp/f.csv"
  std::string name() const { return what_ + " " + path_; }

 private:
  std::FILE* file_ = nullptr;
  std::string path_;
  std::string what_;
};

}  // namespace ale
