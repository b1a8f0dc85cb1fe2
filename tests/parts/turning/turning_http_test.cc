// Turned parts over real HTTP on a real SQLite file (docs/api.md "Turned
// parts"): the issue's hand check exactly in CSV and JSON, in the answer,
// the history and the report in every format; the history paged and
// filtered; compensation changes marked; hostile files refused naming row
// and field with nothing stored.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/time_format.h"

namespace thermocomp {
namespace {

using nlohmann::json;
using testing::kT0;

const std::string kParts = "/api/v1/machines/m1/turned-parts";
const std::string kHeader = "part,feature,d_des_mm,d_w_mm,d_c_mm,d_pp_mm,cut_at\n";
const std::string kHandCheck = "P1,D40,40.000,40.030,40.010,40.016,2026-03-10T08:00:00Z\n";

MachineRecord Machine() {
  MachineRecord m;
  m.name = "m1";
  m.sensors = {{0, "T1", "spindle", 0.3}};
  m.axes = {{0, "X", 0.0, {"T1"}, 0.03}};
  return m;
}

class TurningHttpTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = testing::TestClient(http_->port());
    FieldErrors errors;
    ASSERT_TRUE(app_->machines().Register(Machine(), "test", &errors).ok());
  }
  httplib::Result PostCsv(const std::string& body) {
    return client_->Post(kParts, body, "text/csv");
  }
  httplib::Result PostJson(const std::string& body) {
    return client_->Post(kParts, body, "application/json");
  }
  json Get(const std::string& path) {
    auto r = client_->Get(path);
    EXPECT_TRUE(r);
    if (!r) return json();
    EXPECT_EQ(r->status, 200) << path << ": " << r->body;
    return json::parse(r->body, nullptr, false);
  }
  // POST `body`, expect `status` with the first error at `row` naming
  // `field`, and nothing stored (no part, no audit row).
  void ExpectRefused(const std::string& body, bool csv, int status, size_t row,
                     const std::string& field, const std::string& message = "") {
    SCOPED_TRACE(body.substr(0, 200));
    const int64_t audits = Count("SELECT COUNT(*) FROM audit");
    auto r = csv ? PostCsv(body) : PostJson(body);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, status) << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
    const json p = json::parse(r->body, nullptr, false);
    ASSERT_TRUE(p.contains("errors")) << r->body;
    EXPECT_EQ(p["errors"][0]["index"], row) << r->body;
    EXPECT_EQ(p["errors"][0]["field"], field) << r->body;
    EXPECT_NE(p["detail"].get<std::string>().find(field), std::string::npos) << r->body;
    if (!message.empty()) {
      EXPECT_NE(p["errors"][0]["message"].get<std::string>().find(message), std::string::npos)
          << r->body;
    }
    EXPECT_EQ(Count("SELECT COUNT(*) FROM turned_parts"), stored_);
    EXPECT_EQ(Count("SELECT COUNT(*) FROM audit"), audits);
  }
  std::unique_ptr<httplib::Client> client_;
  int64_t stored_ = 0;
};

// The JSON of a part holds the hand check's numbers as the decimals.
void ExpectHandCheck(const json& part) {
  EXPECT_EQ(part["part"], "P1");
  EXPECT_EQ(part["feature"], "D40");
  EXPECT_EQ(part["cut_at"], "2026-03-10T08:00:00.000Z");
  EXPECT_EQ(part["d_des_mm"].dump(), "40.0");
  EXPECT_EQ(part["d_w_mm"].dump(), "40.03");
  EXPECT_EQ(part["d_c_mm"].dump(), "40.01");
  EXPECT_EQ(part["d_pp_mm"].dump(), "40.016");
  EXPECT_EQ(part["delta_f_mm"].dump(), "0.015");
  EXPECT_EQ(part["delta_th_mm"].dump(), "-0.01");
  EXPECT_EQ(part["delta_g_mm"].dump(), "0.003");
  EXPECT_EQ(part["delta_tot_mm"].dump(), "0.008");
  EXPECT_EQ(part["delta_f_mm"].get<double>() + part["delta_th_mm"].get<double>() +
                part["delta_g_mm"].get<double>(),
            0.015 - 0.010 + 0.003);
}

