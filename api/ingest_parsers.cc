#include "api/ingest_parsers.h"

#include <charconv>
#include <cmath>

#include <nlohmann/json.hpp>

#include "server/time_format.h"

namespace thermocomp::api {
namespace {

using nlohmann::json;

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r'))
    s.remove_suffix(1);
  return s;
}

// Splits CSV text into lines of fields (no quoting: identifiers and numbers only).
std::vector<std::vector<std::string_view>> SplitCsv(std::string_view body) {
  std::vector<std::vector<std::string_view>> rows;
  size_t pos = 0;
  while (pos < body.size()) {
    size_t end = body.find('\n', pos);
    if (end == std::string_view::npos) end = body.size();
    std::string_view line = Trim(body.substr(pos, end - pos));
    pos = end + 1;
    if (line.empty()) continue;
    std::vector<std::string_view> cells;
    size_t c = 0;
    while (true) {
      size_t comma = line.find(',', c);
      cells.push_back(
          Trim(line.substr(c, comma == std::string_view::npos ? line.npos : comma - c)));
      if (comma == std::string_view::npos) break;
      c = comma + 1;
    }
    rows.push_back(std::move(cells));
  }
  return rows;
}

std::optional<double> ParseDouble(std::string_view s) {
  double v;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size() || s.empty()) {
    // from_chars rejects "nan"/"inf" spellings in some forms; treat them as non-finite numbers.
    if (s == "nan" || s == "NaN" || s == "inf" || s == "-inf" || s == "Infinity") return NAN;
    return std::nullopt;
  }
  return v;
}

std::optional<int64_t> TsFromJson(const json& j) {
  if (j.is_number_integer()) return j.get<int64_t>();
  if (j.is_string()) return ParseTs(j.get<std::string>());
  return std::nullopt;
}

const char* kTsHelp = "must be RFC 3339 UTC or integer Unix milliseconds";

std::optional<json> ParseJson(const std::string& body, std::vector<FieldError>& errors) {
  try {
    return json::parse(body);
  } catch (const json::parse_error& e) {
    errors.push_back({0, "body", std::string("malformed JSON at byte ") + std::to_string(e.byte)});
    return std::nullopt;
  }
}

}  // namespace

std::optional<int64_t> ParseTs(const std::string& text) {
  if (!text.empty() && (std::isdigit(static_cast<unsigned char>(text[0])) || text[0] == '-') &&
      text.find_first_not_of("-0123456789") == std::string::npos) {
    int64_t v;
    auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (ec == std::errc() && p == text.data() + text.size()) return v;
    return std::nullopt;
  }
  return ParseRfc3339(text);
}

// Reads {"samples": [{"sensor": s, "ts": t, "value": v}, ...]} as events,
// straight into the inputs: no document tree for a hot path that carries
// thousands of samples per request. Unknown keys are ignored.
class TemperatureSax : public nlohmann::json_sax<json> {
 public:
  TemperatureSax(std::vector<TemperatureInput>& out, std::vector<FieldError>& errors,
                 const char* channel_key)
      : out_(out), errors_(errors), channel_key_(channel_key) {}

