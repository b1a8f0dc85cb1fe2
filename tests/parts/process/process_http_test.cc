// Part-error models from the process over real HTTP on a real SQLite file:
// process records in as CSV and JSON (every hostile file refused with the
// row and column named and nothing stored), a fit on a simulated lathe
// that finds the truth's inputs and drops the dead one, a machine with
// nothing to find whose models are not activated, the versions listed,
// shown and activated, and predictions that are refused outside the
// trained ranges.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/time_format.h"
#include "service/parts/process/part_model_service.h"
#include "sim/parts/process_lathe.h"

namespace thermocomp {
namespace {

using nlohmann::json;
using testing::kT0;

const std::string kRecords = "/api/v1/machines/lathe/process-records";
const std::string kModels = "/api/v1/machines/lathe/part-models";

// A small network (hidden 2, restarts 2) keeps the test fast under sanitizers.
json FitBody(const std::string& target = "size_error_um") {
  return {{"target", target},       {"types", {"quadratic", "neural"}},
          {"held_out_share", 0.25}, {"seed", 1},
          {"neural_hidden", 2},     {"neural_restarts", 2}};
}

class ProcessHttpTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = testing::TestClient(http_->port());
    FieldErrors errors;
    MachineRecord m = VirtualMachine::Definition("lathe");
    ASSERT_TRUE(app_->machines().Register(m, "test", &errors).ok());
  }
  httplib::Result PostJson(const std::string& path, const json& body) {
    return client_->Post(path, body.dump(), "application/json");
  }
  httplib::Result PostCsv(const std::string& csv) {
    return client_->Post(kRecords, csv, "text/csv");
  }
  std::string Csv(int records, uint64_t seed, bool nothing = false) {
    return LatheCsv(SimulateLathe(
        {.seed = seed, .records = records, .start_ms = kT0, .nothing_to_find = nothing}));
  }
  // POST `csv`, expect `status` naming `field` at data row `row`, nothing stored.
  void ExpectRefused(const std::string& csv, int status, size_t row, const std::string& field,
                     const std::string& content_type = "text/csv") {
    SCOPED_TRACE(field + " row " + std::to_string(row));
    const int64_t records = Count("SELECT COUNT(*) FROM process_records");
    const int64_t audits = Count("SELECT COUNT(*) FROM audit");
    auto r = client_->Post(kRecords, csv, content_type);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, status) << r->body.substr(0, 400);
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
    const json p = json::parse(r->body, nullptr, false);
    bool named = false;
    for (const json& e : p.value("errors", json::array())) {
      named |= e.value("field", "") == field && e.value("index", size_t{999999}) == row;
    }
    EXPECT_TRUE(named) << r->body.substr(0, 400);
    EXPECT_EQ(Count("SELECT COUNT(*) FROM process_records"), records);
    EXPECT_EQ(Count("SELECT COUNT(*) FROM audit"), audits);
  }
  std::unique_ptr<httplib::Client> client_;
};

const std::string kHeader =
    "part,feature,cut_at,ap_mm,f_mm_rev,vc_m_min,temperature_c,size_error_um\n";
const std::string kGoodRow = "P1,D1,2026-03-01T06:00:00Z,1.5,0.2,200,25,1.2\n";

