// Tolerant readers for the codecs' decoders: a stored report may predate a
// field, so a missing or mistyped member reads as a stated fallback (NaN
// for numbers that were never computed) rather than throwing.
#pragma once

#include <limits>

#include <nlohmann/json.hpp>

namespace thermocomp::json_read {

inline double NumberOr(const nlohmann::json& j, const char* key,
                       double fallback = std::numeric_limits<double>::quiet_NaN()) {
  auto it = j.find(key);
  return it != j.end() && it->is_number() ? it->get<double>() : fallback;
}

// The member at `key` when it has the expected type, else an empty one.
inline const nlohmann::json& ObjectAt(const nlohmann::json& j, const char* key) {
  static const nlohmann::json kEmpty = nlohmann::json::object();
  auto it = j.find(key);
  return it != j.end() && it->is_object() ? *it : kEmpty;
}

inline const nlohmann::json& ArrayAt(const nlohmann::json& j, const char* key) {
  static const nlohmann::json kEmpty = nlohmann::json::array();
  auto it = j.find(key);
  return it != j.end() && it->is_array() ? *it : kEmpty;
}

// `key` as T, or `fallback` when absent or null. Throws on a wrong type,
// which the decoders turn into a Status.
template <typename T>
T ValueOr(const nlohmann::json& j, const char* key, T fallback) {
  auto it = j.find(key);
  if (it == j.end() || it->is_null()) return fallback;
  return it->get<T>();
}

}  // namespace thermocomp::json_read
