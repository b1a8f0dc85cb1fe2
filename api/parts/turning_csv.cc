#include "api/parts/turning_csv.h"

#include <array>
#include <string_view>

#include <nlohmann/json.hpp>

#include "api/csv_cells.h"
#include "core/time_format.h"
#include "model/parts/diameter_decimal.h"
#include "reports/json_fields.h"
#include "reports/json_text.h"

namespace thermocomp::api {
namespace {

using nlohmann::json;

enum Column { kPart, kFeature, kDes, kW, kC, kPp, kCutAt, kColumns };
constexpr std::array<const char*, kColumns> kNames = {"part",   "feature", "d_des_mm", "d_w_mm",
                                                      "d_c_mm", "d_pp_mm", "cut_at"};
const char* kTsHelp =
    "must be RFC 3339 (e.g. 2026-03-01T06:00:00Z) or integer Unix milliseconds, from 2000 to 2099";

int64_t* Diameter(TurnedPartInput& in, int column) {
  switch (column) {
    case kDes:
      return &in.d_des_nm;
    case kW:
      return &in.d_w_nm;
    case kC:
      return &in.d_c_nm;
    case kPp:
      return &in.d_pp_nm;
    default:
      return nullptr;
  }
}

// The header's columns in the order of kNames, or false with the error.
bool Header(std::string_view line, std::array<int, kColumns>& at, size_t& width,
            FieldErrors& errors) {
  at.fill(-1);
  const std::vector<std::string_view> cells = CsvCells(line);
  width = cells.size();
  for (size_t i = 0; i < cells.size(); ++i) {
    int found = -1;
    for (int k = 0; k < kColumns; ++k) {
      if (cells[i] == kNames[k]) found = k;
    }
    const std::string name(cells[i]);
    if (found < 0) {
      errors.push_back({0, name.empty() ? "header" : name,
                        "unknown column: the columns are part, feature, d_des_mm, d_w_mm, "
                        "d_c_mm, d_pp_mm (diameters in mm), cut_at"});
    } else if (at[found] >= 0) {
      errors.push_back({0, name, "column named twice in the header"});
    } else {
      at[found] = static_cast<int>(i);
    }
  }
  for (int k = 0; k < kColumns; ++k) {
    if (at[k] < 0) errors.push_back({0, kNames[k], "required column missing from the header"});
  }
  return errors.empty();
}

}  // namespace

bool ParseTurnedPartsCsv(const std::string& body_text, std::vector<TurnedPartInput>& out,
                         FieldErrors& errors, Status* status) {
  std::string_view body = body_text;
  if (body.substr(0, 3) == "\xEF\xBB\xBF") body.remove_prefix(3);  // a spreadsheet's BOM
  size_t pos = 0;
  auto next_line = [&]() {
    size_t end = body.find('\n', pos);
    if (end == std::string_view::npos) end = body.size();
    std::string_view line = TrimCell(body.substr(pos, end - pos));
    pos = end + 1;
    return line;
  };
  std::string_view header;
  while (pos < body.size() && header.empty()) header = next_line();
  std::array<int, kColumns> at{};
  size_t width = 0;
  if (header.empty()) {
    errors.push_back({0, "header",
                      "CSV must start with a header part,feature,d_des_mm,d_w_mm,d_c_mm,d_pp_mm,"
                      "cut_at"});
    *status = Status::InvalidArgument("empty CSV");
    return false;
  }
  if (!Header(header, at, width, errors)) {
    *status = Status::InvalidArgument("CSV header");
    return false;
  }
  size_t row = 0;
  while (pos < body.size()) {
    const std::string_view line = next_line();
    ++row;
    if (line.empty()) continue;  // a blank line: counted, nothing in it
    if (out.size() >= TurningService::kMaxRows) {
      *status = Status::TooLarge("at most " + std::to_string(TurningService::kMaxRows) +
                                 " turned parts per request");
      errors.push_back(
          {row, "row", "beyond " + std::to_string(TurningService::kMaxRows) + " rows"});
      return false;
    }
    const std::vector<std::string_view> cells = CsvCells(line);
    if (cells.size() != width) {
      errors.push_back(
          {row, "row",
           "expected " + std::to_string(width) + " fields, got " + std::to_string(cells.size())});
      continue;
    }
    TurnedPartInput in;
    in.row = row;
    in.part = std::string(cells[static_cast<size_t>(at[kPart])]);
    in.feature = std::string(cells[static_cast<size_t>(at[kFeature])]);
    bool ok = true;
    for (int k : {kDes, kW, kC, kPp}) {
      std::string why;
      auto nm = ParseMillimetresNm(cells[static_cast<size_t>(at[k])], &why);
      if (!nm) {
        errors.push_back({row, kNames[k], why});
        ok = false;
      } else {
        *Diameter(in, k) = *nm;
      }
    }
    auto ts = ParseTimestamp(cells[static_cast<size_t>(at[kCutAt])]);
    if (!ts) {
      errors.push_back({row, "cut_at", kTsHelp});
      ok = false;
    } else {
      in.cut_ms = *ts;
    }
    if (ok) out.push_back(std::move(in));
  }
  if (errors.empty() && out.empty()) errors.push_back({0, "body", "no data rows after the header"});
  if (!errors.empty()) *status = Status::InvalidArgument("invalid CSV");
  return errors.empty();
}

bool ParseTurnedPartsJson(const std::string& body, std::vector<TurnedPartInput>& out,
                          FieldErrors& errors, Status* status) {
  auto j = ParseJsonBody(body, errors, status);
  if (!j) return false;
  JsonFields fields(*j, errors);
  const json* parts = fields.IsObject() ? fields.Array("parts") : nullptr;
  if (!parts) {
    *status = Status::InvalidArgument("body must be {\"parts\": [...]}");
    return false;
  }
  if (parts->size() > TurningService::kMaxRows) {
    *status = Status::TooLarge("at most " + std::to_string(TurningService::kMaxRows) +
                               " turned parts per request");
    errors.push_back(
        {0, "parts", "more than " + std::to_string(TurningService::kMaxRows) + " items"});
    return false;
  }
  out.reserve(parts->size());
  for (size_t i = 0; i < parts->size(); ++i) {
    const json& item = (*parts)[i];
    JsonFields f = fields.Item(item, i, "");
    if (!f.IsObject("part")) continue;
    const size_t before = errors.total();
    TurnedPartInput in;
    in.row = i;
    if (auto s = f.String("part", JsonFields::kRequired, 64)) in.part = *s;
    if (auto s = f.String("feature", JsonFields::kRequired, 64)) in.feature = *s;
    if (auto t = f.Timestamp("cut_at")) in.cut_ms = *t;
    for (int k : {kDes, kW, kC, kPp}) {
      const char* key = kNames[k];
      std::string why = "required: a number or a decimal string in mm";
      std::optional<int64_t> nm;
      if (item.contains(key)) {
        const json& v = item[key];
        if (v.is_number()) {
          nm = DoubleMillimetresNm(v.get<double>(), &why);
        } else if (v.is_string()) {
          nm = ParseMillimetresNm(v.get_ref<const std::string&>(), &why);
        } else {
          why = "must be a number or a decimal string in mm";
        }
      }
      if (nm) {
        *Diameter(in, k) = *nm;
      } else {
        f.Error(key, why);
      }
    }
    if (errors.total() == before) out.push_back(std::move(in));
  }
  if (errors.empty() && out.empty()) errors.push_back({0, "parts", "no turned parts"});
  if (!errors.empty()) *status = Status::InvalidArgument("invalid turned parts");
  return errors.empty();
}

}  // namespace thermocomp::api