TEST_F(ProcessHttpTest, HostileFilesAreRefusedNamingRowAndColumnAndStoreNothing) {
  ExpectRefused(
      "part,feature,cut_at,ap_mm,vc_m_min,size_error_um\nP1,D1,2026-03-01T06:00:00Z,1,"
      "200,1\n",
      400, 0, "f_mm_rev");
  ExpectRefused(
      "part,feature,cut_at,ap_mm,f_mm_rev,vc_m_min\nP1,D1,2026-03-01T06:00:00Z,1,0.2,"
      "200\n",
      400, 0, "size_error_um");
  ExpectRefused("part,feature,cut_at,ap_mm,ap_mm,f_mm_rev,vc_m_min,size_error_um\n", 400, 0,
                "ap_mm");
  ExpectRefused("part,feature,cut_at,ap_mm,f_mm_rev,vc_m_min,size_error_um,colour\n", 400, 0,
                "colour");
  for (const char* bad : {"nan", "inf", "-inf", "1e999", "abc", "0x1p3x"}) {
    ExpectRefused(kHeader + kGoodRow + "P1,D2,2026-03-01T06:01:00Z,1.5,0.2,200," + bad + ",1\n",
                  400, 2, "temperature_c");
  }
  ExpectRefused(kHeader + kGoodRow + "P2,D1,2026-03-01T06:01:00Z,1.5,0.2,200,25\n", 400, 2, "row");
  ExpectRefused(kHeader + kGoodRow + "P2,D1,yesterday,1.5,0.2,200,25,1\n", 400, 2, "cut_at");
  // Wrong units: a depth of cut in µm, a feed in mm/min, a size error in mm as µm.
  ExpectRefused(kHeader + kGoodRow + "P2,D1,2026-03-01T06:01:00Z,1500,0.2,200,25,1\n", 400, 2,
                "ap_mm");
  ExpectRefused(kHeader + "P2,D1,2026-03-01T06:01:00Z,1.5,200,200,25,1\n", 400, 1, "f_mm_rev");
  ExpectRefused(kHeader + "P2,D1,2026-03-01T06:01:00Z,1.5,0.2,-5,25,1\n", 400, 1, "vc_m_min");
  ExpectRefused(kHeader + "P2,D1,2026-03-01T06:01:00Z,1.5,0.2,200,25,\n", 400, 1, "size_error_um");
  ExpectRefused(kHeader + kGoodRow + "P1,D1,2026-03-01T06:02:00Z,1.5,0.2,200,25,1\n", 400, 2,
                "feature");
  ExpectRefused(kHeader + kGoodRow + "P 2,D1,2026-03-01T06:02:00Z,1.5,0.2,200,25,1\n", 400, 2,
                "part");
  ExpectRefused(kHeader + kGoodRow +
                    "P\xff"
                    "2,D1,2026-03-01T06:02:00Z,1.5,0.2,200,25,1\n",
                400, 2, "row");
  ExpectRefused("", 400, 0, "header");
  ExpectRefused(kHeader, 400, 0, "body");
  ExpectRefused(kHeader + std::string(1000000, '\n'), 413, 100001, "row");
  ExpectRefused(kHeader + kGoodRow + std::string(200000, '\n') + kGoodRow, 413, 100001, "row");
  ExpectRefused(R"({"records": [{"part": "P1", "feature": "D1", "cut_at": "2026-03-01T06:00:00Z",
                 "ap_mm": 1.5, "f_mm_rev": 0.2, "vc_m_min": 200, "size_error_um": 1e999}]})",
                400, 0, "body", "application/json");
  ExpectRefused(R"({"records": [{"part": "P1", "feature": "D1", "cut_at": "2026-03-01T06:00:00Z",
                 "ap_mm": 1.5, "vc_m_min": 200, "size_error_um": 1}]})",
                400, 0, "records.f_mm_rev", "application/json");
  EXPECT_EQ(client_->Post(kRecords, kHeader + kGoodRow, "text/plain")->status, 415);
  EXPECT_EQ(
      client_->Post("/api/v1/machines/nowhere/process-records", kHeader + kGoodRow, "text/csv")
          ->status,
      404);

  // Accepted once; the same feature again is a conflict and adds nothing.
  auto ok = PostCsv(kHeader + kGoodRow);
  ASSERT_EQ(ok->status, 201) << ok->body;
  EXPECT_EQ(json::parse(ok->body)["accepted"], 1);
  auto again = PostCsv(kHeader + "P9,D9,2026-03-01T06:05:00Z,1,0.2,200,25,1\n" + kGoodRow);
  EXPECT_EQ(again->status, 409) << again->body;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM process_records"), 1);
  auto listed = client_->Get(kRecords);
  ASSERT_EQ(listed->status, 200);
  const json records = json::parse(listed->body)["records"];
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(records[0]["ap_mm"], 1.5);
  EXPECT_TRUE(records[0]["fc_n"].is_null());
  ASSERT_EQ(PostCsv(kHeader + "P3,D1,2026-03-01T07:00:00Z,1,0.2,200,25,1\n")->status, 201);
  auto newest = client_->Get(kRecords + "?limit=1");
  ASSERT_EQ(newest->status, 200);
  ASSERT_EQ(json::parse(newest->body)["records"].size(), 1u);
  EXPECT_EQ(json::parse(newest->body)["records"][0]["part"], "P3");
  for (const char* bad : {"0", "-1", "abc", "100001", "1e3"}) {
    EXPECT_EQ(client_->Get(kRecords + "?limit=" + bad)->status, 400) << bad;
  }
}

