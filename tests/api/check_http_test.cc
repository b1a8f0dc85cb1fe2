// Column and positioning checks over real HTTP on a real SQLite file:
// request -> acknowledged -> result -> request closed, overdue with an injected clock,
// weekly requests, machine-zero change as an event, ISO 230-2 results,
// reports and pitch tables, and malformed checks refused with nothing stored.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <cmath>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/time_format.h"
#include "reports/check_report_codec.h"
#include "reports/machine_status_codec.h"

namespace thermocomp {
namespace {

using nlohmann::json;

class CheckHttpTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = testing::TestClient(http_->port());
    FieldErrors errors;
    ASSERT_TRUE(app_->machines().Register(VirtualMachine::Definition("m1"), "test", &errors).ok());
  }
  httplib::Result Post(const std::string& path, const json& body) {
    return client_->Post(path, body.dump(), "application/json");
  }
  json Get(const std::string& path, int expect = 200) {
    auto r = client_->Get(path);
    EXPECT_TRUE(r);
    if (!r) return {};
    EXPECT_EQ(r->status, expect) << path << " " << r->body;
    return json::parse(r->body, nullptr, false);
  }
  void PutArtifact() {
    json art = {{"points",
                 {{{"id", "KD"},
                   {"nominal", {{"x", 0.0}, {"y", 500.0}, {"z", 0.0}}},
                   {"expansion", {{"y", {{"beta_mm_per_c", 0.0069}, {"b_mm", -0.1371}}}}}},
                  {{"id", "P1"}, {"nominal", {{"x", 100.0}, {"y", 400.0}, {"z", 0.0}}}},
                  {{"id", "P2"}, {"nominal", {{"x", 100.0}, {"y", 600.0}, {"z", 0.0}}}}}},
                {"schemes",
                 {{{"id", "a"},
                   {"travel_axis", "Y"},
                   {"deviation_axis", "X"},
                   {"reference_point", "P1"}}}}};
    auto r = client_->Put("/api/v1/artifacts/col-1", art.dump(), "application/json");
    ASSERT_EQ(r->status, 201) << r->body;
    // Read back as it was put.
    auto back = client_->Get("/api/v1/artifacts/col-1");
    ASSERT_EQ(back->status, 200) << back->body;
    EXPECT_EQ(json::parse(back->body), art);
  }
  // A column check whose spheres sit on a circle about (dx, dz) with the
  // artifact at 21.3 degC (KD's Y expansion 0.00987 mm) and Y shifted by dy.
  json ColumnCheck(const std::string& ts, double dx, double dy, double dz) {
    const double y = 500.0 + 0.00987 + dy;
    return {{"ts", ts},
            {"artifact", "col-1"},
            {"artifact_temperature_c", 21.3},
            {"spheres",
             {{{"sphere", "KD"}, {"b_deg", 0}, {"x", 250.0 + dx}, {"y", y}, {"z", dz}},
              {{"sphere", "KD"}, {"b_deg", 90}, {"x", dx}, {"y", y}, {"z", 250.0 + dz}},
              {{"sphere", "KD"}, {"b_deg", 180}, {"x", -250.0 + dx}, {"y", y}, {"z", dz}}}},
            {"points",
             {{{"id", "P1"}, {"scheme", "a"}, {"x", 100.002}, {"y", 400.0}, {"z", 0.0}},
              {{"id", "P2"}, {"scheme", "a"}, {"x", 100.007}, {"y", 600.0}, {"z", 0.0}}}},
            {"parallelism",
             {{"ball", {{"x", 0.0}, {"y", 500.0}, {"z", 0.0}}},
              {"shank", {{"x", 0.002}, {"y", 500.0}, {"z", 0.0}}},
              {"height_mm", 100.0}}}};
  }
  json Positioning() {
    return {{"axis", "Y"},
            {"ts", "2026-03-10T08:00:00Z"},
            {"targets_mm", {0, 1000}},
            {"runs",
             {{{"direction", "+"}, {"deviations_um", {1.0, -1.0}}},
              {{"direction", "-"}, {"deviations_um", {0.0, 2.0}}},
              {{"direction", "+"}, {"deviations_um", {3.0, -1.0}}},
              {{"direction", "-"}, {"deviations_um", {2.0, 4.0}}}}},
            {"compensation_active", false},
            {"uncertainty",
             {{"device_um_per_m", 0.5},
              {"misalignment_mm", 2},
              {"alpha_um_per_m_c", 11.7},
              {"temperature_range_c", 0.35},
              {"delta_t_c", 3},
              {"alpha_range_um_per_m_c", 1},
              {"e_ve_um", 2}}}};
  }
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(CheckHttpTest, RequestThenResultClosesTheRequest) {
  PutArtifact();
  auto r = Post("/api/v1/machines/m1/column-checks/requests",
                {{"reason", "after collision"}, {"due", "2026-03-17T00:00:00Z"}});
  ASSERT_EQ(r->status, 201) << r->body;
  const int64_t id = json::parse(r->body)["id"];
  json pending = Get("/api/v1/machines/m1/column-checks/requests?state=pending");
  ASSERT_EQ(pending["requests"].size(), 1u);
  EXPECT_EQ(pending["requests"][0]["reason"], "after collision");
  EXPECT_EQ(Get("/api/v1/machines/m1")["checks"]["pending"], 1);

  r = Post("/api/v1/machines/m1/column-checks",
           ColumnCheck("2026-03-16T06:00:00Z", 0.003, 0.004, -0.002));
  ASSERT_EQ(r->status, 201) << r->body;
  json result = json::parse(r->body);
  EXPECT_EQ(result["request_id"], id);
  EXPECT_NEAR(result["machine_zero_mm"]["X"].get<double>(), 0.003, 1e-9);
  EXPECT_NEAR(result["machine_zero_mm"]["Y"].get<double>(), 0.004, 1e-9);
  EXPECT_NEAR(result["machine_zero_mm"]["Z"].get<double>(), -0.002, 1e-9);
  // Two points lie on their least-squares line (ISO 230-1): the 5 um
  // between them over 200 mm is the line's slope, not straightness.
  EXPECT_NEAR(result["straightness_um"]["a"].get<double>(), 0.0, 1e-6);
  EXPECT_NEAR(result["straightness_line_slope_um_per_m"]["a"].get<double>(), 25.0, 1e-6);
  EXPECT_NEAR(result["spindle_z_parallelism_um_per_100mm"]["X"].get<double>(), 2.0, 1e-6);
  json done = Get("/api/v1/machines/m1/column-checks/requests?state=done");
  ASSERT_EQ(done["requests"].size(), 1u);
  EXPECT_EQ(done["requests"][0]["check_id"], result["id"]);
  EXPECT_EQ(Get("/api/v1/machines/m1")["checks"]["pending"], 0);
  EXPECT_EQ(Get("/api/v1/machines/m1")["last_column_check"]["id"], result["id"]);
  const std::string one = "/api/v1/machines/m1/column-checks/" + result["id"].dump();
  EXPECT_EQ(Get(one)["machine_zero_mm"], result["machine_zero_mm"]);
  auto md = client_->Get(one + "?format=markdown");
  EXPECT_NE(md->body.find("| offset µm | 3.00 | 4.00 | -2.00 |"), std::string::npos) << md->body;
  // The same check again is not stored twice.
  r = Post("/api/v1/machines/m1/column-checks",
           ColumnCheck("2026-03-16T06:00:00Z", 0.003, 0.004, -0.002));
  EXPECT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM column_checks"), 1);
}

TEST_F(CheckHttpTest, UnansweredRequestBecomesOverdueOnTheClock) {
  const int64_t now = clock_.NowMs();
  auto r = Post("/api/v1/machines/m1/column-checks/requests",
                {{"reason", "weekly"}, {"due", now + 3600000}});
  ASSERT_EQ(r->status, 201);
  EXPECT_TRUE(Get("/api/v1/machines/m1/column-checks/requests?state=overdue")["requests"].empty());
  clock_.Advance(2 * 3600000);
  EXPECT_EQ(Get("/api/v1/machines/m1/column-checks/requests?state=overdue")["requests"].size(), 1u);
  EXPECT_EQ(Get("/api/v1/machines/m1")["checks"]["overdue"], 1);
  auto metrics = client_->Get("/metrics");
  EXPECT_NE(metrics->body.find("thermocomp_column_checks_overdue{machine=\"m1\"} 1"),
            std::string::npos);
  Get("/api/v1/machines/m1/column-checks/requests?state=late", 400);
}

TEST_F(CheckHttpTest, MachinesThatOptInGetAWeeklyRequest) {
  // m2 did not opt in (no reference artifact on its line): never requested.
  auto r =
      client_->Put("/api/v1/machines/m2", R"({"sensors": [{"id": "T1"}]})", "application/json");
  ASSERT_EQ(r->status, 201) << r->body;
  EXPECT_FALSE(Get("/api/v1/machines/m2")["automatic_column_checks"].get<bool>());
  EXPECT_TRUE(Get("/api/v1/machines/m1")["automatic_column_checks"].get<bool>());
  EXPECT_EQ(app_->checks().EnsurePeriodicRequests(), 1);
  EXPECT_EQ(app_->checks().EnsurePeriodicRequests(), 0);
  clock_.Advance(6 * 86400000LL);
  EXPECT_EQ(app_->checks().EnsurePeriodicRequests(), 0);
  clock_.Advance(86400000LL + 1);
  EXPECT_EQ(app_->checks().EnsurePeriodicRequests(), 1);
  json all = Get("/api/v1/machines/m1/column-checks/requests");
  ASSERT_EQ(all["requests"].size(), 2u);
  EXPECT_TRUE(all["requests"][0]["automatic"].get<bool>());
  EXPECT_TRUE(Get("/api/v1/machines/m2/column-checks/requests")["requests"].empty());
  // Opting out by an update stops them; the other fields stay as they were.
  r = client_->Put("/api/v1/machines/m1", R"({"automatic_column_checks": false})",
                   "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(json::parse(r->body)["controller"], "sinumerik");
  clock_.Advance(8 * 86400000LL);
  EXPECT_EQ(app_->checks().EnsurePeriodicRequests(), 0);
}

TEST_F(CheckHttpTest, MachineZeroMovingBeyondToleranceIsAnEventAndInTheHistory) {
  clock_.Set(testing::kT0 + 30 * 86400000LL);  // 2026-04-01: the checks below are past
  PutArtifact();
  ASSERT_EQ(Post("/api/v1/machines/m1/column-checks", ColumnCheck("2026-03-09T06:00:00Z", 0, 0, 0))
                ->status,
            201);
  ASSERT_EQ(
      Post("/api/v1/machines/m1/column-checks", ColumnCheck("2026-03-16T06:00:00Z", 0, 0.004, 0))
          ->status,
      201);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM events WHERE kind = 'column_check'"), 0);  // 4 um < 10 um
  auto r =
      Post("/api/v1/machines/m1/column-checks", ColumnCheck("2026-03-23T06:00:00Z", 0, 0.030, 0));
  ASSERT_EQ(r->status, 201);
  json third = json::parse(r->body);
  EXPECT_TRUE(third["beyond_tolerance"].get<bool>());
  EXPECT_NEAR(third["zero_change_um"]["Y"].get<double>(), 26.0, 1e-6);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM events WHERE kind = 'column_check'"), 1);
  json history = Get("/api/v1/machines/m1/column-checks");
  ASSERT_EQ(history["checks"].size(), 3u);
  EXPECT_NEAR(history["machine_zero_trend"]["range_um"]["Y"].get<double>(), 30.0, 1e-6);
  EXPECT_NEAR(history["machine_zero_trend"]["Y_um_per_week"].get<double>(), 15.0, 1e-6);
  // It comes back to 10 um: the range is largest minus smallest (30 um),
  // not last minus first (10 um).
  ASSERT_EQ(
      Post("/api/v1/machines/m1/column-checks", ColumnCheck("2026-03-30T06:00:00Z", 0, 0.010, 0))
          ->status,
      201);
  history = Get("/api/v1/machines/m1/column-checks");
  EXPECT_NEAR(history["machine_zero_trend"]["range_um"]["Y"].get<double>(), 30.0, 1e-6);
  json drift =
      Get("/api/v1/machines/m1/drift?axis=Y&from=2026-03-01T00:00:00Z&to=2026-04-01T00:00:00Z");
  EXPECT_EQ(drift["machine_zero"].size(), 4u);
}

TEST_F(CheckHttpTest, CheckReportsDecodeToWhatWasServed) {
  clock_.Set(testing::kT0 + 30 * 86400000LL);
  PutArtifact();
  ASSERT_EQ(Post("/api/v1/machines/m1/column-checks", ColumnCheck("2026-03-09T06:00:00Z", 0, 0, 0))
                ->status,
            201);
  auto r =
      Post("/api/v1/machines/m1/column-checks", ColumnCheck("2026-03-16T06:00:00Z", 0, 0.012, 0));
  ASSERT_EQ(r->status, 201);
  const json posted = json::parse(r->body);
  const json got = Get("/api/v1/machines/m1/column-checks/" + posted["id"].dump());
  auto column = ColumnCheckReportFromJson(got);
  ASSERT_TRUE(column.ok()) << column.status().ToString();
  EXPECT_EQ(ColumnCheckReportToJson(*column), got);
  EXPECT_TRUE(column->beyond_tolerance);
  ASSERT_TRUE(column->zero_change);
  EXPECT_NEAR(column->zero_change->change_um.y, 12.0, 1e-9);
  json served_without_machine = got;
  served_without_machine.erase("machine");
  EXPECT_EQ(served_without_machine, posted);  // what POST answered is what is stored

  auto p = Post("/api/v1/machines/m1/positioning-checks", Positioning());
  ASSERT_EQ(p->status, 201);
  const json positioning = json::parse(p->body);
  auto decoded = PositioningCheckReportFromJson(positioning);
  ASSERT_TRUE(decoded.ok()) << decoded.status().ToString();
  EXPECT_EQ(PositioningCheckReportToJson(*decoded), positioning);
  EXPECT_FALSE(PositioningCheckReportFromJson(json{{"id", 1}}).ok());

  // The machine's status names the newest check and reads back the same.
  const json machine = Get("/api/v1/machines/m1");
  auto status = MachineStatusFromJson(machine);
  ASSERT_TRUE(status.ok()) << status.status().ToString();
  ASSERT_TRUE(status->last_column_check);
  EXPECT_EQ(status->last_column_check->id, posted["id"].get<int64_t>());
  EXPECT_TRUE(status->last_column_check->beyond_tolerance);
  const json reencoded = MachineStatusToJson(*status);
  for (const auto& [key, value] : reencoded.items()) {
    EXPECT_EQ(value, machine[key]) << key;
  }
}

TEST_F(CheckHttpTest, PositioningCheckIsEvaluatedReportedAndTurnedIntoPitchTables) {
  auto r = Post("/api/v1/machines/m1/positioning-checks", Positioning());
  ASSERT_EQ(r->status, 201) << r->body;
  json e = json::parse(r->body);
  const double s2 = std::sqrt(2.0);
  EXPECT_NEAR(e["iso230_2"]["A_um"].get<double>(), 2 + 4 * s2, 1e-9);
  EXPECT_NEAR(e["iso230_2"]["R_um"].get<double>(), 2 * s2 + 4, 1e-9);
  EXPECT_EQ(e["iso230_2"]["B_um"], 4.0);
  EXPECT_NEAR(e["vdi3441"]["P_um"].get<double>(), 1 + 6 * s2, 1e-9);
  EXPECT_NEAR(e["uncertainty_um"]["R_up_down"].get<double>(), 2.4, 1e-9);
  const std::string base = "/api/v1/machines/m1/positioning-checks/" + e["id"].dump();
  EXPECT_EQ(Get(base), e);
  auto html = client_->Get(base + "?format=html");
  EXPECT_NE(html->body.find("<polyline"), std::string::npos);
  EXPECT_NE(html->body.find("<table>"), std::string::npos);  // a page, not text in <pre>
  auto md = client_->Get(base + "?format=markdown");
  EXPECT_NE(md->body.find("VDI/DGQ 3441"), std::string::npos);

  auto lcnc = client_->Get(base + "/pitch-table?format=linuxcnc&per_direction=true");
  ASSERT_EQ(lcnc->status, 200);
  // Target 0: actual forward = 0 + 2 um, backward = 0 + 1 um.
  EXPECT_NE(lcnc->body.find("0.000000 0.002000 0.001000"), std::string::npos) << lcnc->body;
  auto sin = client_->Get(base + "/pitch-table?format=sinumerik");
  EXPECT_NE(sin->body.find("$AA_ENC_COMP[0,0,Y1]=-0.001500"), std::string::npos) << sin->body;
  EXPECT_NE(sin->body.find("$MA_BACKLASH[0,Y1]=-0.001500"), std::string::npos);
  auto beck = client_->Get(base + "/pitch-table?format=beckhoff&per_direction=true");
  EXPECT_NE(beck->body.find("kw.ssfk.table[1].pos 10"), std::string::npos) << beck->body;
  // Refused naming the parameter, once, and never silently ignored.
  auto fanuc = client_->Get(base + "/pitch-table?format=fanuc");
  ASSERT_EQ(fanuc->status, 400);
  json fp = json::parse(fanuc->body);
  EXPECT_EQ(fp["errors"][0]["field"], "format") << fp;
  EXPECT_EQ(fp["detail"], "invalid pitch table query") << fp;
  auto sin_dir = client_->Get(base + "/pitch-table?format=sinumerik&per_direction=true");
  ASSERT_EQ(sin_dir->status, 400);
  EXPECT_EQ(json::parse(sin_dir->body)["errors"][0]["field"], "per_direction") << sin_dir->body;
  EXPECT_EQ(client_->Get(base + "/pitch-table?format=csv&per_direction=yes")->status, 400);

  // The laser software's CSV gives the same evaluation.
  std::string csv = "target_mm,run,direction,deviation_um\n";
  const char* rows[] = {"0,1,+,1", "1000,1,+,-1", "1000,2,-,2", "0,2,-,0",
                        "0,3,+,3", "1000,3,+,-1", "1000,4,-,4", "0,4,-,2"};
  for (const char* row : rows) csv += std::string(row) + "\n";
  auto c = client_->Post("/api/v1/machines/m1/positioning-checks?axis=Y&ts=2026-03-11T08:00:00Z",
                         csv, "text/csv");
  ASSERT_EQ(c->status, 201) << c->body;
  json ce = json::parse(c->body);
  EXPECT_EQ(ce["iso230_2"]["A_um"], e["iso230_2"]["A_um"]);
  EXPECT_EQ(ce["vdi3441"], e["vdi3441"]);
  // Without a budget the uncertainty is not stated (not a perfect 0.00).
  EXPECT_FALSE(ce["uncertainty_um"]["stated"].get<bool>());
  auto cmd = client_->Get("/api/v1/machines/m1/positioning-checks/" + ce["id"].dump() +
                          "?format=markdown");
  EXPECT_NE(cmd->body.find("| A (accuracy) | "), std::string::npos);
  EXPECT_NE(cmd->body.find("not stated"), std::string::npos) << cmd->body;
  // The CSV carries its budget and temperatures as query parameters, and
  // gives the JSON check's uncertainties.
  const std::string query =
      "?axis=Y&ts=2026-03-12T08:00:00Z&device_um_per_m=0.5&misalignment_mm=2&alpha_um_per_m_c=11.7"
      "&temperature_range_c=0.35&delta_t_c=3&alpha_range_um_per_m_c=1&e_ve_um=2"
      "&machine_temperature_c=20.6&air_temperature_c=20.4&note=laser%20XL-80";
  c = client_->Post("/api/v1/machines/m1/positioning-checks" + query, csv, "text/csv");
  ASSERT_EQ(c->status, 201) << c->body;
  ce = json::parse(c->body);
  EXPECT_TRUE(ce["uncertainty_um"]["stated"].get<bool>());
  EXPECT_EQ(ce["uncertainty_um"], e["uncertainty_um"]);
  EXPECT_EQ(ce["input"]["machine_temperature_c"], 20.6);
  EXPECT_EQ(ce["input"]["note"], "laser XL-80");
  // An unknown or malformed parameter is a 400 naming it; nothing stored.
  for (const char* bad : {"?axis=Y&ts=2026-03-13T08:00:00Z&devise_um_per_m=0.5",
                          "?axis=Y&ts=2026-03-13T08:00:00Z&e_ve_um=two",
                          "?axis=Y&ts=2026-03-13T08:00:00Z&compensation_active=yes",
                          "?axis=Y&ts=2026-03-13T08:00:00Z&e_ve_um=1&e_ve_um=2"}) {
    auto r2 =
        client_->Post("/api/v1/machines/m1/positioning-checks" + std::string(bad), csv, "text/csv");
    EXPECT_EQ(r2->status, 400) << bad << " " << r2->body;
  }
  EXPECT_EQ(Count("SELECT COUNT(*) FROM positioning_checks"), 3);

  // Listed per machine, oldest first, with the values of each report.
  const json list = Get("/api/v1/machines/m1/positioning-checks");
  ASSERT_EQ(list["checks"].size(), 3u);
  const json& first = list["checks"][0];
  EXPECT_EQ(first["id"], e["id"]);
  EXPECT_EQ(first["axis"], "Y");
  EXPECT_DOUBLE_EQ(first["A_um"].get<double>(), e["iso230_2"]["A_um"].get<double>());
  EXPECT_DOUBLE_EQ(first["P_um"].get<double>(), e["vdi3441"]["P_um"].get<double>());
  EXPECT_DOUBLE_EQ(first["travel_mm"].get<double>(), 1000.0);
  EXPECT_LE(list["checks"][0]["ts"].get<std::string>(), list["checks"][1]["ts"].get<std::string>());
  EXPECT_EQ(Get("/api/v1/machines/m1/positioning-checks?axis=Y")["checks"].size(), 3u);
  EXPECT_EQ(client_->Get("/api/v1/machines/m1/positioning-checks?axis=Q")->status, 404);
  EXPECT_EQ(client_->Get("/api/v1/machines/m1/positioning-checks?ts=x")->status, 400);
  EXPECT_EQ(client_->Get("/api/v1/machines/m1/positioning-checks?axis=Y&axis=X")->status, 400);
  EXPECT_EQ(client_->Get("/api/v1/machines/m1/positioning-checks?axis=%FF")->status, 400);
  EXPECT_EQ(client_->Get("/api/v1/machines/m1/positioning-checks?axis=")->status, 400);
  EXPECT_EQ(client_->Get("/api/v1/machines/nope/positioning-checks")->status, 404);
}

TEST_F(CheckHttpTest, MalformedChecksAreRefusedAndStoreNothing) {
  PutArtifact();
  auto expect = [&](const json& body, int status, const std::string& field) {
    auto r = Post("/api/v1/machines/m1/positioning-checks", body);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, status) << body.dump() << " " << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
    json p = json::parse(r->body);
    ASSERT_FALSE(p["errors"].empty()) << r->body;
    EXPECT_EQ(p["errors"][0]["field"].get<std::string>().rfind(field, 0), 0u) << r->body;
  };
  json b = Positioning();
  b.erase("runs");
  expect(b, 400, "runs");
  b = Positioning();
  b["runs"][1]["deviations_um"] = {0.0};
  expect(b, 422, "runs[1].deviations_um");
  b = Positioning();
  b["targets_mm"] = {1000, 0};
  expect(b, 422, "targets_mm");
  b = Positioning();
  b["runs"].erase(3);
  expect(b, 422, "runs");
  b = Positioning();
  b["runs"][0]["direction"] = "up";
  expect(b, 400, "runs.direction");
  b = Positioning();
  b["axis"] = "Q";
  auto r = Post("/api/v1/machines/m1/positioning-checks", b);
  EXPECT_EQ(r->status, 404);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM positioning_checks"), 0);

  json cc = ColumnCheck("2026-03-16T06:00:00Z", 0, 0, 0);
  cc["artifact"] = "nope";
  EXPECT_EQ(Post("/api/v1/machines/m1/column-checks", cc)->status, 422);
  cc = ColumnCheck("2026-03-16T06:00:00Z", 0, 0, 0);
  cc["request_id"] = 99;
  EXPECT_EQ(Post("/api/v1/machines/m1/column-checks", cc)->status, 422);
  cc = ColumnCheck("2026-03-16T06:00:00Z", 0, 0, 0);
  cc["spheres"].erase(2);
  EXPECT_EQ(Post("/api/v1/machines/m1/column-checks", cc)->status, 422);
  cc.erase("spheres");
  EXPECT_EQ(Post("/api/v1/machines/m1/column-checks", cc)->status, 400);
  EXPECT_EQ(
      Post("/api/v1/machines/nope/column-checks", ColumnCheck("2026-03-16T06:00:00Z", 0, 0, 0))
          ->status,
      404);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM column_checks"), 0);
  auto bad_art = client_->Put("/api/v1/artifacts/col-2", R"({"points": []})", "application/json");
  EXPECT_EQ(bad_art->status, 400);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM artifacts"), 1);
  EXPECT_EQ(client_->Get("/api/v1/artifacts/col-2")->status, 404);
}

// The line acknowledges a request it will run: the first acknowledgement is
// kept, a done request is a conflict, and a request of another machine, a
// malformed id or name is refused with nothing stored.
TEST_F(CheckHttpTest, AcknowledgingARequestRecordsTheFirstWhileItIsOpen) {
  FieldErrors errors;
  ASSERT_TRUE(app_->machines().Register(VirtualMachine::Definition("m2"), "test", &errors).ok());
  const std::string base = "/api/v1/machines/m1/column-checks/requests";
  auto r = Post(base, {{"reason", "spindle exchanged"}});
  ASSERT_EQ(r->status, 201) << r->body;
  const std::string id = json::parse(r->body)["id"].dump();
  const std::string ack = base + "/" + id + "/acknowledge";
  json listed = Get(base)["requests"][0];
  EXPECT_TRUE(listed["acknowledged_at"].is_null() && listed["acknowledged_by"].is_null());

  auto refused = [&](const std::string& path, const std::string& body, int status,
                     const std::string& field) {
    auto b = client_->Post(path, body, "application/json");
    ASSERT_TRUE(b);
    EXPECT_EQ(b->status, status) << path << " " << body << " " << b->body;
    EXPECT_EQ(b->get_header_value("Content-Type"), "application/problem+json");
    if (!field.empty()) {
      EXPECT_EQ(json::parse(b->body)["errors"][0]["field"], field) << b->body;
    }
  };
  // Empty, too long, a control character, a number; a name that reads as
  // another (a direction override, a zero-width space, padding).
  for (const json& by :
       {json(""), json(std::string(65, 'a')), json("line\n2"), json(7), json("admin\u202Eevil"),
        json("Ann\u200B"), json(" Ann"), json("Ann\u00A0"), json("ad\u00ADmin")}) {
    refused(ack, json{{"by", by}}.dump(), 400, "by");
  }
  refused(ack, "[]", 400, "body");
  refused(base + "/first/acknowledge", "", 400, "id");
  refused(base + "/99999/acknowledge", "", 404, "");
  refused("/api/v1/machines/m2/column-checks/requests/" + id + "/acknowledge", "", 404, "");
  refused("/api/v1/machines/nope/column-checks/requests/" + id + "/acknowledge", "", 404, "");
  EXPECT_EQ(Count("SELECT COUNT(*) FROM check_requests WHERE acknowledged_at IS NOT NULL"), 0);

  // 64 characters of two bytes each are a name.
  std::string name;
  for (int i = 0; i < 64; ++i) name += "ü";
  r = Post(ack, {{"by", name}});
  ASSERT_EQ(r->status, 200) << r->body;
  const json first = json::parse(r->body);
  EXPECT_EQ(first["id"].dump(), id);
  EXPECT_EQ(first["state"], "pending");
  EXPECT_EQ(first["acknowledged_by"], name);
  EXPECT_EQ(first["acknowledged_at"], FormatRfc3339(clock_.NowMs()));
  EXPECT_EQ(Get(base)["requests"][0], first);
  // Again, later and by someone else: the first one is kept.
  clock_.Advance(60000);
  r = client_->Post(ack, "", "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_EQ(json::parse(r->body), first);
  EXPECT_EQ(json::parse(Post(ack, {{"by", "Ben"}})->body), first);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM audit WHERE action = 'check-request-acknowledge'"), 1);

  // Without tokens and without a name nobody is named.
  r = Post(base, {{"reason", "weekly"}});
  const std::string second = base + "/" + json::parse(r->body)["id"].dump() + "/acknowledge";
  r = client_->Post(second, "", "application/json");
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_TRUE(json::parse(r->body)["acknowledged_by"].is_null());
  EXPECT_FALSE(json::parse(r->body)["acknowledged_at"].is_null());

  // A result closes the oldest open request; acknowledging it is then a
  // conflict, and what was acknowledged stays.
  PutArtifact();
  r = Post("/api/v1/machines/m1/column-checks", ColumnCheck("2026-03-16T06:00:00Z", 0, 0, 0));
  ASSERT_EQ(r->status, 201) << r->body;
  ASSERT_EQ(json::parse(r->body)["request_id"].dump(), id);
  refused(ack, "", 409, "");
  json done = Get(base + "?state=done")["requests"][0];
  EXPECT_EQ(done["acknowledged_by"], name);
  EXPECT_EQ(done["acknowledged_at"], first["acknowledged_at"]);
}

// A plant in Berlin reads its reports in Berlin time; the JSON stays UTC.
class CheckHttpBerlinTest : public CheckHttpTest {
 protected:
  void Configure(Config& c) override { c.web_time_zone = "Europe/Berlin"; }
};

TEST_F(CheckHttpBerlinTest, TheReportSaysWhenInThePlantsZone) {
  PutArtifact();
  auto r = Post("/api/v1/machines/m1/column-checks",
                ColumnCheck("2026-03-16T06:00:00Z", 0.003, 0.004, -0.002));
  ASSERT_EQ(r->status, 201) << r->body;
  const std::string one = "/api/v1/machines/m1/column-checks/" + json::parse(r->body)["id"].dump();
  EXPECT_EQ(Get(one)["ts"], "2026-03-16T06:00:00.000Z");
  for (const char* query : {"?format=markdown", "?format=html"}) {
    auto text = client_->Get(one + query);
    ASSERT_TRUE(text);
    EXPECT_NE(text->body.find("Measured 2026-03-16 07:00:00 CET"), std::string::npos) << text->body;
  }
}

}  // namespace
}  // namespace thermocomp
