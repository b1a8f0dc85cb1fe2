// FieldError / FieldErrors: what is wrong with a request, item by item.
// FieldErrors keeps the first kMaxReported errors in full and counts the
// rest, so a body of a million bad items costs a hundred messages, not a
// million (memory and response size stay bounded).
#pragma once

#include <cstddef>
#include <initializer_list>
#include <string>
#include <vector>

namespace thermocomp {

// One rejected item of a batch: where (item index, or CSV data row from 0),
// which field, why.
struct FieldError {
  size_t index = 0;
  std::string field;
  std::string message;
};

class FieldErrors {
 public:
  static constexpr size_t kMaxReported = 100;

  FieldErrors() = default;
  FieldErrors(std::initializer_list<FieldError> list) {
    for (const auto& e : list) push_back(e);
  }

  void push_back(FieldError e) {
    if (items_.size() < kMaxReported) items_.push_back(std::move(e));
    ++total_;
  }
  bool empty() const { return total_ == 0; }
  void clear() {
    items_.clear();
    total_ = 0;
  }
  // Errors kept in full (at most kMaxReported).
  size_t size() const { return items_.size(); }
  // Errors found in all, kept or only counted.
  size_t total() const { return total_; }
  const FieldError& operator[](size_t i) const { return items_[i]; }
  const FieldError& front() const { return items_.front(); }
  std::vector<FieldError>::const_iterator begin() const { return items_.begin(); }
  std::vector<FieldError>::const_iterator end() const { return items_.end(); }

 private:
  std::vector<FieldError> items_;
  size_t total_ = 0;
};

}  // namespace thermocomp
