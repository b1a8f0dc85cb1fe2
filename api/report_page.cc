#include "api/report_page.h"

#include <cmark-gfm-core-extensions.h>
#include <cmark-gfm.h>

#include <memory>
#include <mutex>

#include "reports/analysis_report_text.h"
#include "reports/fit_report_text.h"

namespace thermocomp::api {
namespace {

constexpr const char* kStyle =
    "body{font:15px/1.45 system-ui,'DejaVu Sans',sans-serif;color:#1d2733;max-width:72em;"
    "margin:1em auto;padding:0 1em}table{border-collapse:collapse;margin:.4em 0 1em;"
    "font-variant-numeric:tabular-nums}th,td{border-bottom:1px solid #d5dbe1;padding:.3em .6em;"
    "text-align:left;vertical-align:top}th{background:#f6f8fa}code{font-size:92%}"
    "h1{font-size:1.4em}h2{font-size:1.15em;margin-top:1.4em}figure{margin:1em 0}"
    "figcaption{color:#5f6b78;font-size:90%}";

std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

// Without CMARK_OPT_UNSAFE raw HTML is left out ("raw HTML omitted") and
// links to javascript:, vbscript:, file: and data: (but images) are
// emptied; invalid UTF-8 becomes U+FFFD. User text is escaped before it
// gets here (service/report_text.h); this is the second wall.
constexpr int kCmarkOptions = CMARK_OPT_DEFAULT | CMARK_OPT_VALIDATE_UTF8;
static_assert((kCmarkOptions & CMARK_OPT_UNSAFE) == 0, "reports never pass raw HTML through");

std::string MarkdownToHtml(const std::string& markdown) {
  static std::once_flag registered;
  std::call_once(registered, [] { cmark_gfm_core_extensions_ensure_registered(); });
  std::unique_ptr<cmark_parser, decltype(&cmark_parser_free)> parser(
      cmark_parser_new(kCmarkOptions), cmark_parser_free);
  // Tables only: the autolink extension is never attached, so a bare
  // "www.example" or URL in a report stays text.
  if (cmark_syntax_extension* table = cmark_find_syntax_extension("table")) {
    cmark_parser_attach_syntax_extension(parser.get(), table);
  }
  cmark_parser_feed(parser.get(), markdown.data(), markdown.size());
  std::unique_ptr<cmark_node, decltype(&cmark_node_free)> doc(cmark_parser_finish(parser.get()),
                                                              cmark_node_free);
  char* html =
      cmark_render_html(doc.get(), kCmarkOptions, cmark_parser_get_syntax_extensions(parser.get()));
  std::string out = html ? html : "";
  cmark_get_default_mem_allocator()->free(html);
  return out;
}

}  // namespace

std::string ReportPage(const std::string& title, const std::string& markdown,
                       const std::string& figures) {
  std::string body = MarkdownToHtml(markdown);
  if (!figures.empty()) {
    const size_t section = body.find("<h2");
    body.insert(section == std::string::npos ? body.size() : section, figures);
  }
  return "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
         "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><title>" +
         Escape(title) + "</title><style>" + kStyle + "</style></head><body>\n" + body +
         "</body></html>\n";
}

std::string AnalysisHtml(const AnalysisReport& r, const PlantTime& time) {
  return ReportPage("Effect analysis " + std::to_string(r.id), AnalysisMarkdown(r, time),
                    "<figure>" + AnalysisErrorChartSvg(r) +
                        "<figcaption>RMSE of the declared model (grey) and with the effects "
                        "added (blue), µm.</figcaption></figure>");
}

std::string FitReportHtml(const FitReport& r, const PlantTime& time) {
  return ReportPage("Model " + r.machine + " " + r.axis, FitReportMarkdown(r, time));
}

}  // namespace thermocomp::api
