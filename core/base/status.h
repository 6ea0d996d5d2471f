// Status and Result: how every fallible call in ale-slam reports why it failed.
// No exceptions on the hot path; libraries that throw are wrapped at the boundary.
#pragma once

#include <optional>
#include <string>
#include <utility>

namespace ale {

enum class StatusCode {
  kOk = 0,
  kInvalidArgument,  // a caller passed something out of range or inconsistent
  kNotFound,         // a file, device or key that should exist does not
  kIoError,          // the OS refused a read, write or ioctl
  kCorruptData,      // a file or buffer exists but its content is malformed
  kOutOfMemory,      // a fixed-capacity pool is exhausted
  kUnsupported,      // an optional capability this backend does not have
  kUnavailable,      // a device went away or is busy
  kTimeout,          // nothing arrived in the allowed time
  kNotConverged,     // an iterative solver stopped at its iteration limit (its best state is kept)
  kFrameRejected,    // a frame the SLAM core will not process (e.g. its timestamp does not increase)
  kEndOfStream,      // a replay has no more frames (not an error for the caller's loop)
  kInternal,         // a broken invariant inside ale-slam
};

const char* to_string(StatusCode code);

class [[nodiscard]] Status {
 public:
  Status() = default;  // ok
  Status(StatusCode code, std::string message) : code_(code), message_(std::move(message)) {}

  static Status ok_status() { return Status(); }

  bool ok() const { return code_ == StatusCode::kOk; }
  StatusCode code() const { return code_; }
  const std::string& message() const { return message_; }
  // "<code>: <message>", or "ok".
  std::string to_string() const;

 private:
  StatusCode code_ = StatusCode::kOk;
  std::string message_;
};

inline Status invalid_argument(std::string m) { return {StatusCode::kInvalidArgument, std::move(m)}; }
inline Status frame_rejected(std::string m) { return {StatusCode::kFrameRejected, std::move(m)}; }
inline Status not_found(std::string m) { return {StatusCode::kNotFound, std::move(m)}; }
inline Status io_error(std::string m) { return {StatusCode::kIoError, std::move(m)}; }
inline Status corrupt_data(std::string m) { return {StatusCode::kCorruptData, std::move(m)}; }
inline Status out_of_memory(std::string m) { return {StatusCode::kOutOfMemory, std::move(m)}; }
inline Status unsupported(std::string m) { return {StatusCode::kUnsupported, std::move(m)}; }
inline Status unavailable(std::string m) { return {StatusCode::kUnavailable, std::move(m)}; }
inline Status end_of_stream(std::string m) { return {StatusCode::kEndOfStream, std::move(m)}; }
inline Status internal_error(std::string m) { return {StatusCode::kInternal, std::move(m)}; }

// A value or the Status that says why there is none.
template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : value_(std::move(value)) {}  // NOLINT: implicit on purpose
  Result(Status status) : status_(std::move(status)) {  // NOLINT
    if (status_.ok()) status_ = internal_error("Result constructed from an ok Status without a value");
  }

  bool ok() const { return value_.has_value(); }
  const Status& status() const { return status_; }
  T& value() & { return *value_; }
  const T& value() const& { return *value_; }
  T&& value() && { return std::move(*value_); }
  T* operator->() { return &*value_; }
  const T* operator->() const { return &*value_; }
  T& operator*() & { return *value_; }
  const T& operator*() const& { return *value_; }

 private:
  std::optional<T> value_;
  Status status_;
};

}  // namespace ale

// Return early from a function returning Status or Result<T> when `expr` fails.
#define ALE_RETURN_IF_ERROR(expr)                  \
  do {                                             \
    ::ale::Status ale_status_ = (expr);            \
    if (!ale_status_.ok()) return ale_status_;     \
  } while (0)
