// Report pages: Markdown tables become HTML tables, our figures sit after
// the introduction, and markup inside report text is never passed through.
// Every renderer writes user-supplied strings (ids, names, reasons) as
// text: no link, image, HTML or extra table cell comes out of them, in the
// Markdown or in the HTML made from it.
#include "api/report_page.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "api/check_reports.h"
#include "reports/analysis_report_text.h"
#include "reports/fit_report_text.h"
#include "reports/report_text.h"

namespace thermocomp::api {
namespace {

using nlohmann::json;

TEST(ReportPageTest, TablesAreTablesAndFiguresFollowTheIntroduction) {
  const std::string page = ReportPage(
      "Check 1", "# Check 1\n\nIntro.\n\n## Results\n\n| a | b |\n|---|---|\n| 1 | 2 |\n",
      "<figure><svg></svg></figure>");
  EXPECT_NE(page.find("<title>Check 1</title>"), std::string::npos);
  EXPECT_NE(page.find("<table>"), std::string::npos);
  EXPECT_NE(page.find("<td>2</td>"), std::string::npos);
  const size_t figure = page.find("<figure>");
  ASSERT_NE(figure, std::string::npos);
  EXPECT_LT(page.find("Intro."), figure);
  EXPECT_LT(figure, page.find("<h2>Results</h2>"));
}

TEST(ReportPageTest, MarkupInTheTextIsNeverPassedThrough) {
  const std::string page =
      ReportPage("<script>t</script>",
                 "# R\n\nreason: <script>alert(1)</script> <img src=x onerror=alert(2)>\n\n"
                 "| note |\n|---|\n| <b onclick=x>bold</b> |\n\n<iframe src=//evil></iframe>\n");
  EXPECT_EQ(page.find("<script"), std::string::npos) << page;
  EXPECT_EQ(page.find("<img"), std::string::npos) << page;
  EXPECT_EQ(page.find("<iframe"), std::string::npos) << page;
  EXPECT_EQ(page.find("onclick="), std::string::npos) << page;
  EXPECT_NE(page.find("&lt;script&gt;t&lt;/script&gt;"), std::string::npos);
}

TEST(ReportPageTest, BareAddressesAreNotLinked) {
  // No autolink extension: a name that looks like an address stays text.
  const std::string page = ReportPage("t", "# R\n\nsee www.evil.example and http://evil.example\n");
  EXPECT_EQ(page.find("<a "), std::string::npos) << page;
}

// Strings an attacker can give as an id, a name, a note or a reason.
const std::vector<std::string> kHostile = {
    "[x](http://evil.example)",
    "![i](http://evil.example/a.png)",
    "[x](http://evil.example) ![i](http://evil.example/a.png) | a | <b>",
    "<b>bold</b>",
    "<http://evil.example>",
    "www.evil.example",
    "a | b | c",
    "`code` | `x",
    "*em* _em_ **strong** ~~s~~",
    "# heading",
    "line\n| x | y |\n|---|---|\n",
    "tab\there\r\nnext",
    "[ref]: http://evil.example",
    "&lt;b&gt; &amp;",
    "\\| escaped pipe",
    "1. list",
    "- item",
};

// Rows of the first table after `heading` in an HTML page: cells per row.
std::vector<int> CellsPerRow(const std::string& html, const std::string& heading) {
  std::vector<int> cells;
  size_t at = html.find(heading);
  if (at == std::string::npos) return cells;
  const size_t end = html.find("</table>", at);
  for (size_t row = html.find("<tr>", at); row < end; row = html.find("<tr>", row + 1)) {
    const size_t row_end = html.find("</tr>", row);
    int n = 0;
    for (size_t c = html.find("<t", row + 1); c < row_end; c = html.find("<t", c + 1)) {
      if (html.compare(c, 3, "<td") == 0 || html.compare(c, 3, "<th") == 0) ++n;
    }
    cells.push_back(n);
  }
  return cells;
}

// Unescaped pipes of every Markdown table row after `heading`, up to the
// table's end (a blank line).
std::vector<int> PipesPerRow(const std::string& md, const std::string& heading) {
  std::vector<int> pipes;
  size_t at = md.find(heading);
  if (at == std::string::npos) return pipes;
  at = md.find("\n|", at);
  while (at != std::string::npos && at + 1 < md.size() && md[at + 1] == '|') {
    const size_t end = md.find('\n', at + 1);
    int n = 0;
    for (size_t i = at + 1; i < end; ++i) {
      if (md[i] == '|' && md[i - 1] != '\\') ++n;
    }
    pipes.push_back(n);
    at = end;
  }
  return pipes;
}

// Whether `needle` occurs in `md` other than right after a backslash.
bool HasUnescaped(const std::string& md, const std::string& needle) {
  for (size_t at = md.find(needle); at != std::string::npos; at = md.find(needle, at + 1)) {
    if (at == 0 || md[at - 1] != '\\') return true;
  }
  return false;
}

void ExpectOnlyText(const std::string& md, const std::string& html, const std::string& what) {
  for (const char* made : {"<a ", "<img", "<b>", "<em>", "<del>", "<ol", "heading</h"}) {
    EXPECT_EQ(html.find(made), std::string::npos) << what << ": " << made << "\n" << html;
  }
  for (const char* raw : {"<b>", "<img", "<a ", "<http", "\n# heading"}) {
    EXPECT_FALSE(HasUnescaped(md, raw)) << what << ": " << raw << "\n" << md;
  }
}

TEST(ReportTextTest, EveryHostileStringIsLiteralTextInATableCell) {
  for (const std::string& s : kHostile) {
    const std::string md = "# R\n\nid " + report_text::Text(s) + ", name " + report_text::Code(s) +
                           ".\n\n## T\n\n| id | name | n |\n|---|---|---|\n| " +
                           report_text::Text(s) + " | " + report_text::Code(s) + " | 1 |\n";
    const std::string html = ReportPage("t", md);
    ExpectOnlyText(md, html, s);
    for (int n : CellsPerRow(html, "<h2>T</h2>")) EXPECT_EQ(n, 3) << s << "\n" << html;
    for (int n : PipesPerRow(md, "## T")) EXPECT_EQ(n, 4) << s << "\n" << md;
  }
}

TEST(ReportTextTest, TextReadsBackAsTheSameCharacters) {
  // cmark-gfm turns the escapes back into the characters: the page shows
  // what was sent (HTML-escaped), not a mangled form.
  const std::string html =
      ReportPage("t", "# R\n\n" + report_text::Text("a_b*c [d](e) 1.5") + "\n");
  EXPECT_NE(html.find("a_b*c [d](e) 1.5"), std::string::npos) << html;
}

TEST(ReportTextTest, FitReportKeepsNamesAndReasonsAsText) {
  for (const std::string& s : kHostile) {
    FitReport r;
    r.machine = "m1";
    r.axis = "Y";
    r.status = "rejected";
    r.reason = s;
    r.trigger = s;
    r.declared_inputs = {s};
    r.fit.terms.resize(2);
    r.fit.terms[0].name = "intercept";
    r.fit.terms[1].name = s;
    r.removed_terms.resize(1);
    r.removed_terms[0].name = s;
    r.removed_terms[0].reason = s;
    r.residuals.largest = {{s, 1, 0, 2.5}};
    r.validation_runs = {s};
    r.acceptance_reasons = {s};
    const std::string md = FitReportMarkdown(r);
    ExpectOnlyText(md, FitReportHtml(r), "fit: " + s);
    for (int n : PipesPerRow(md, "## Coefficients")) EXPECT_EQ(n, 7) << s << "\n" << md;
    for (int n : CellsPerRow(FitReportHtml(r), "Coefficients")) EXPECT_EQ(n, 6) << s;
    for (int n : CellsPerRow(FitReportHtml(r), "Largest")) EXPECT_EQ(n, 4) << s;
  }
}

TEST(ReportTextTest, AnalysisReportKeepsNamesAndReasonsAsText) {
  for (const std::string& s : kHostile) {
    AnalysisReport r;
    r.context = {"m1", "Y", s, 0, {s}, {s}};
    r.superseded = {s};
    r.closest.resize(1);
    r.closest[0].name = s;
    r.set_aside = {{s, s, {}}};
    r.ambiguous = {{s, {}}};
    r.model = AnalysisModelOutcome{2, s, s};
    const std::string md = AnalysisMarkdown(r);
    ExpectOnlyText(md, AnalysisHtml(r), "analysis: " + s);
  }
}

json ColumnCheckReport(const std::string& artifact, const std::string& scheme,
                       const std::vector<std::string>& points) {
  json details = json::object();
  for (const auto& p : points) details[p] = 1.5;
  return {{"id", 7},
          {"machine", "m1"},
          {"ts", "2026-03-16T06:00:00Z"},
          {"artifact", artifact},
          {"artifact_temperature_c", 21.3},
          {"machine_zero_mm", {{"X", 0.003}, {"Y", 0.004}, {"Z", -0.002}}},
          {"circle", {{"radius_mm", 250.0}, {"residual_um", 0.5}}},
          {"straightness_um", {{scheme, 2.0}, {"plain", 1.0}}},
          {"straightness_points_um", {{scheme, details}, {"plain", {{"P1", 0.0}}}}}};
}

TEST(ReportTextTest, ColumnCheckKeepsArtifactSchemeAndPointIdsAsText) {
  for (const std::string& s : kHostile) {
    const json r = ColumnCheckReport(s, s, {s, "P2"});
    const std::string md = ColumnCheckMarkdown(r);
    const std::string html = ColumnCheckHtml(r);
    ExpectOnlyText(md, html, "column check: " + s);
    const std::vector<int> rows = CellsPerRow(html, "Straightness");
    EXPECT_EQ(rows.size(), 3u) << s << "\n" << html;  // header and two schemes
    for (int n : rows) EXPECT_EQ(n, 3) << s << "\n" << html;
    for (int n : PipesPerRow(md, "## Straightness")) EXPECT_EQ(n, 4) << s << "\n" << md;
  }
}

}  // namespace
}  // namespace thermocomp::api
