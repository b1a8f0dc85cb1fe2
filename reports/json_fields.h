// JsonFields: the fields of one object of a JSON request, read without
// throwing. Every field that is missing when required, of the wrong JSON
// type or out of its range is recorded as a FieldError (the item's index
// and the field's path, e.g. "runs.direction") and read as nullopt, so a
// codec reads every field it needs and reports everything wrong at once.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/field_errors.h"
#include "core/time_format.h"

namespace thermocomp {

// Free text (notes, reasons): at most this many bytes of valid UTF-8.
inline constexpr size_t kMaxTextLength = 1000;

class JsonFields {
 public:
  enum Need { kRequired, kOptional };

  // `path` prefixes field names in errors ("runs." for the items of runs).
  JsonFields(const nlohmann::json& object, FieldErrors& errors, size_t index = 0,
             std::string path = "");

  // False (and an error naming `what`) when the value is not an object.
  bool IsObject(const char* what = "body");
  bool Has(const char* key) const;

  std::optional<std::string> String(const char* key, Need need = kRequired,
                                    size_t max_length = kMaxTextLength);
  // A finite number within [min, max].
  std::optional<double> Number(const char* key, Need need = kRequired,
                               double min = -std::numeric_limits<double>::max(),
                               double max = std::numeric_limits<double>::max());
  // An integer (no fraction, no exponent beyond int64) within [min, max].
  std::optional<int64_t> Integer(const char* key, Need need, int64_t min, int64_t max);
  std::optional<bool> Bool(const char* key, Need need = kOptional);
  // RFC 3339 text or integer Unix milliseconds, within [kEarliestTsMs, kLatestTsMs).
  std::optional<int64_t> Timestamp(const char* key, Need need = kRequired);
  // Arrays and objects: a pointer to the value, or null (with an error when
  // present with the wrong type, or required and missing).
  const nlohmann::json* Array(const char* key, Need need = kRequired);
  const nlohmann::json* Object(const char* key, Need need = kRequired);
  std::optional<std::vector<std::string>> Strings(const char* key, Need need = kOptional,
                                                  size_t max_items = 1000);
  // Numbers of an array value (all finite), or nullopt with an error.
  std::optional<std::vector<double>> Numbers(const char* key, Need need = kRequired,
                                             size_t max_items = 100000);

  // The reader of a nested object (an item of an array at `index`, or a
  // field), sharing the error list.
  JsonFields Item(const nlohmann::json& value, size_t index, const std::string& path) const;
  JsonFields Field(const nlohmann::json& value, const char* key) const;

  void Error(const std::string& field, std::string message);
  FieldErrors& errors() { return errors_; }

 private:
  const nlohmann::json* Find(const char* key, Need need, const char* expected);
  std::string Path(const char* key) const { return path_ + key; }

  const nlohmann::json& j_;
  FieldErrors& errors_;
  size_t index_;
  std::string path_;
};

}  // namespace thermocomp
