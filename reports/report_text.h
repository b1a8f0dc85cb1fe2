// Number, list and text formats the readable reports share (Markdown and
// the pages made from it), so every report prints a length, a p-value, a
// missing value and a user's string the same way.
//
// Every string that comes from data (machine, artifact, point, scheme,
// sensor, term and run names, reasons, notes, times read back from a
// stored report) goes into Markdown through Text or Code: it stays the
// literal text in the Markdown and in the HTML rendered from it, never a
// link, an image, emphasis, a heading, HTML or a table cell of its own.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace thermocomp::report_text {

// printf `format` of a finite value; "-" for NaN (not computed) or inf.
std::string Fixed(double v, const char* format);
// Millimetres as micrometres with two decimals.
std::string Um(double mm);
// A p-value; 0 means it underflowed double, not that it is zero.
std::string P(double p);
// Text(a), Text(b), ... joined by ", ", or "none".
std::string Join(const std::vector<std::string>& list);

// `s` as Markdown inline text: every ASCII punctuation character
// backslash-escaped (CommonMark reads any of them escaped as itself, so
// [ ] ( ) ! < > * _ ` | # + - . and the rest lose their meaning, and the
// dot in "www.x.example" keeps GFM's autolink away), and line breaks and
// other control characters written as spaces, so a name stays on its line
// (a table row, a list item).
std::string Text(std::string_view s);
// A name as a code span (`lag(Tco, 30 min)`), which shows it verbatim; a
// name a code span cannot hold safely (a backtick, a pipe inside a table,
// a control character, empty) or that would put an HTML tag into the
// Markdown (< or >) is written as Text instead.
std::string Code(std::string_view s);

}  // namespace thermocomp::report_text
