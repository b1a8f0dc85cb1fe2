#include "api/ingest_parsers.h"

#include <charconv>
#include <cmath>
#include <set>

#include <nlohmann/json.hpp>

#include "core/time_format.h"
#include "reports/json_fields.h"
#include "reports/json_text.h"

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
      cells.push_back(Trim(
          line.substr(c, comma == std::string_view::npos ? std::string_view::npos : comma - c)));
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

// The optional `compensated` column: true/false/1/0 (an empty cell is false).
std::optional<bool> ParseCompensated(std::string_view s) {
  if (s.empty() || s == "false" || s == "0") return false;
  if (s == "true" || s == "1") return true;
  return std::nullopt;
}

constexpr const char* kCompensatedColumn = "compensated";
constexpr const char* kCompensatedHelp = "must be true, false, 1 or 0";

// A column named twice would let one cell overwrite the other unseen (or
// make a sample conflict with itself): the header is refused, naming it.
bool RepeatedColumn(const std::vector<std::string_view>& header, FieldErrors& errors) {
  std::set<std::string_view> seen;
  for (std::string_view name : header) {
    if (!seen.insert(name).second) {
      errors.push_back({0, std::string(name), "column named twice in the header"});
      return true;
    }
  }
  return false;
}

const char* kTsHelp =
    "must be RFC 3339 (e.g. 2026-03-01T06:00:00Z) or integer Unix milliseconds, from 2000 to 2099";

}  // namespace

// Reads {"samples": [{"sensor": s, "ts": t, "value": v}, ...]} as events,
// straight into the inputs: no document tree for a hot path that carries
// thousands of samples per request. Unknown keys are ignored; nesting is
// bounded like every JSON body (kMaxJsonDepth).
class TemperatureSax : public nlohmann::json_sax<json> {
 public:
  TemperatureSax(std::vector<TemperatureInput>& out, FieldErrors& errors, const char* channel_key)
      : out_(out), errors_(errors), channel_key_(channel_key) {}

