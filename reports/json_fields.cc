#include "reports/json_fields.h"

#include <cmath>

#include "reports/json_text.h"

namespace thermocomp {
namespace {

std::string Range(double min, double max) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.10g..%.10g", min, max);
  return buf;
}

}  // namespace

JsonFields::JsonFields(const nlohmann::json& object, FieldErrors& errors, size_t index,
                       std::string path)
    : j_(object), errors_(errors), index_(index), path_(std::move(path)) {}

void JsonFields::Error(const std::string& field, std::string message) {
  errors_.push_back({index_, field, std::move(message)});
}

bool JsonFields::IsObject(const char* what) {
  if (j_.is_object()) return true;
  Error(path_.empty() ? what : path_.substr(0, path_.size() - 1), "must be a JSON object");
  return false;
}

bool JsonFields::Has(const char* key) const {
  return j_.is_object() && j_.contains(key) && !j_[key].is_null();
}

const nlohmann::json* JsonFields::Find(const char* key, Need need, const char* expected) {
  if (!Has(key)) {
    if (need == kRequired) Error(Path(key), std::string("required ") + expected);
    return nullptr;
  }
  return &j_[key];
}

std::optional<std::string> JsonFields::String(const char* key, Need need, size_t max_length) {
  const nlohmann::json* v = Find(key, need, "string");
  if (!v) return std::nullopt;
  if (!v->is_string()) {
    Error(Path(key), "must be a string");
    return std::nullopt;
  }
  const std::string& s = v->get_ref<const std::string&>();
  if (s.size() > max_length) {
    Error(Path(key), "longer than " + std::to_string(max_length) + " bytes");
    return std::nullopt;
  }
  return s;
}

std::optional<double> JsonFields::Number(const char* key, Need need, double min, double max) {
  const nlohmann::json* v = Find(key, need, "number");
  if (!v) return std::nullopt;
  if (!v->is_number()) {
    Error(Path(key), "must be a number");
    return std::nullopt;
  }
  const double d = v->get<double>();
  if (!std::isfinite(d) || d < min || d > max) {
    Error(Path(key), "must be a finite number within " + Range(min, max));
    return std::nullopt;
  }
  return d;
}

std::optional<int64_t> JsonFields::Integer(const char* key, Need need, int64_t min, int64_t max) {
  const nlohmann::json* v = Find(key, need, "integer");
  if (!v) return std::nullopt;
  const std::string range = std::to_string(min) + ".." + std::to_string(max);
  if (!v->is_number_integer()) {
    Error(Path(key), "must be an integer within " + range);
    return std::nullopt;
  }
  if (v->is_number_unsigned() && v->get<uint64_t>() > static_cast<uint64_t>(max)) {
    Error(Path(key), "must be an integer within " + range);
    return std::nullopt;
  }
  const int64_t i = v->get<int64_t>();
  if (i < min || i > max) {
    Error(Path(key), "must be an integer within " + range);
    return std::nullopt;
  }
  return i;
}

std::optional<bool> JsonFields::Bool(const char* key, Need need) {
  const nlohmann::json* v = Find(key, need, "boolean");
  if (!v) return std::nullopt;
  if (!v->is_boolean()) {
    Error(Path(key), "must be true or false");
    return std::nullopt;
  }
  return v->get<bool>();
}

std::optional<int64_t> JsonFields::Timestamp(const char* key, Need need) {
  const nlohmann::json* v = Find(key, need, "time (RFC 3339 or Unix ms)");
  if (!v) return std::nullopt;
  std::optional<int64_t> ms;
  if (v->is_number_integer() && !(v->is_number_unsigned() && v->get<uint64_t>() > INT64_MAX)) {
    ms = v->get<int64_t>();
    if (*ms < kEarliestTsMs || *ms >= kLatestTsMs) ms.reset();
  } else if (v->is_string()) {
    ms = ParseTimestamp(v->get_ref<const std::string&>());
  }
  if (!ms) {
    Error(Path(key),
          "must be RFC 3339 (e.g. 2026-03-01T06:00:00Z) or integer Unix milliseconds, "
          "from 2000 to 2099");
  }
  return ms;
}

const nlohmann::json* JsonFields::Array(const char* key, Need need) {
  const nlohmann::json* v = Find(key, need, "array");
  if (v && !v->is_array()) {
    Error(Path(key), "must be an array");
    return nullptr;
  }
  return v;
}

const nlohmann::json* JsonFields::Object(const char* key, Need need) {
  const nlohmann::json* v = Find(key, need, "object");
  if (v && !v->is_object()) {
    Error(Path(key), "must be an object");
    return nullptr;
  }
  return v;
}

std::optional<std::vector<std::string>> JsonFields::Strings(const char* key, Need need,
                                                            size_t max_items) {
  const nlohmann::json* v = Array(key, need);
  if (!v) return std::nullopt;
  std::vector<std::string> out;
  for (const auto& item : *v) {
    if (!item.is_string() || item.get_ref<const std::string&>().size() > kMaxTextLength) {
      Error(Path(key), "must be an array of strings");
      return std::nullopt;
    }
    out.push_back(item.get<std::string>());
  }
  if (out.size() > max_items) {
    Error(Path(key), "more than " + std::to_string(max_items) + " items");
    return std::nullopt;
  }
  return out;
}

std::optional<std::vector<double>> JsonFields::Numbers(const char* key, Need need,
                                                       size_t max_items) {
  const nlohmann::json* v = Array(key, need);
  if (!v) return std::nullopt;
  if (v->size() > max_items) {
    Error(Path(key), "more than " + std::to_string(max_items) + " items");
    return std::nullopt;
  }
  std::vector<double> out;
  out.reserve(v->size());
  for (const auto& item : *v) {
    if (!item.is_number() || !std::isfinite(item.get<double>())) {
      Error(Path(key), "must be an array of finite numbers");
      return std::nullopt;
    }
    out.push_back(item.get<double>());
  }
  return out;
}

JsonFields JsonFields::Item(const nlohmann::json& value, size_t index,
                            const std::string& path) const {
  return JsonFields(value, errors_, index, path_ + path + ".");
}

JsonFields JsonFields::Field(const nlohmann::json& value, const char* key) const {
  return JsonFields(value, errors_, index_, path_ + key + ".");
}

}  // namespace thermocomp