  bool start_object(std::size_t) override {
    ++depth_;
    if (depth_ == 2 && in_samples_) {
      current_ = TemperatureInput{};
      seen_ = 0;
    } else if (depth_ == 2 || depth_ > 2) {
      return Fail("sample", "must be a flat object");
    }
    return true;
  }
  bool end_object() override {
    if (depth_ == 2 && in_samples_) {
      const size_t i = out_.size();
      if (!(seen_ & kSensor)) errors_.push_back({i, channel_key_, "required string"});
      if (!(seen_ & kTs)) errors_.push_back({i, "ts", kTsHelp});
      if (!(seen_ & kValue)) errors_.push_back({i, "value", "required number"});
      out_.push_back(std::move(current_));
    }
    --depth_;
    return true;
  }
  bool start_array(std::size_t) override {
    if (depth_ == 1 && key_ == "samples") {
      in_samples_ = true;
      saw_samples_ = true;
      return true;
    }
    if (depth_ >= 2) return Fail("sample", "must be a flat object");
    return Fail("samples", "body must be {\"samples\": [...]}");
  }
  bool end_array() override {
    in_samples_ = false;
    return true;
  }
  bool key(string_t& k) override {
    key_ = k;
    return true;
  }
  bool string(string_t& s) override {
    if (!InSample()) return Top("samples");
    if (key_ == channel_key_) {
      current_.sensor = s;
      seen_ |= kSensor;
    } else if (key_ == "ts") {
      if (auto ts = ParseTs(s)) current_.ts_ms = *ts, seen_ |= kTs;
    }
    return true;
  }
  bool number_integer(number_integer_t v) override { return Number(static_cast<double>(v), v); }
  bool number_unsigned(number_unsigned_t v) override {
    return Number(static_cast<double>(v), static_cast<int64_t>(v));
  }
  bool number_float(number_float_t v, const string_t&) override { return Number(v, std::nullopt); }
  bool boolean(bool) override { return InSample() || Top("samples"); }
  bool null() override { return InSample() || Top("samples"); }
  bool binary(binary_t&) override { return Fail("body", "binary values are not JSON"); }
  bool parse_error(std::size_t position, const std::string&,
                   const nlohmann::detail::exception&) override {
    errors_.push_back({0, "body", "malformed JSON at byte " + std::to_string(position)});
    return false;
  }
  bool Finish() {
    if (errors_.empty() && !saw_samples_) {
      errors_.push_back({0, "samples", "body must be {\"samples\": [...]}"});
    }
    return errors_.empty();
  }

 private:
  static constexpr int kSensor = 1, kTs = 2, kValue = 4;
  bool InSample() const { return in_samples_ && depth_ == 2; }
  // A scalar at the top level is only an error when it is the samples key.
  bool Top(const char* field) {
    if (depth_ == 1 && key_ == field) return Fail(field, "body must be {\"samples\": [...]}");
    if (depth_ == 0) return Fail("samples", "body must be {\"samples\": [...]}");
    return true;
  }
  bool Number(double v, std::optional<int64_t> integer) {
    if (!InSample()) return Top("samples");
    if (key_ == "value") {
      current_.value = v;
      seen_ |= kValue;
    } else if (key_ == "ts" && integer) {
      current_.ts_ms = *integer;
      seen_ |= kTs;
    }
    return true;
  }
  bool Fail(const char* field, const char* message) {
    errors_.push_back({out_.size(), field, message});
    return false;
  }

  std::vector<TemperatureInput>& out_;
  std::vector<FieldError>& errors_;
  const char* channel_key_;  // "sensor", or "signal" for auxiliary signals
  TemperatureInput current_;
  std::string key_;
  int depth_ = 0, seen_ = 0;
  bool in_samples_ = false, saw_samples_ = false;
};

// Samples of named channels: temperatures ("sensor") or signals ("signal").
bool ParseChannelJson(const std::string& body, const char* key, std::vector<TemperatureInput>& out,
                      std::vector<FieldError>& errors) {
  TemperatureSax sax(out, errors, key);
  out.reserve(body.size() / 48);
  const bool parsed = json::sax_parse(body, &sax);
  return parsed && sax.Finish();
}