TEST_F(ProcessHttpTest, FitFindsTheTruthAndPredictionsOutsideTheRangeAreRefused) {
  auto posted = PostCsv(Csv(160, 21));
  ASSERT_EQ(posted->status, 201) << posted->body.substr(0, 600);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM process_records"), 160);
  auto fit = PostJson(kModels + "/fit", FitBody());
  ASSERT_TRUE(fit);
  ASSERT_EQ(fit->status, 201) << fit->body.substr(0, 2000);
  const json report = json::parse(fit->body);

  // Power: the truth's inputs kept, the dead one dropped.
  std::set<std::string> kept;
  for (const json& k : report["kept"]) kept.insert(k.get<std::string>());
  EXPECT_EQ(kept, (std::set<std::string>{"ap_mm", "f_mm_rev", "vc_m_min", "temperature_c"}));
  bool fp_ranked = false;
  for (const json& i : report["ranking"]["inputs"]) {
    if (i["name"] == "fp_n") {
      fp_ranked = true;
      EXPECT_FALSE(i["kept"].get<bool>());
      EXPECT_LT(i["ratio"].get<double>(), 1.05);
    }
  }
  EXPECT_TRUE(fp_ranked);
  EXPECT_EQ(report["held_out_rows"], 40);
  EXPECT_EQ(report["training_rows"], 120);

  // Held-out error near the noise (1 µm); far below the mean's.
  ASSERT_TRUE(report["accepted"].get<bool>()) << report["decision"];
  const int active = report["active_version"].get<int>();
  double best = 1e9, best_served = 1e9;
  for (const json& t : report["types"]) {
    ASSERT_TRUE(t["fitted"].get<bool>()) << t.dump();
    const json& h = t["held_out"];
    EXPECT_GT(h["baseline_rmse"].get<double>(), 3.0);
    EXPECT_EQ(t["predicted"].size(), 40u);
    best = std::min(best, h["rmse"].get<double>());
    best_served = std::min(best_served, h["served_rmse"].get<double>());
  }
  EXPECT_LT(best, 1.6);
  EXPECT_GT(best, 0.6);
  // Where the model serves, its error is the noise's.
  EXPECT_LT(best_served, 1.35);

  // The held-out records took no part in training: every held-out record id
  // is outside the training part.
  std::set<int64_t> held;
  for (const json& h : report["held_out"]) held.insert(h["record_id"].get<int64_t>());
  EXPECT_EQ(held.size(), 40u);

  // Listed, shown in every format.
  auto list = client_->Get(kModels);
  ASSERT_EQ(list->status, 200);
  const json models = json::parse(list->body)["models"];
  ASSERT_EQ(models.size(), 2u);
  int actives = 0;
  for (const json& m : models) actives += m["status"] == "active";
  EXPECT_EQ(actives, 1);
  auto one = client_->Get(kModels + "/" + std::to_string(active));
  ASSERT_EQ(one->status, 200);
  EXPECT_EQ(json::parse(one->body)["model"]["ranges"].size(), 4u);
  EXPECT_EQ(client_->Get(kModels + "/99")->status, 404);

  // The guard: inside a value, outside never one.
  const std::string predict = kModels + "/" + std::to_string(active) + "/predict";
  json inputs = {{"ap_mm", 1.5}, {"f_mm_rev", 0.2}, {"vc_m_min", 200}, {"temperature_c", 25}};
  auto in = PostJson(predict, {{"inputs", inputs}});
  ASSERT_EQ(in->status, 200) << in->body;
  const json pin = json::parse(in->body);
  EXPECT_TRUE(pin["valid"].get<bool>());
  EXPECT_TRUE(pin["in_range"].get<bool>());
  EXPECT_NEAR(pin["value"].get<double>(), LatheTruthSizeErrorUm(1.5, 0.2, 200, 25), 1.5);
  for (int version : {1, 2}) {
    json far = inputs;
    far["ap_mm"] = 6.0;
    auto out = PostJson(kModels + "/" + std::to_string(version) + "/predict", {{"inputs", far}});
    ASSERT_EQ(out->status, 200) << out->body;
    const json pout = json::parse(out->body);
    EXPECT_FALSE(pout["valid"].get<bool>());
    EXPECT_FALSE(pout["in_range"].get<bool>());
    EXPECT_TRUE(pout["value"].is_null());
    ASSERT_EQ(pout["outside"].size(), 1u);
    EXPECT_EQ(pout["outside"][0]["input"], "ap_mm");
    EXPECT_LE(pout["outside"][0]["high"].get<double>(), kLatheApMm[1]);
    EXPECT_NE(pout["reason"].get<std::string>().find("ap_mm"), std::string::npos);
  }
  // Bad inputs: unknown, missing, not a number.
  json typo = inputs;
  typo["ap"] = 1.0;
  EXPECT_EQ(PostJson(predict, {{"inputs", typo}})->status, 400);
  json missing = inputs;
  missing.erase("vc_m_min");
  auto m = PostJson(predict, {{"inputs", missing}});
  EXPECT_EQ(m->status, 400);
  EXPECT_NE(m->body.find("inputs.vc_m_min"), std::string::npos);
  json text = inputs;
  text["ap_mm"] = "1.5";
  EXPECT_EQ(PostJson(predict, {{"inputs", text}})->status, 400);
  EXPECT_EQ(PostJson(predict, json::object())->status, 400);

  // Activation of the other version, audited.
  const int other = active == 1 ? 2 : 1;
  auto act =
      client_->Post(kModels + "/" + std::to_string(other) + "/activate", "", "application/json");
  ASSERT_EQ(act->status, 200) << act->body;
  EXPECT_EQ(json::parse(act->body)["status"], "active");
  EXPECT_EQ(Count("SELECT COUNT(*) FROM part_models WHERE status = 'active'"), 1);
  EXPECT_EQ(client_->Post(kModels + "/77/activate", "", "application/json")->status, 404);
}