  bool start_object(std::size_t) override {
    if (!Open()) return false;
    if (in_samples_) {
      if (level_ != 3) return Fail("sample", "must be a flat object {sensor, ts, value}");
      current_ = TemperatureInput{};
      seen_ = 0;
      return true;
    }
    if (level_ == 2 && key_ == "samples") return Fail("samples", "must be an array");
    return true;  // the body, or an unknown key's object
  }
  bool end_object() override {
    if (in_samples_ && level_ == 3) {
      const size_t i = items_++;
      if (!(seen_ & kSensor)) errors_.push_back({i, channel_key_, "required string"});
      if (!(seen_ & kTs)) errors_.push_back({i, "ts", kTsHelp});
      if (!(seen_ & kValue)) errors_.push_back({i, "value", "required number"});
      if (seen_ == (kSensor | kTs | kValue)) out_.push_back(std::move(current_));
    }
    --level_;
    return true;
  }
  bool start_array(std::size_t) override {
    if (!Open()) return false;
    if (level_ == 1) return Fail("body", "must be {\"samples\": [...]}");
    if (in_samples_) return Fail("sample", "must be a flat object {sensor, ts, value}");
    if (level_ == 2 && key_ == "samples") {
      in_samples_ = true;
      saw_samples_ = true;
    }
    return true;  // samples, or an unknown key's array
  }
  bool end_array() override {
    if (in_samples_ && level_ == 2) in_samples_ = false;
    --level_;
    return true;
  }
  bool key(string_t& k) override {
    key_ = k;
    return true;
  }
  bool string(string_t& s) override {
    if (!Scalar()) return false;
    if (!InSample()) return true;
    if (key_ == channel_key_) {
      current_.sensor = s;
      seen_ |= kSensor;
    } else if (key_ == "ts") {
      if (auto ts = ParseTimestamp(s)) current_.ts_ms = *ts, seen_ |= kTs;
    } else if (key_ == "value") {
      errors_.push_back({items_, "value", "must be a number"});
    }
    return true;
  }
  bool number_integer(number_integer_t v) override {
    return Number(static_cast<double>(v), v >= kEarliestTsMs && v < kLatestTsMs);
  }
  bool number_unsigned(number_unsigned_t v) override {
    return Number(static_cast<double>(v), v >= static_cast<uint64_t>(kEarliestTsMs) &&
                                              v < static_cast<uint64_t>(kLatestTsMs));
  }
  bool number_float(number_float_t v, const string_t&) override { return Number(v, false); }
  bool boolean(bool) override { return Scalar(); }
  bool null() override { return Scalar(); }
  bool binary(binary_t&) override { return Fail("body", "binary values are not JSON"); }
  bool parse_error(std::size_t position, const std::string&,
                   const nlohmann::detail::exception& e) override {
    errors_.push_back({items_, "body",
                       e.id == 406 ? "a number is out of range (beyond +-1.8e308)"
                                   : "malformed JSON at byte " + std::to_string(position)});
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
  bool InSample() const { return in_samples_ && level_ == 3; }
  bool Open() {
    if (++level_ > kMaxJsonDepth) {
      return Fail("body", "nested deeper than 32 levels");
    }
    return true;
  }
  // A scalar: the whole body, an item of samples or the samples key itself
  // are malformed; a field of a sample or an unknown key's value are fine.
  bool Scalar() {
    if (level_ == 0) return Fail("body", "must be {\"samples\": [...]}");
    if (level_ == 1 && key_ == "samples") return Fail("samples", "must be an array");
    if (in_samples_ && level_ == 2) return Fail("sample", "must be an object {sensor, ts, value}");
    return true;
  }
  bool Number(double v, bool valid_ts) {
    if (!Scalar()) return false;
    if (!InSample()) return true;
    if (key_ == "value") {
      current_.value = v;
      seen_ |= kValue;
    } else if (key_ == "ts" && valid_ts) {
      current_.ts_ms = static_cast<int64_t>(v);
      seen_ |= kTs;
    } else if (key_ == channel_key_) {
      errors_.push_back({items_, channel_key_, "must be a string"});
    }
    return true;
  }
  bool Fail(const char* field, const char* message) {
    errors_.push_back({items_, field, message});
    return false;
  }

  std::vector<TemperatureInput>& out_;
  FieldErrors& errors_;
  const char* channel_key_;  // "sensor", or "signal" for auxiliary signals
  TemperatureInput current_;
  std::string key_;
  int level_ = 0, seen_ = 0;
  size_t items_ = 0;  // samples read, for error indexes
  bool in_samples_ = false, saw_samples_ = false;
};

// Samples of named channels: temperatures ("sensor") or signals ("signal").
bool ParseChannelJson(const std::string& body, const char* key, std::vector<TemperatureInput>& out,
                      FieldErrors& errors) {
  TemperatureSax sax(out, errors, key);
  out.reserve(body.size() / 48);
  const bool parsed = json::sax_parse(body, &sax);
  return parsed && sax.Finish();
}

bool ParseChannelCsv(const std::string& body, const std::string& key,
                     std::vector<TemperatureInput>& out, FieldErrors& errors) {
  auto rows = SplitCsv(body);
  if (rows.empty() || rows[0].empty() || rows[0][0] != "ts" || rows[0].size() < 2) {
    errors.push_back(
        {0, "header", "CSV must start with a header ts," + key + ",value or ts,<" + key + ">,..."});
    return false;
  }
  const auto& header = rows[0];
  if (RepeatedColumn(header, errors)) return false;
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
    auto ts = ParseTimestamp(cells[0]);
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
  }
  return errors.empty();
}

bool ParseTemperaturesJson(const std::string& body, std::vector<TemperatureInput>& out,
                           FieldErrors& errors) {
  return ParseChannelJson(body, "sensor", out, errors);
}

