#include "reports/report_text.h"

#include <cmath>
#include <cstdio>

namespace thermocomp::report_text {
namespace {

bool Control(unsigned char c) {
  return c < 0x20 || c == 0x7f;
}

bool AsciiPunctuation(unsigned char c) {
  return (c >= 0x21 && c <= 0x2f) || (c >= 0x3a && c <= 0x40) || (c >= 0x5b && c <= 0x60) ||
         (c >= 0x7b && c <= 0x7e);
}

}  // namespace

std::string Fixed(double v, const char* format) {
  if (!std::isfinite(v)) return "-";
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string Um(double mm) {
  return Fixed(mm * 1000.0, "%.2f");
}

std::string P(double p) {
  return p == 0.0 ? "< 1e-300" : Fixed(p, "%.2g");
}

std::string Join(const std::vector<std::string>& list) {
  std::string out;
  for (const auto& s : list) out += (out.empty() ? "" : ", ") + Text(s);
  return out.empty() ? "none" : out;
}

std::string Text(std::string_view s) {
  std::string out;
  out.reserve(s.size() + s.size() / 4);
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (Control(c)) {
      out += ' ';
      continue;
    }
    if (AsciiPunctuation(c)) out += '\\';
    out += ch;
  }
  return out;
}

std::string Code(std::string_view s) {
  bool plain = !s.empty();
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (ch == '`' || ch == '|' || ch == '<' || ch == '>' || Control(c)) plain = false;
  }
  if (!plain) return Text(s);
  std::string out = "`";
  out += s;
  return out + "`";
}

}  // namespace thermocomp::report_text