bool ParseChannelCsv(const std::string& body, const std::string& key,
                     std::vector<TemperatureInput>& out, std::vector<FieldError>& errors) {
  auto rows = SplitCsv(body);
  if (rows.empty() || rows[0].empty() || rows[0][0] != "ts" || rows[0].size() < 2) {
    errors.push_back(
        {0, "header", "CSV must start with a header ts," + key + ",value or ts,<" + key + ">,..."});
    return false;
  }
  const auto& header = rows[0];
  const bool long_form = header.size() == 3 && header[1] == key && header[2] == "value";
  out.reserve((rows.size() - 1) * (long_form ? 1 : header.size() - 1));
  for (size_t r = 1; r < rows.size(); ++r) {
    const auto& cells = rows[r];
    const size_t index = r - 1;
    if (cells.size() != header.size()) {
      errors.push_back({index, "row",
                        "expected " + std::to_string(header.size()) + " fields, got " +
                            std::to_string(cells.size())});
      continue;
    }
    auto ts = ParseTs(std::string(cells[0]));
    if (!ts) {
      errors.push_back({index, "ts", kTsHelp});
      continue;
    }
    if (long_form) {
      auto v = ParseDouble(cells[2]);
      if (!v)
        errors.push_back({index, "value", "not a number"});
      else
        out.push_back({std::string(cells[1]), *ts, *v});
      continue;
    }
    for (size_t c = 1; c < cells.size(); ++c) {
      if (cells[c].empty()) continue;  // a sensor without a reading at this time
      auto v = ParseDouble(cells[c]);
      if (!v)
        errors.push_back({index, std::string(header[c]), "not a number"});
      else
        out.push_back({std::string(header[c]), *ts, *v});
    }
    if (errors.size() > 100) break;
  }
  return errors.empty();
}

bool ParseTemperaturesJson(const std::string& body, std::vector<TemperatureInput>& out,
                           std::vector<FieldError>& errors) {
  return ParseChannelJson(body, "sensor", out, errors);
}

bool ParseTemperaturesCsv(const std::string& body, std::vector<TemperatureInput>& out,
                          std::vector<FieldError>& errors) {
  return ParseChannelCsv(body, "sensor", out, errors);
}

namespace {

std::vector<SignalInput> AsSignals(const std::vector<TemperatureInput>& samples) {
  std::vector<SignalInput> out;
  out.reserve(samples.size());
  for (const auto& s : samples) out.push_back({s.sensor, s.ts_ms, s.value});
  return out;
}

}  // namespace

bool ParseSignalsJson(const std::string& body, std::vector<SignalInput>& out,
                      std::vector<FieldError>& errors) {
  std::vector<TemperatureInput> samples;
  const bool ok = ParseChannelJson(body, "signal", samples, errors);
  out = AsSignals(samples);
  return ok;
}

bool ParseSignalsCsv(const std::string& body, std::vector<SignalInput>& out,
                     std::vector<FieldError>& errors) {
  std::vector<TemperatureInput> samples;
  const bool ok = ParseChannelCsv(body, "signal", samples, errors);
  out = AsSignals(samples);
  return ok;
}

bool ParseEventJson(const std::string& body, EventInput& out, std::vector<FieldError>& errors) {
  auto j = ParseJson(body, errors);
  if (!j) return false;
  if (!j->is_object()) {
    errors.push_back({0, "body", "must be a JSON object {ts, kind, note}"});
    return false;
  }
  auto ts = TsFromJson(j->value("ts", json()));
  if (!ts)
    errors.push_back({0, "ts", kTsHelp});
  else
    out.ts_ms = *ts;
  if (!j->contains("kind") || !(*j)["kind"].is_string()) {
    errors.push_back({0, "kind", "required string: maintenance, collision, column_check or other"});
  } else {
    out.kind = (*j)["kind"].get<std::string>();
  }
  if (j->contains("note")) {
    if (!(*j)["note"].is_string())
      errors.push_back({0, "note", "must be a string"});
    else
      out.note = (*j)["note"].get<std::string>();
  }
  return errors.empty();
}

