// The pages (docs/pages.md): one shell per page, filled by its script from
// the JSON API with the browser's own credentials, plus the scripts, the
// stylesheet and Debian's dygraphs. The shells carry no data, so they are
// served without credentials; the API decides what each user sees.
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
// be a zone name when the configuration was read, so it needs no escaping).
std::string Shell(const std::string& page, const std::string& title, const std::string& zone) {
  const WebAsset* shell = FindWebAsset("page.html");
  std::string html = shell ? shell->body : "";
  html = Replace(html, "{{script}}", page + ".js");
  html = Replace(html, "{{title}}", title);
  return Replace(html, "{{time_zone}}", zone);
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
      {m, "machine", "Machine"},
      {m + "/checks", "machine_checks", "Machine checks"},
      {a + "/models", "models", "Model versions"},
      {a + "/models/([0-9]{1,9})", "model", "Model report"},
      {a + "/analysis", "analyses", "Effect analyses"},
      {a + "/analysis/([0-9]{1,18})", "analysis", "Effect analysis"},
  };
  for (const auto& [pattern, page, title] : pages) {
    const std::string html = Shell(page, title, app_.config().web_time_zone);
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
