// What the pages and reports make of hostile strings, over real HTTP:
// the sign-in page never sends the browser off this origin, whatever
// ?next= says, and a column check whose artifact, scheme and point ids are
// Markdown, HTML and addresses is reported with those ids as text.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <httplib.h>
#include <nlohmann/json.hpp>

namespace thermocomp {
namespace {

using nlohmann::json;

class PageSafetyTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = testing::TestClient(http_->port());
  }
  // The return path the sign-in page is given for ?next=<encoded>, read
  // back from its meta tag (HTML entities undone).
  std::string ReturnPath(const std::string& encoded_next) {
    auto r = client_->Get("/ui/sign-in?next=" + encoded_next);
    EXPECT_TRUE(r);
    if (!r) return "(no answer)";
    EXPECT_EQ(r->status, 200);
    const std::string tag = "<meta name=\"thermocomp-next\" content=\"";
    const size_t at = r->body.find(tag);
    EXPECT_NE(at, std::string::npos) << r->body;
    if (at == std::string::npos) return "(no meta)";
    const size_t from = at + tag.size();
    std::string value = r->body.substr(from, r->body.find('"', from) - from);
    for (const auto& [entity, c] :
         {std::pair{"&lt;", "<"}, std::pair{"&gt;", ">"}, std::pair{"&quot;", "\""},
          std::pair{"&#39;", "'"}, std::pair{"&amp;", "&"}}) {
      for (size_t i = value.find(entity); i != std::string::npos; i = value.find(entity, i + 1))
        value.replace(i, std::string(entity).size(), c);
    }
    return value;
  }
  std::unique_ptr<httplib::Client> client_;
};

// Whether a browser on http://127.0.0.1 that sets location.href to `path`
// stays on that origin: a path starting with one "/" that no browser reads
// as "//" (no backslash, no tab, CR or LF it would drop).
bool StaysOnOrigin(const std::string& path) {
  if (path.empty() || path[0] != '/') return false;
  std::string read;
  for (char c : path) {
    if (c == '\t' || c == '\r' || c == '\n') continue;
    read += c == '\\' ? '/' : c;
  }
  return read.size() < 2 || read[1] != '/';
}

TEST_F(PageSafetyTest, SignInNeverReturnsOffTheOrigin) {
  // As they appear in the address: percent-encoded once by whoever built
  // the link, so the server's query decoding gives the hostile value, and
  // some encoded twice so a second decoding would.
  const std::vector<std::string> hostile = {
      "//evil.example/",
      "%2F%2Fevil.example%2F",
      "/%5Cevil.example/",
      "/%255Cevil.example/",
      "%2F%5Cevil.example%2F",
      "/%09/evil.example/",
      "/%2509/evil.example/",
      "/%0D%0A/evil.example/",
      "/%0A/evil.example/",
      "/%00/evil.example/",
      "/%2F/evil.example/",
      "/%252F/evil.example/",
      "/%25252F/evil.example/",
      "https://evil.example/",
      "https:%2F%2Fevil.example",
      "HTTPS://evil.example",
      "//evil.example@127.0.0.1/",
      "javascript:alert(1)",
      "javascript%3Aalert(1)",
      "%20/evil.example",
      "%09//evil.example",
      "/%5C/evil.example",
      "\\evil.example",
      "%5C%5Cevil.example",
      "/a%5Cb",
      "evil.example",
      "",
      "%",
      std::string(3000, '/'),
  };
  for (const std::string& next : hostile) {
    const std::string path = ReturnPath(next);
    EXPECT_TRUE(StaysOnOrigin(path)) << next << " -> " << path;
    EXPECT_EQ(path, "/") << next;  // falls back to the overview
  }
}

TEST_F(PageSafetyTest, SignInReturnPathCannotLeaveItsAttribute) {
  auto r = client_->Get("/ui/sign-in?next=/x%22%3E%3Cscript%3Ealert(1)%3C/script%3E%27");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->body.find("<script>alert"), std::string::npos) << r->body;
  EXPECT_NE(r->body.find("content=\"/x&quot;&gt;&lt;script&gt;"), std::string::npos) << r->body;
}

TEST_F(PageSafetyTest, SignInKeepsHonestReturnPaths) {
  EXPECT_EQ(ReturnPath("%2Fui%2Fmachines%2Fm1%3Fx%3D1"), "/ui/machines/m1?x=1");
  EXPECT_EQ(ReturnPath("%2Fui%2Fmachines%2Fm1%2Faxes%2FY%2Fmodels%2F3"),
            "/ui/machines/m1/axes/Y/models/3");
  EXPECT_EQ(ReturnPath("%2F"), "/");
  EXPECT_EQ(ReturnPath("%2F%3Frefresh%3D5%26a%3D%2520b"), "/?refresh=5&a=%20b");
  // Other pages carry no return path of their own.
  auto r = client_->Get("/ui/checks?next=%2F%2Fevil.example");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->body.find("evil"), std::string::npos);
}

TEST_F(PageSafetyTest, SignInScriptReadsTheVettedPathOnly) {
  auto r = client_->Get("/static/sign_in.js");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  EXPECT_EQ(r->body.find("param(\"next\")"), std::string::npos);
  EXPECT_EQ(r->body.find("location.search"), std::string::npos);
  EXPECT_NE(r->body.find("thermocomp-next"), std::string::npos);
  EXPECT_NE(r->body.find("url.origin === location.origin"), std::string::npos);
}

