// The pages (docs/pages.md): one shell per page, filled by its script from
// the JSON API with the browser's own credentials, plus the scripts, the
// stylesheet and Debian's dygraphs. The shells carry no data, so they are
// served without credentials; the API decides what each user sees. The
// sign-in shell carries where to go once signed in: ?next= when it is a
// path on this origin (SignInReturnPath), else "/".
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <fstream>
#include <sstream>

#include "api/http_util.h"
#include "api/problem.h"
#include "api/web/web_assets.h"

namespace thermocomp::api {
namespace {

// No script but our own files, nothing framed, nothing sent elsewhere.
void PageHeaders(Res& res) {
  res.set_header("Content-Security-Policy",
                 "default-src 'self'; script-src 'self'; style-src 'self' 'unsafe-inline'; "
                 "img-src 'self' data: blob:; object-src 'none'; base-uri 'none'; "
                 "frame-ancestors 'none'; form-action 'self'");
  res.set_header("X-Content-Type-Options", "nosniff");
  res.set_header("X-Frame-Options", "DENY");
  res.set_header("Referrer-Policy", "no-referrer");
  res.set_header("Cache-Control", "no-cache");
}

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
  return text;
}

// The shell with the page's script and the plant's time zone (checked to
// be a zone name when the configuration was read, so it needs no
// escaping); "{{next}}" is left for the request to fill.
std::string Shell(const std::string& page, const std::string& title, const std::string& zone) {
  const WebAsset* shell = FindWebAsset("page.html");
  std::string html = shell ? shell->body : "";
  html = Replace(html, "{{script}}", page + ".js");
  html = Replace(html, "{{title}}", title);
  return Replace(html, "{{time_zone}}", zone);
}

std::string AttributeEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&#39;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

int HexDigit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// One round of percent-decoding; a '%' without two hex digits stays.
std::string PercentDecoded(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    const int hi = s[i] == '%' && i + 2 < s.size() ? HexDigit(s[i + 1]) : -1;
    const int lo = hi >= 0 ? HexDigit(s[i + 2]) : -1;
    if (lo >= 0) {
      out += static_cast<char>(hi * 16 + lo);
      i += 2;
    } else {
      out += s[i];
    }
  }
  return out;
}

// A path on this origin, read as a browser would: "/" then anything but a
// second "/" or a backslash (which browsers read as "/", making "//host"),
// and no backslash or control character anywhere (browsers drop tab, CR
// and LF inside a URL, so "/<tab>/host" is "//host"). A scheme
// ("https:", "javascript:") cannot precede the leading "/".
bool IsLocalPath(const std::string& s) {
  if (s.empty() || s[0] != '/') return false;
  if (s.size() > 1 && (s[1] == '/' || s[1] == '\\')) return false;
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (c < 0x20 || c == 0x7f || ch == '\\') return false;
  }
  return true;
}

// Where the sign-in page sends the browser: `next` when it is a path on
// this origin, else "/".
std::string SignInReturnPath(const std::string& next) {
  constexpr size_t kMaxLength = 2048;
  constexpr int kMaxDecodings = 4;
  if (next.size() > kMaxLength) return "/";
  // The value as given (the query is decoded once already) and every
  // further decoding of it must be a local path: "/%2F/host" and
  // "/%5Chost" are refused as "//host" is.
  std::string form = next;
  for (int round = 0; round <= kMaxDecodings; ++round) {
    if (!IsLocalPath(form)) return "/";
    std::string decoded = PercentDecoded(form);
    if (decoded == form) return next;
    form = std::move(decoded);
  }
  return "/";  // still changing: encoded deeper than any link of ours
}

}  // namespace

void HttpServer::PageRoutes() {
  auto& s = server_;
  const std::string m = "/ui/machines/([A-Za-z0-9_.-]{1,64})";
  const std::string a = m + "/axes/([A-Z])";
  const std::vector<std::array<std::string, 3>> pages = {
      {"/", "overview", "Line overview"},
      {"/ui/sign-in", "sign_in", "Sign in"},
      {"/ui/checks", "checks", "Checks"},
      {"/ui/compare", "compare", "Compare machines"},
      {"/ui/audit", "audit", "Audit trail"},
      {m, "machine", "Machine"},
      {m + "/checks", "machine_checks", "Machine checks"},
      {a + "/models", "models", "Model versions"},
      {a + "/models/([0-9]{1,9})", "model", "Model report"},
      {a + "/analysis", "analyses", "Effect analyses"},
      {a + "/analysis/([0-9]{1,18})", "analysis", "Effect analysis"},
      {m + "/plates", "plates", "Test plates"},
      {m + "/plates/([A-Za-z0-9_.-]{1,64})", "plates", "Test plate"},
      {m + "/turned-parts", "turned_parts", "Turned parts"},
      {m + "/part-models", "part_models", "Part-error models"},
      {m + "/surfaces", "surfaces", "Surfaces"},
      {m + "/surfaces/([A-Za-z0-9_.-]{1,64})", "surfaces", "Surface corrections"},
  };
  for (const auto& [pattern, page, title] : pages) {
    const std::string shell = Shell(page, title, app_.config().web_time_zone);
    if (page == "sign_in") {
      // Where to go once signed in, vetted here: the script reads it from
      // the page, never from the address.
      s.Get(pattern, [shell](const Req& req, Res& res) {
        const std::string next = SignInReturnPath(req.get_param_value("next"));
        PageHeaders(res);
        res.set_content(Replace(shell, "{{next}}", AttributeEscape(next)),
                        "text/html; charset=utf-8");
      });
      continue;
    }
    const std::string html = Replace(shell, "{{next}}", "/");
    s.Get(pattern, [html](const Req&, Res& res) {
      PageHeaders(res);
      res.set_content(html, "text/html; charset=utf-8");
    });
  }
  s.Get("/static/([a-z_]{1,32}\\.(js|css))", [](const Req& req, Res& res) {
    const WebAsset* asset = FindWebAsset(req.matches[1].str());
    if (!asset) return WriteProblem(res, 404, "no such file: " + req.path);
    PageHeaders(res);
    res.set_content(asset->body, asset->type);
  });
  // Debian's libjs-dygraphs, read from its folder (web.dygraphs_dir).
  s.Get("/static/dygraphs/(dygraph\\.min\\.(js|css))", [this](const Req& req, Res& res) {
    const std::string path = app_.config().web_dygraphs_dir + "/" + req.matches[1].str();
    std::ifstream in(path, std::ios::binary);
    if (!in) {
      return WriteProblem(res, 404,
                          "charting library missing: " + path +
                              " (install libjs-dygraphs or set web.dygraphs_dir)");
    }
    std::ostringstream body;
    body << in.rdbuf();
    PageHeaders(res);
    res.set_header("Cache-Control", "max-age=86400");
    res.set_content(body.str(), req.matches[2] == "js" ? "text/javascript; charset=utf-8"
                                                       : "text/css; charset=utf-8");
  });
}

}  // namespace thermocomp::api
