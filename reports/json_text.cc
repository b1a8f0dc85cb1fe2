#include "reports/json_text.h"

#include <cstdint>
#include <optional>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

namespace thermocomp {

bool ValidUtf8(std::string_view s) {
  size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    int extra = 0;
    uint32_t cp = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if ((c & 0xE0) == 0xC0) {
      extra = 1;
      cp = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      extra = 2;
      cp = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      extra = 3;
      cp = c & 0x07;
    } else {
      return false;
    }
    if (i + extra >= s.size()) return false;  // truncated sequence
    for (int k = 1; k <= extra; ++k) {
      const auto cc = static_cast<unsigned char>(s[i + k]);
      if ((cc & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (cc & 0x3F);
    }
    static const uint32_t kMin[] = {0, 0x80, 0x800, 0x10000};
    if (cp < kMin[extra] || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
    i += extra + 1;
  }
  return true;
}

}  // namespace thermocomp

namespace thermocomp {
namespace {

using Json = nlohmann::json;

// Builds the document with nlohmann's own DOM builder, stopping at the
// first value beyond the bounds. (nlohmann's callback parser would do the
// counting too, but it rescans an array at the end of each element:
// quadratic in the number of items.)
class BoundedDomSax : public nlohmann::json_sax<Json> {
 public:
  explicit BoundedDomSax(Json& result) : dom_(result, false) {}

  bool null() override { return Value() && dom_.null(); }
  bool boolean(bool v) override { return Value() && dom_.boolean(v); }
  bool number_integer(number_integer_t v) override { return Value() && dom_.number_integer(v); }
  bool number_unsigned(number_unsigned_t v) override { return Value() && dom_.number_unsigned(v); }
  bool number_float(number_float_t v, const string_t& s) override {
    return Value() && dom_.number_float(v, s);
  }
  bool string(string_t& v) override { return Value() && dom_.string(v); }
  bool binary(binary_t& v) override { return Value() && dom_.binary(v); }
  bool start_object(std::size_t n) override {
    if (!Open()) return false;
    keys_.emplace_back();
    return dom_.start_object(n);
  }
  // A key given twice is refused: which of its values is meant is not
  // said, and the last silently winning let "a":5000,"a":0.1 through.
  bool key(string_t& k) override {
    if (!keys_.back().insert(k).second) {
      duplicate_ = k;
      error_ = "given twice in one object";
      return false;
    }
    return dom_.key(k);
  }
  bool end_object() override {
    --depth_;
    keys_.pop_back();
    return dom_.end_object();
  }
  bool start_array(std::size_t n) override { return Open() && dom_.start_array(n); }
  bool end_array() override {
    --depth_;
    return dom_.end_array();
  }
  bool parse_error(std::size_t position, const std::string&,
                   const nlohmann::detail::exception& e) override {
    error_ = e.id == 406 ? "a number is out of range (beyond +-1.8e308)"
                         : "malformed JSON at byte " + std::to_string(position);
    return false;
  }

  // Empty when the body was read completely.
  const std::string& error() const { return error_; }
  bool too_many_values() const { return too_many_; }
  // The key given twice, when that was the error.
  const std::optional<std::string>& duplicate() const { return duplicate_; }

 private:
  bool Value() {
    if (++values_ <= kMaxJsonValues) return true;
    too_many_ = true;
    error_ = "more than " + std::to_string(kMaxJsonValues) + " JSON values";
    return false;
  }
  bool Open() {
    if (++depth_ > kMaxJsonDepth) {
      error_ = "nested deeper than " + std::to_string(kMaxJsonDepth) + " levels";
      return false;
    }
    return Value();
  }

  nlohmann::detail::json_sax_dom_parser<Json> dom_;
  std::vector<std::unordered_set<std::string>> keys_;  // of each open object
  std::optional<std::string> duplicate_;
  int depth_ = 0;
  size_t values_ = 0;
  bool too_many_ = false;
  std::string error_;
};

}  // namespace

std::optional<nlohmann::json> ParseJsonBody(std::string_view body, FieldErrors& errors,
                                            Status* status) {
  // nlohmann's reader takes a NUL byte for the end of the input and would
  // ignore what follows it; JSON allows none outside a string, nor raw
  // inside one.
  if (const size_t nul = body.find('\0'); nul != std::string_view::npos) {
    errors.push_back(
        {0, "body", "malformed JSON at byte " + std::to_string(nul) + " (a NUL byte)"});
    if (status) *status = Status::InvalidArgument("malformed JSON");
    return std::nullopt;
  }
  Json result;
  BoundedDomSax sax(result);
  const bool complete = Json::sax_parse(body.begin(), body.end(), &sax);
  if (complete && sax.error().empty()) return result;
  errors.push_back({0, sax.duplicate() ? *sax.duplicate() : "body",
                    sax.error().empty() ? "malformed JSON" : sax.error()});
  if (status) {
    *status = sax.too_many_values() ? Status::TooLarge("too many JSON values")
                                    : Status::InvalidArgument("malformed JSON");
  }
  return std::nullopt;
}

}  // namespace thermocomp