TEST_F(ProcessHttpTest, ReportsAsMarkdownAndHtml) {
  ASSERT_EQ(PostCsv(Csv(80, 5))->status, 201);
  json body = FitBody();
  body["types"] = {"quadratic"};
  auto fit = PostJson(kModels + "/fit", body);
  ASSERT_EQ(fit->status, 201) << fit->body.substr(0, 1000);
  auto md = client_->Get(kModels + "/1?format=markdown");
  ASSERT_EQ(md->status, 200) << md->body;
  EXPECT_NE(md->body.find("# Part-error fit"), std::string::npos);
  EXPECT_NE(md->body.find("Inputs by sensitivity"), std::string::npos);
  auto html = client_->Get(kModels + "/1?format=html");
  ASSERT_EQ(html->status, 200);
  EXPECT_NE(html->body.find("<table>"), std::string::npos);
  EXPECT_EQ(client_->Get(kModels + "/1?format=pdf")->status, 400);
}

TEST_F(ProcessHttpTest, NothingToFindIsNotClaimed) {
  ASSERT_EQ(PostCsv(Csv(160, 21, true))->status, 201);
  auto fit = PostJson(kModels + "/fit", FitBody());
  ASSERT_TRUE(fit);
  ASSERT_TRUE(fit->status == 200 || fit->status == 201) << fit->body.substr(0, 1000);
  const json report = json::parse(fit->body);
  EXPECT_FALSE(report["accepted"].get<bool>()) << report["decision"];
  EXPECT_TRUE(report["active_version"].is_null());
  EXPECT_EQ(Count("SELECT COUNT(*) FROM part_models WHERE status IN ('active', 'candidate')"), 0);
  for (const json& t : report["types"]) {
    if (!t["fitted"].get<bool>()) continue;
    EXPECT_FALSE(t["held_out"]["beats_baseline"].get<bool>());
    EXPECT_LT(t["held_out"]["r2"].get<double>(), 0.2);
  }
  // Even with the inputs forced as candidates, nothing passes the ranking
  // and nothing is stored as served.
  json forced = FitBody();
  forced["inputs"] = {"ap_mm", "f_mm_rev", "vc_m_min"};
  forced["seed"] = 2;
  auto again = PostJson(kModels + "/fit", forced);
  ASSERT_TRUE(again->status == 200 || again->status == 201) << again->body.substr(0, 1000);
  EXPECT_FALSE(json::parse(again->body)["accepted"].get<bool>());
  EXPECT_EQ(Count("SELECT COUNT(*) FROM part_models WHERE status = 'active'"), 0);
}

