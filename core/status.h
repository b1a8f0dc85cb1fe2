// Status: the outcome of an operation that can fail, returned as a value.
// A Status is either OK or carries a code and a message meant for a person.
// Codes map onto the HTTP problem types of the API (see api/problem.h).
#pragma once

#include <string>
#include <utility>

namespace thermocomp {

class Status {
 public:
  enum class Code {
    kOk = 0,
    kInvalidArgument,      // malformed input (HTTP 400)
    kNotFound,             // unknown machine, axis, model (404)
    kConflict,             // same key, different value (409)
    kUnprocessable,        // valid syntax, unusable content (422)
    kTooLarge,             // body or batch too large (413)
    kFailedPrecondition,   // state does not allow it (409)
    kUnavailable,          // not ready, or busy: retry (503)
    kInsufficientStorage,  // the disk is full (507)
    kInternal,             // a bug or an I/O failure (500)
  };

  Status() = default;
  static Status Ok() { return Status(); }
  static Status InvalidArgument(std::string m) { return {Code::kInvalidArgument, std::move(m)}; }
  static Status NotFound(std::string m) { return {Code::kNotFound, std::move(m)}; }
  static Status Conflict(std::string m) { return {Code::kConflict, std::move(m)}; }
  static Status Unprocessable(std::string m) { return {Code::kUnprocessable, std::move(m)}; }
  static Status TooLarge(std::string m) { return {Code::kTooLarge, std::move(m)}; }
  static Status FailedPrecondition(std::string m) {
    return {Code::kFailedPrecondition, std::move(m)};
  }
  static Status Unavailable(std::string m) { return {Code::kUnavailable, std::move(m)}; }
  static Status InsufficientStorage(std::string m) {
    return {Code::kInsufficientStorage, std::move(m)};
  }
  static Status Internal(std::string m) { return {Code::kInternal, std::move(m)}; }

  bool ok() const { return code_ == Code::kOk; }
  Code code() const { return code_; }
  const std::string& message() const { return message_; }
  std::string ToString() const { return ok() ? "OK" : message_; }

 private:
  Status(Code c, std::string m) : code_(c), message_(std::move(m)) {}
  Code code_ = Code::kOk;
  std::string message_;
};

// A value or the Status that explains why there is none.
template <typename T>
class StatusOr {
 public:
  StatusOr(T value) : value_(std::move(value)) {}          // NOLINT: implicit by design
  StatusOr(Status status) : status_(std::move(status)) {}  // NOLINT
  bool ok() const { return status_.ok(); }
  const Status& status() const { return status_; }
  const T& value() const& { return value_; }
  T& value() & { return value_; }
  T&& value() && { return std::move(value_); }
  const T* operator->() const { return &value_; }
  T* operator->() { return &value_; }
  const T& operator*() const& { return value_; }
  T& operator*() & { return value_; }
  T value_or(T fallback) const& { return ok() ? value_ : std::move(fallback); }

 private:
  Status status_;
  T value_{};
};

}  // namespace thermocomp