// Cells of each row of the first table after `heading`.
std::vector<int> CellsPerRow(const std::string& html, const std::string& heading) {
  std::vector<int> cells;
  const size_t at = html.find(heading);
  if (at == std::string::npos) return cells;
  const size_t end = html.find("</table>", at);
  for (size_t row = html.find("<tr>", at); row < end; row = html.find("<tr>", row + 1)) {
    const size_t row_end = html.find("</tr>", row);
    int n = 0;
    for (size_t c = html.find("<td", row); c < row_end; c = html.find("<td", c + 1)) ++n;
    for (size_t c = html.find("<th", row); c < row_end; c = html.find("<th", c + 1)) ++n;
    cells.push_back(n);
  }
  return cells;
}

TEST_F(PageSafetyTest, ColumnCheckReportKeepsHostileIdsAsText) {
  FieldErrors errors;
  ASSERT_TRUE(app_->machines().Register(VirtualMachine::Definition("m1"), "test", &errors).ok());
  // Ids are free text of up to 64 characters; the artifact's name in the
  // path is a plain name, which may still look like an address.
  const std::string link = "[x](http://evil.example) | a | <b>";
  const std::string image = "![i](http://evil.example/a.png)";
  const std::string scheme = "[s](http://evil.example) | <b>s</b>";
  json artifact = {
      {"points",
       {{{"id", "KD"}, {"nominal", {{"x", 0.0}, {"y", 500.0}, {"z", 0.0}}}},
        {{"id", link}, {"nominal", {{"x", 100.0}, {"y", 400.0}, {"z", 0.0}}}},
        {{"id", image}, {"nominal", {{"x", 100.0}, {"y", 600.0}, {"z", 0.0}}}},
        {{"id", "www.evil.example"}, {"nominal", {{"x", 100.0}, {"y", 700.0}, {"z", 0.0}}}}}},
      {"schemes",
       {{{"id", scheme}, {"travel_axis", "Y"}, {"deviation_axis", "X"}, {"reference_point", link}},
        {{"id", "www.evil.example"},
         {"travel_axis", "Y"},
         {"deviation_axis", "X"},
         {"reference_point", image}}}}};
  auto r = client_->Put("/api/v1/artifacts/www.evil.example", artifact.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 201) << r->body;
  const double y = 500.0;
  json check = {
      {"ts", "2026-03-10T06:00:00Z"},
      {"artifact", "www.evil.example"},
      {"artifact_temperature_c", 20.0},
      {"spheres",
       {{{"sphere", "KD"}, {"b_deg", 0}, {"x", 250.0}, {"y", y}, {"z", 0.0}},
        {{"sphere", "KD"}, {"b_deg", 90}, {"x", 0.0}, {"y", y}, {"z", 250.0}},
        {{"sphere", "KD"}, {"b_deg", 180}, {"x", -250.0}, {"y", y}, {"z", 0.0}}}},
      {"points",
       {{{"id", link}, {"scheme", scheme}, {"x", 100.002}, {"y", 400.0}, {"z", 0.0}},
        {{"id", image}, {"scheme", scheme}, {"x", 100.007}, {"y", 600.0}, {"z", 0.0}},
        {{"id", "www.evil.example"}, {"scheme", scheme}, {"x", 100.001}, {"y", 700.0}, {"z", 0.0}},
        {{"id", image}, {"scheme", "www.evil.example"}, {"x", 100.0}, {"y", 600.0}, {"z", 0.0}},
        {{"id", "www.evil.example"},
         {"scheme", "www.evil.example"},
         {"x", 100.003},
         {"y", 700.0},
         {"z", 0.0}}}}};
  r = client_->Post("/api/v1/machines/m1/column-checks", check.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 201) << r->body;
  const std::string one = "/api/v1/machines/m1/column-checks/" + json::parse(r->body)["id"].dump();

  auto md = client_->Get(one + "?format=markdown");
  auto html = client_->Get(one + "?format=html");
  ASSERT_TRUE(md && html);
  ASSERT_EQ(md->status, 200) << md->body;
  ASSERT_EQ(html->status, 200) << html->body;
  for (const char* made : {"<a ", "<img", "<b>", "href=", "src="}) {
    EXPECT_EQ(html->body.find(made), std::string::npos) << made << "\n" << html->body;
  }
  for (const char* raw : {"<b>", "<img", "<a ", "](http", "<http"}) {
    EXPECT_EQ(md->body.find(raw), std::string::npos) << raw << "\n" << md->body;
  }
  // The straightness table: a header and one row per scheme, three cells
  // each, whatever the ids hold.
  const std::vector<int> rows = CellsPerRow(html->body, "Straightness");
  ASSERT_EQ(rows.size(), 3u) << html->body;
  for (int n : rows) EXPECT_EQ(n, 3) << html->body;
  // The ids are shown as they were given (HTML-escaped).
  EXPECT_NE(html->body.find("[x](http://evil.example) | a | &lt;b&gt;"), std::string::npos)
      << html->body;
  EXPECT_NE(html->body.find("www.evil.example"), std::string::npos);
}

}  // namespace
}  // namespace thermocomp