bool ParseProbePointsJson(const std::string& body, std::vector<ProbePointInput>& out,
                          std::vector<FieldError>& errors) {
  auto j = ParseJson(body, errors);
  if (!j) return false;
  if (!j->is_object() || !j->contains("points") || !(*j)["points"].is_array()) {
    errors.push_back({0, "points", "body must be {\"points\": [...]}"});
    return false;
  }
  size_t i = 0;
  for (const json& p : (*j)["points"]) {
    ProbePointInput in;
    if (!p.is_object()) {
      errors.push_back({i++, "point", "must be an object"});
      continue;
    }
    if (auto it = p.find("run"); it != p.end() && it->is_string())
      in.run = *it;
    else
      errors.push_back({i, "run", "required string"});
    if (auto it = p.find("k"); it != p.end() && it->is_number_integer())
      in.k = it->get<int>();
    else
      errors.push_back({i, "k", "required integer"});
    if (auto ts = p.contains("ts") ? TsFromJson(p["ts"]) : std::nullopt)
      in.ts_ms = *ts;
    else
      errors.push_back({i, "ts", kTsHelp});
    for (const char* part : {"position", "deviation"}) {
      if (!p.contains(part)) continue;
      if (!p[part].is_object()) {
        errors.push_back({i, part, "must be an object of axis: mm"});
        continue;
      }
      for (auto& [axis, v] : p[part].items()) {
        if (!v.is_number()) {
          errors.push_back({i, std::string(part) + "." + axis, "must be a number"});
          continue;
        }
        auto& av = in.axes[axis];
        (std::string(part) == "position" ? av.position_mm : av.deviation_mm) = v.get<double>();
      }
    }
    if (p.contains("temperatures")) {
      if (!p["temperatures"].is_object()) {
        errors.push_back({i, "temperatures", "must be an object of sensor: degC"});
      } else {
        for (auto& [sensor, v] : p["temperatures"].items()) {
          if (v.is_number())
            in.temperatures[sensor] = v.get<double>();
          else
            errors.push_back({i, "temperatures." + sensor, "must be a number"});
        }
      }
    }
    out.push_back(std::move(in));
    ++i;
  }
  return errors.empty();
}

bool ParseProbePointsCsv(const std::string& body, std::vector<ProbePointInput>& out,
                         std::vector<FieldError>& errors) {
  auto rows = SplitCsv(body);
  if (rows.empty() || rows[0].size() < 4 || rows[0][0] != "ts" || rows[0][1] != "run" ||
      rows[0][2] != "k") {
    errors.push_back(
        {0, "header",
         "CSV must start with ts,run,k, then pos_<axis>/dev_<axis> and sensor columns"});
    return false;
  }
  const auto& header = rows[0];
  for (size_t r = 1; r < rows.size(); ++r) {
    const auto& cells = rows[r];
    const size_t index = r - 1;
    if (cells.size() != header.size()) {
      errors.push_back({index, "row", "expected " + std::to_string(header.size()) + " fields"});
      continue;
    }
    ProbePointInput in;
    auto ts = ParseTs(std::string(cells[0]));
    if (!ts)
      errors.push_back({index, "ts", kTsHelp});
    else
      in.ts_ms = *ts;
    in.run = std::string(cells[1]);
    int k = -1;
    auto [p, ec] = std::from_chars(cells[2].data(), cells[2].data() + cells[2].size(), k);
    if (ec != std::errc() || p != cells[2].data() + cells[2].size()) {
      errors.push_back({index, "k", "not an integer"});
    }
    in.k = k;
    for (size_t c = 3; c < cells.size(); ++c) {
      if (cells[c].empty()) continue;
      auto v = ParseDouble(cells[c]);
      std::string name(header[c]);
      if (!v) {
        errors.push_back({index, name, "not a number"});
        continue;
      }
      if (name.rfind("pos_", 0) == 0)
        in.axes[name.substr(4)].position_mm = *v;
      else if (name.rfind("dev_", 0) == 0)
        in.axes[name.substr(4)].deviation_mm = *v;
      else
        in.temperatures[name] = *v;
    }
    out.push_back(std::move(in));
  }
  return errors.empty();
}

}  // namespace thermocomp::api