TEST_F(TurningHttpTest, HandCheckIsExactInEveryFormat) {
  auto r = PostCsv(kHeader + kHandCheck);
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 201) << r->body;
  EXPECT_NE(r->body.find("\"delta_f_mm\":0.015"), std::string::npos) << r->body;
  json posted = json::parse(r->body);
  EXPECT_EQ(posted["accepted"], 1);
  ExpectHandCheck(posted["parts"][0]);
  EXPECT_EQ(Count("SELECT d_w_nm FROM turned_parts"), 40030000);

  ExpectHandCheck(Get(kParts)["parts"][0]);
  const json report = Get(kParts + "/report");
  ASSERT_EQ(report["features"].size(), 1u);
  ExpectHandCheck(report["features"][0]["latest"]);
  EXPECT_EQ(report["features"][0]["summary"]["count"], 1);
  EXPECT_DOUBLE_EQ(report["features"][0]["summary"]["mean_delta_tot_um"].get<double>(), 8.0);

  const std::string row =
      "| 40.000 | 40.030 | 40.010 | 40.016 | +0.015 | -0.010 | +0.003 | +0.008 |";
  auto md = client_->Get(kParts + "/report?format=markdown");
  ASSERT_TRUE(md);
  EXPECT_EQ(md->status, 200);
  EXPECT_EQ(md->get_header_value("Content-Type"), "text/markdown");
  EXPECT_NE(md->body.find(row), std::string::npos) << md->body;
  auto html = client_->Get(kParts + "/report?format=html");
  ASSERT_TRUE(html);
  EXPECT_EQ(html->status, 200);
  EXPECT_EQ(html->get_header_value("Content-Type"), "text/html");
  for (const char* cell :
       {"<td>40.000</td>", "<td>40.030</td>", "<td>40.010</td>", "<td>40.016</td>",
        "<td>+0.015</td>", "<td>-0.010</td>", "<td>+0.003</td>", "<td>+0.008</td>"}) {
    EXPECT_NE(html->body.find(cell), std::string::npos) << cell;
  }
  auto bad = client_->Get(kParts + "/report?format=xml");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
}

TEST_F(TurningHttpTest, HandCheckThroughJsonNumbersAndStrings) {
  const json numbers = {{"parts",
                         {{{"part", "P1"},
                           {"feature", "D40"},
                           {"d_des_mm", 40.000},
                           {"d_w_mm", 40.030},
                           {"d_c_mm", 40.010},
                           {"d_pp_mm", 40.016},
                           {"cut_at", "2026-03-10T08:00:00Z"}}}}};
  auto r = PostJson(numbers.dump());
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 201) << r->body;
  ExpectHandCheck(json::parse(r->body)["parts"][0]);
  // The same part with the diameters as decimal strings and the time in
  // Unix ms: identical, so a duplicate, stored once.
  const std::string strings =
      R"({"parts":[{"part":"P1","feature":"D40","d_des_mm":"40.000","d_w_mm":"40.030",)"
      R"("d_c_mm":"40.010","d_pp_mm":"40.016","cut_at":1773129600000}]})";
  r = PostJson(strings);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(json::parse(r->body)["duplicates"], 1);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM turned_parts"), 1);
  // Changed values under the same part and feature: a conflict, nothing stored.
  stored_ = 1;
  ExpectRefused(kHeader + "P2,D40,40,40.01,40.01,40.01,2026-03-10T09:00:00Z\n" +
                    "P1,D40,40.000,40.030,40.010,40.017,2026-03-10T08:00:00Z\n",
                true, 409, 2, "feature", "already stored");
}