TEST_F(ProcessHttpTest, FitRequestsThatCannotBeMetStoreNothing) {
  auto expect = [&](const json& body, int status, const std::string& needle) {
    SCOPED_TRACE(body.dump());
    auto r = PostJson(kModels + "/fit", body);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, status) << r->body;
    EXPECT_NE(r->body.find(needle), std::string::npos) << r->body;
    EXPECT_EQ(Count("SELECT COUNT(*) FROM part_models"), 0);
  };
  // Too few records for the requested model.
  ASSERT_EQ(PostCsv(Csv(10, 3))->status, 201);
  expect(FitBody(), 422, "too few records");
  // An input that does not vary (on a machine of its own: mixed with the
  // records above, vc would vary in a handful of them).
  FieldErrors errors;
  ASSERT_TRUE(
      app_->machines().Register(VirtualMachine::Definition("lathe2"), "test", &errors).ok());
  std::string csv = "part,feature,cut_at,ap_mm,f_mm_rev,vc_m_min,temperature_c,size_error_um\n";
  const auto sim = SimulateLathe({.seed = 4, .records = 60, .start_ms = kT0});
  for (const auto& r : sim) {
    csv += r.part + "," + r.feature + "," + FormatRfc3339(r.cut_ms) + "," +
           std::to_string(r.values.at("ap_mm")) + "," + std::to_string(r.values.at("f_mm_rev")) +
           ",200," + std::to_string(r.values.at("temperature_c")) + "," +
           std::to_string(r.values.at("size_error_um")) + "\n";
  }
  ASSERT_EQ(client_->Post("/api/v1/machines/lathe2/process-records", csv, "text/csv")->status, 201);
  const std::string fit2 = "/api/v1/machines/lathe2/part-models/fit";
  json body = FitBody();
  auto constant = PostJson(fit2, body);
  EXPECT_EQ(constant->status, 422);
  EXPECT_NE(constant->body.find("input vc_m_min does not vary"), std::string::npos)
      << constant->body;
  body["inputs"] = {"ap_mm", "f_mm_rev", "vc_m_min"};
  auto named = PostJson(fit2, body);
  EXPECT_EQ(named->status, 422);
  EXPECT_NE(named->body.find("input vc_m_min does not vary"), std::string::npos) << named->body;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM part_models"), 0);
  // A network too large for the records, alone: no type fitted.
  body["inputs"] = {"ap_mm", "f_mm_rev", "temperature_c"};
  body["types"] = {"neural"};
  body["neural_hidden"] = 8;
  auto big = PostJson(fit2, body);
  EXPECT_EQ(big->status, 422);
  EXPECT_NE(big->body.find("no model type could be fitted"), std::string::npos) << big->body;
  // The request itself.
  expect({{"target", "colour_um"}}, 400, "target");
  expect({{"inputs", {"ap_mm", "ap_mm"}}}, 400, "inputs");
  expect({{"inputs", {"spindle_rpm"}}}, 400, "inputs");
  expect({{"types", {"spline"}}}, 400, "types");
  expect({{"held_out_share", 0.9}}, 400, "held_out_share");
  expect({{"neural_hidden", 100}}, 400, "neural_hidden");
  expect({{"sede", 1}}, 400, "sede");
  EXPECT_EQ(client_->Post(kModels + "/fit", "{", "application/json")->status, 400);
  EXPECT_EQ(PostJson("/api/v1/machines/nowhere/part-models/fit", FitBody())->status, 404);
}

}  // namespace
}  // namespace thermocomp