bool ParseTemperaturesCsv(const std::string& body, std::vector<TemperatureInput>& out,
                          FieldErrors& errors) {
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

bool ParseSignalsJson(const std::string& body, std::vector<SignalInput>& out, FieldErrors& errors) {
  std::vector<TemperatureInput> samples;
  const bool ok = ParseChannelJson(body, "signal", samples, errors);
  out = AsSignals(samples);
  return ok;
}

bool ParseSignalsCsv(const std::string& body, std::vector<SignalInput>& out, FieldErrors& errors) {
  std::vector<TemperatureInput> samples;
  const bool ok = ParseChannelCsv(body, "signal", samples, errors);
  out = AsSignals(samples);
  return ok;
}

bool ParseEventJson(const std::string& body, EventInput& out, FieldErrors& errors) {
  auto j = ParseJsonBody(body, errors);
  if (!j) return false;
  JsonFields f(*j, errors);
  if (!f.IsObject()) return false;
  if (auto ts = f.Timestamp("ts")) out.ts_ms = *ts;
  if (auto kind = f.String("kind", JsonFields::kRequired, 64)) out.kind = *kind;
  if (auto note = f.String("note", JsonFields::kOptional, kMaxNoteLength)) out.note = *note;
  return errors.empty();
}

bool ParseProbePointsJson(const std::string& body, std::vector<ProbePointInput>& out,
                          FieldErrors& errors) {
  auto j = ParseJsonBody(body, errors);
  if (!j) return false;
  JsonFields body_fields(*j, errors);
  if (!body_fields.IsObject()) return false;
  const json* points = body_fields.Array("points");
  if (!points) return false;
  out.reserve(points->size());
  for (size_t i = 0; i < points->size(); ++i) {
    JsonFields f = body_fields.Item((*points)[i], i, "points");
    if (!f.IsObject()) continue;
    ProbePointInput in;
    in.run = f.String("run", JsonFields::kRequired, 64).value_or("");
    in.k = static_cast<int>(f.Integer("k", JsonFields::kRequired, 0, kMaxProbeK).value_or(0));
    in.ts_ms = f.Timestamp("ts").value_or(0);
    in.compensated = f.Bool("compensated", JsonFields::kOptional).value_or(false);
    for (const char* part : {"position", "deviation"}) {
      const json* axes = f.Object(part, JsonFields::kOptional);
      if (!axes) continue;
      JsonFields values = f.Field(*axes, part);
      for (const auto& [axis, v] : axes->items()) {
        auto mm = values.Number(axis.c_str());
        if (!mm) continue;
        auto& av = in.axes[axis];
        (std::string(part) == "position" ? av.position_mm : av.deviation_mm) = *mm;
      }
    }
    if (const json* t = f.Object("temperatures", JsonFields::kOptional)) {
      JsonFields values = f.Field(*t, "temperatures");
      for (const auto& [sensor, v] : t->items()) {
        if (auto c = values.Number(sensor.c_str())) in.temperatures[sensor] = *c;
      }
    }
    out.push_back(std::move(in));
  }
  return errors.empty();
}

bool ParseProbePointsCsv(const std::string& body, std::vector<ProbePointInput>& out,
                         FieldErrors& errors) {
  auto rows = SplitCsv(body);
  if (rows.empty() || rows[0].size() < 4 || rows[0][0] != "ts" || rows[0][1] != "run" ||
      rows[0][2] != "k") {
    errors.push_back(
        {0, "header",
         "CSV must start with ts,run,k, then pos_<axis>/dev_<axis> and sensor columns"});
    return false;
  }
  const auto& header = rows[0];
  if (RepeatedColumn(header, errors)) return false;
  for (size_t r = 1; r < rows.size(); ++r) {
    const auto& cells = rows[r];
    const size_t index = r - 1;
    if (cells.size() != header.size()) {
      errors.push_back({index, "row", "expected " + std::to_string(header.size()) + " fields"});
      continue;
    }
    ProbePointInput in;
    auto ts = ParseTimestamp(cells[0]);
    if (!ts)
      errors.push_back({index, "ts", kTsHelp});
    else
      in.ts_ms = *ts;
    in.run = std::string(cells[1]);
    int k = -1;
    auto [p, ec] = std::from_chars(cells[2].data(), cells[2].data() + cells[2].size(), k);
    if (ec != std::errc() || p != cells[2].data() + cells[2].size() || k < 0 || k > kMaxProbeK) {
      errors.push_back({index, "k", "not an integer within 0.." + std::to_string(kMaxProbeK)});
    }
    in.k = k;
    for (size_t c = 3; c < cells.size(); ++c) {
      std::string name(header[c]);
      if (name == kCompensatedColumn) {
        if (auto flag = ParseCompensated(cells[c]))
          in.compensated = *flag;
        else
          errors.push_back({index, name, kCompensatedHelp});
        continue;
      }
      if (cells[c].empty()) continue;
      auto v = ParseDouble(cells[c]);
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

bool ParseDisplacementsCsv(const std::string& body, int64_t run_gap_ms,
                           std::vector<ProbePointInput>& out, FieldErrors& errors) {
  auto rows = SplitCsv(body);
  const bool has_run = !rows.empty() && rows[0].size() > 1 && rows[0][1] == "run";
  const size_t first_axis = has_run ? 2 : 1;
  bool header_ok = !rows.empty() && rows[0].size() > first_axis && rows[0][0] == "ts";
  size_t compensated_column = 0;  // none
  for (size_t c = first_axis; header_ok && c < rows[0].size(); ++c) {
    if (rows[0][c] == kCompensatedColumn && compensated_column == 0) {
      compensated_column = c;
      continue;
    }
    header_ok = rows[0][c].size() > 4 && rows[0][c].substr(0, 4) == "dev_";
  }
  header_ok = header_ok && rows[0].size() > first_axis + (compensated_column ? 1 : 0);
  if (!header_ok) {
    errors.push_back({0, "header",
                      "CSV must start with ts,[run,] then dev_<axis> columns (and an optional "
                      "compensated column)"});
    return false;
  }
  const auto& header = rows[0];
  if (RepeatedColumn(header, errors)) return false;
  std::string run;
  int k = 0;
  int64_t last_ts = 0;
  for (size_t r = 1; r < rows.size(); ++r) {
    const auto& cells = rows[r];
    const size_t index = r - 1;
    if (cells.size() != header.size()) {
      errors.push_back({index, "row", "expected " + std::to_string(header.size()) + " fields"});
      continue;
    }
    auto ts = ParseTimestamp(cells[0]);
    if (!ts) {
      errors.push_back({index, "ts", kTsHelp});
      continue;
    }
    if (!out.empty() && *ts <= last_ts) {
      errors.push_back({index, "ts", "not after the previous sample (samples in time order)"});
      continue;
    }
    const std::string given = has_run ? std::string(cells[1]) : std::string();
    const bool new_run =
        out.empty() || (has_run && given != run) || (!has_run && *ts - last_ts > run_gap_ms);
    if (new_run) {
      if (has_run) {
        run = given;
      } else {  // "D20260301T060000Z": the start, in a run's alphabet
        run = "D";
        for (char ch : FormatRfc3339(*ts).substr(0, 19)) {
          if (ch != '-' && ch != ':') run += ch;
        }
        run += 'Z';
      }
      k = 0;
    }
    if (k > kMaxProbeK) {
      errors.push_back(
          {index, "ts", "more than " + std::to_string(kMaxProbeK) + " samples in run"});
      continue;
    }
    ProbePointInput in;
    in.ts_ms = *ts;
    in.run = run;
    in.k = k++;
    for (size_t c = first_axis; c < cells.size(); ++c) {
      if (c == compensated_column) {
        if (auto flag = ParseCompensated(cells[c]))
          in.compensated = *flag;
        else
          errors.push_back({index, kCompensatedColumn, kCompensatedHelp});
        continue;
      }
      if (cells[c].empty()) continue;
      auto v = ParseDouble(cells[c]);
      if (!v) {
        errors.push_back({index, std::string(header[c]), "not a number"});
        continue;
      }
      in.axes[std::string(header[c].substr(4))].deviation_mm = *v;
    }
    last_ts = *ts;
    out.push_back(std::move(in));
  }
  return errors.empty();
}

}  // namespace thermocomp::api