TEST_F(TurningHttpTest, HistoryIsOldestFirstFilteredAndPaged) {
  std::string csv = kHeader;
  for (int i = 0; i < 10; ++i) {
    // Written newest first: the history sorts by cut time.
    const int64_t ts = kT0 + (10 - i) * 3600000LL;
    csv +=
        "P" + std::to_string(i) + ",D40,40.000,40.020,40.010,40.012," + std::to_string(ts) + "\n";
    csv += "P" + std::to_string(i) + ",D25,25.000,25.010,25.004,25.006," + FormatRfc3339(ts) + "\n";
  }
  auto r = PostCsv(csv);
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 201) << r->body;
  const json all = Get(kParts);
  EXPECT_EQ(all["total"], 20);
  EXPECT_EQ(all["parts"].size(), 20u);
  EXPECT_TRUE(all["next_offset"].is_null());
  for (size_t i = 1; i < all["parts"].size(); ++i) {
    EXPECT_LE(all["parts"][i - 1]["cut_at"].get<std::string>(),
              all["parts"][i]["cut_at"].get<std::string>());
  }
  const json first = Get(kParts + "?feature=D25&limit=4");
  EXPECT_EQ(first["total"], 10);
  ASSERT_EQ(first["parts"].size(), 4u);
  EXPECT_EQ(first["next_offset"], 4);
  EXPECT_EQ(first["parts"][0]["part"], "P9");  // the oldest
  const json window = Get(kParts + "?feature=D40&from=" + FormatRfc3339(kT0 + 3 * 3600000LL) +
                          "&to=" + std::to_string(kT0 + 5 * 3600000LL));
  EXPECT_EQ(window["total"], 3);
  for (const char* bad : {"?limit=0", "?limit=10001", "?from=yesterday",
                          "?from=2026-03-05T00:00:00Z&to=2026-03-01T00:00:00Z",
                          "?feature=", "?feature=%FF%FE", "?feature=D%2025"}) {
    auto b = client_->Get(kParts + bad);
    ASSERT_TRUE(b);
    EXPECT_EQ(b->status, 400) << bad << ": " << b->body;
  }
  // A feature name that is not valid UTF-8 is named, not answered empty.
  auto not_utf8 = client_->Get(kParts + "?feature=%FF%FE");
  ASSERT_TRUE(not_utf8);
  EXPECT_NE(not_utf8->body.find("\"feature\""), std::string::npos) << not_utf8->body;
  auto unknown = client_->Get("/api/v1/machines/nope/turned-parts");
  ASSERT_TRUE(unknown);
  EXPECT_EQ(unknown->status, 404);
}

// The next page from `next_offset` (the offset parameter must be in the
// request hook's table of parameters, api/http_server.cc RouteParams).
TEST_F(TurningHttpTest, HistoryPagesOnFromNextOffset) {
  std::string csv = kHeader;
  for (int i = 0; i < 10; ++i) {
    csv += "P" + std::to_string(i) + ",D25,25.000,25.010,25.004,25.006," +
           std::to_string(kT0 + (10 - i) * 3600000LL) + "\n";
  }
  auto r = PostCsv(csv);
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 201) << r->body;
  const json page = Get(kParts + "?feature=D25&limit=4&offset=4");
  EXPECT_EQ(page["total"], 10);
  ASSERT_EQ(page["parts"].size(), 4u);
  EXPECT_EQ(page["next_offset"], 8);
  EXPECT_EQ(page["parts"][0]["part"], "P5");  // the fifth oldest
  for (const json& p : page["parts"]) {
    EXPECT_EQ(p["feature"], "D25");
    EXPECT_EQ(p["delta_th_mm"].dump(), "-0.003");
  }
  auto bad = client_->Get(kParts + "?offset=-1");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
}

