// JSON in and out of the process, safely.
//
// JsonText never throws: nlohmann's writer throws on a string that is not
// valid UTF-8, and such strings reach messages as echoes of hostile input
// (a CSV cell, a query parameter, a path). They are written with U+FFFD in
// place of the bad bytes, so every response and stored report is valid JSON.
//
// ParseJsonBody reads an untrusted body with a bound on nesting and on the
// number of values: no body can exhaust the stack when it is written back
// out, or the memory while it is read. It never throws either.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/field_errors.h"
#include "core/status.h"

namespace thermocomp {

inline constexpr int kMaxJsonDepth = 32;
inline constexpr size_t kMaxJsonValues = 1000000;

inline std::string JsonText(const nlohmann::json& j, int indent = -1) {
  return j.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

// Whether `s` is well-formed UTF-8 (no overlong forms, surrogates or code
// points above U+10FFFF). Free text that is stored must be.
bool ValidUtf8(std::string_view s);

// The parsed body, or nullopt with the error in `errors` (field "body") and
// `status`: InvalidArgument for syntax, numbers beyond double range and
// nesting deeper than kMaxJsonDepth; TooLarge beyond kMaxJsonValues values.
std::optional<nlohmann::json> ParseJsonBody(std::string_view body, FieldErrors& errors,
                                            Status* status = nullptr);

}  // namespace thermocomp