TEST_F(TurningHttpTest, ReportMarksCompensationChangesBeforeAndAfter) {
  const int64_t day = 86400000;
  const int64_t change = kT0 + 7 * day;
  {
    // What a fit that made its model active, and a later activation, archive.
    const std::unique_ptr<Session> session = app_->storage().Open();
    ASSERT_TRUE(session->log().Audit(change, "test", "fit", "m1", 100, "X v1 active").ok());
    ASSERT_TRUE(session->log().Audit(change - day, "test", "fit", "m1", 100, "X v0 rejected").ok());
  }
  std::string csv = kHeader;
  for (int i = 0; i < 14; ++i) {
    // 10 µm thermal before the change, 2 µm after; 5 µm force throughout.
    const bool after = kT0 + i * day >= change;
    csv += "P" + std::to_string(i) + ",D40,40.000,40.010," + (after ? "40.006" : "39.990") + "," +
           (after ? "40.006" : "39.990") + "," + std::to_string(kT0 + i * day) + "\n";
  }
  auto r = PostCsv(csv);
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 201) << r->body;
  json report = Get(kParts + "/report");
  ASSERT_EQ(report["compensation_changes"].size(), 1u) << report.dump();
  EXPECT_EQ(report["latest_change"]["axis"], "X");
  EXPECT_EQ(report["latest_change"]["version"], 1);
  EXPECT_EQ(report["latest_change"]["ts"], FormatRfc3339(change));
  const json& f = report["features"][0];
  EXPECT_EQ(f["before_change"]["count"], 7);
  EXPECT_EQ(f["after_change"]["count"], 7);
  EXPECT_DOUBLE_EQ(f["before_change"]["mean_delta_th_um"].get<double>(), -10.0);
  EXPECT_DOUBLE_EQ(f["after_change"]["mean_delta_th_um"].get<double>(), -2.0);
  EXPECT_DOUBLE_EQ(f["before_change"]["thermal_share"].get<double>(), 10.0 / 15.0);
  EXPECT_DOUBLE_EQ(f["after_change"]["thermal_share"].get<double>(), 2.0 / 7.0);
  EXPECT_LT(f["share_trend"]["slope_per_30_days"].get<double>(), 0.0);
  EXPECT_EQ(f["weeks"].size(), 2u);  // kT0 is a Monday: two weeks of 7 days
  // A manual activation later is the latest change; the history lists
  // the changes within its period.
  const int64_t axis_id = app_->machines().Find("m1")->axes[0].id;
  {
    const std::unique_ptr<Session> session = app_->storage().Open();
    ASSERT_TRUE(
        session->models().Insert(axis_id, {0, "candidate", "test", change, "{}", "{}"}).ok());
  }
  clock_.Set(kT0 + 15 * day);
  ASSERT_TRUE(app_->fits().Activate("m1", "X", 1, "test").ok());
  report = Get(kParts + "/report");
  EXPECT_EQ(report["compensation_changes"].size(), 2u);
  EXPECT_EQ(report["latest_change"]["action"], "activate");
  // No part after it yet: before/after stays at the change of day 7.
  EXPECT_EQ(report["features"][0]["change"]["ts"], FormatRfc3339(change));
  EXPECT_EQ(report["features"][0]["after_change"]["count"], 7);
  const json h = Get(kParts + "?to=" + FormatRfc3339(kT0 + 10 * day));
  ASSERT_EQ(h["compensation_changes"].size(), 1u);
  EXPECT_EQ(h["compensation_changes"][0]["kind"], "drift");
  auto md = client_->Get(kParts + "/report?format=markdown");
  ASSERT_TRUE(md);
  EXPECT_NE(md->body.find("axis X drift model v1 activated"), std::string::npos) << md->body;
}

TEST_F(TurningHttpTest, HostileFilesAreRefusedNamingRowAndFieldAndStoreNothing) {
  const std::string ok = "P1,D40,40.000,40.030,40.010,40.016,2026-03-10T08:00:00Z\n";
  auto with = [&](const std::string& row) { return kHeader + ok + row; };
  // Columns.
  ExpectRefused("part,feature,d_des_mm,d_w_mm,d_c_mm,cut_at\n" + std::string("P1,D40,40,40,40,1\n"),
                true, 400, 0, "d_pp_mm", "required column");
  ExpectRefused("part,feature,d_des_mm,d_w_mm,d_c_mm,d_pp_mm,d_pp_mm,cut_at\n", true, 400, 0,
                "d_pp_mm", "named twice");
  ExpectRefused("part,feature,d_des_in,d_w_mm,d_c_mm,d_pp_mm,cut_at\n" + ok, true, 400, 0,
                "d_des_in", "in mm");
  ExpectRefused("", true, 400, 0, "header");
  ExpectRefused(kHeader, true, 400, 0, "body", "no data rows");
  ExpectRefused(kHeader + std::string(1000000, '\n'), true, 400, 0, "body", "no data rows");
  ExpectRefused(kHeader + std::string(1000000, '\n') + "P1,D40,40,40,40,nan,1773129600000\n", true,
                400, 1000001, "d_pp_mm");
  // Values.
  ExpectRefused(with("P2,D40,40.000,nan,40.010,40.016,2026-03-10T08:00:00Z\n"), true, 400, 2,
                "d_w_mm");
  ExpectRefused(with("P2,D40,40.000,inf,40.010,40.016,2026-03-10T08:00:00Z\n"), true, 400, 2,
                "d_w_mm");
  ExpectRefused(with("P2,D40,40.000,1e999,40.010,40.016,2026-03-10T08:00:00Z\n"), true, 400, 2,
                "d_w_mm");
  ExpectRefused(with("P2,D40,40.000,40.030,40.0100001,40.016,2026-03-10T08:00:00Z\n"), true, 400, 2,
                "d_c_mm", "more than 6 decimals");
  ExpectRefused(with("P2,D40,-40.000,40.030,40.010,40.016,2026-03-10T08:00:00Z\n"), true, 400, 2,
                "d_des_mm", "above 0");
  ExpectRefused(with("P2,D40,0,40.030,40.010,40.016,2026-03-10T08:00:00Z\n"), true, 400, 2,
                "d_des_mm", "above 0");
  ExpectRefused(with("P2,D40,40.000,40.030,40.010,41.5,2026-03-10T08:00:00Z\n"), true, 400, 2,
                "d_pp_mm", "more than 1 mm");
  ExpectRefused(with("P2,D40,40.000,40.030,40.010,40.016,yesterday\n"), true, 400, 2, "cut_at");
  ExpectRefused(with("P2,D40,40.000,40.030,40.010,40.016,2099-01-01T00:00:00Z\n"), true, 400, 2,
                "cut_at", "future");
  ExpectRefused(with("P2,D40,40.000,40.030\n"), true, 400, 2, "row", "expected 7 fields");
  ExpectRefused(with("P\xff,D40,40.000,40.030,40.010,40.016,2026-03-10T08:00:00Z\n"), true, 400, 2,
                "part");
  ExpectRefused(with("P3,D 40,40.000,40.030,40.010,40.016,2026-03-10T08:00:00Z\n"), true, 400, 2,
                "feature");
  ExpectRefused(with(ok), true, 400, 2, "feature", "also in row 1");
  // Too many rows: 413.
  std::string many = kHeader;
  for (int i = 0; i <= 100000; ++i)
    many += "P" + std::to_string(i) + ",D,40,40,40,40,1773129600000\n";
  ExpectRefused(many, true, 413, 100001, "row");
  // JSON.
  ExpectRefused("[1]", false, 400, 0, "body");
  ExpectRefused(R"({"parts": 3})", false, 400, 0, "parts");
  ExpectRefused(R"({"parts": [{"part": "P1", "feature": "D40", "d_des_mm": 40, "d_w_mm": 40.03,
                "d_c_mm": 40.01, "d_pp_mm": 1e999, "cut_at": 1773129600000}]})",
                false, 400, 0, "body");
  ExpectRefused(R"({"parts": [{"part": "P1", "feature": "D40", "d_des_mm": 40, "d_w_mm": 40.03,
                "d_c_mm": 40.01, "d_pp_mm": 40.016, "cut_at": 1773129600000},
                {"part": "P2", "feature": "D40", "d_des_mm": 40, "d_w_mm": "NaN",
                "d_c_mm": 40.01, "d_pp_mm": 40.016, "cut_at": 1773129600000}]})",
                false, 400, 1, "d_w_mm");
  ExpectRefused(R"({"parts": [{"part": "P1", "feature": "D40", "d_des_mm": 40, "d_w_mm": 40.0300001,
                "d_c_mm": 40.01, "d_pp_mm": 40.016, "cut_at": 1773129600000}]})",
                false, 400, 0, "d_w_mm", "more than 6 decimals");
  ExpectRefused(R"({"parts": [{"part": "P1", "feature": "D40", "d_des_mm": 40, "d_w_mm": true,
                "d_c_mm": 40.01, "d_pp_mm": 40.016, "cut_at": 1773129600000}]})",
                false, 400, 0, "d_w_mm");
  ExpectRefused(R"({"parts": [{"part": "P1", "feature": "D40", "d_des_mm": 40, "d_w_mm": 40.03,
                "d_c_mm": 40.01, "cut_at": 1773129600000}]})",
                false, 400, 0, "d_pp_mm", "required");
  // Media type and machine.
  auto r = client_->Post(kParts, kHeader + ok, "text/plain");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 415);
  r = client_->Post("/api/v1/machines/nope/turned-parts", kHeader + ok, "text/csv");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 404);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM turned_parts"), 0);
}

}  // namespace
}  // namespace thermocomp
