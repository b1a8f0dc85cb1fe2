// What a control applied (POST .../compensation/applied): stored with the
// server's clock and shown in GET .../compensation, a retry of the newest
// sequence kept once, the roles that may write, bad bodies refused naming
// the field with nothing stored, and the newest record served again after
// a restart.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/time_format.h"

namespace thermocomp {
namespace {

using nlohmann::json;

const std::string kAppliedAdmin = "applied-admin-token-0123456789";
const std::string kAppliedCell1 = "applied-cell-1-token-012345678";
const std::string kAppliedCell2 = "applied-cell-2-token-012345678";
const std::string kAppliedReader = "applied-reader-token-012345678";

class AppliedHttpTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override {
    c.tokens = {{"admin", kAppliedAdmin, "admin", ""},
                {"cell-1", kAppliedCell1, "machine", "m1"},
                {"cell-2", kAppliedCell2, "machine", "m2"},
                {"viewer", kAppliedReader, "reader", ""}};
  }
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = testing::TestClient(http_->port());
    for (const char* name : {"m1", "m2"}) {
      MachineRecord m;
      m.name = name;
      m.sensors = {{0, "T1", "", 1.0}};
      m.axes = {{0, "X", 0.0, {"T1"}, 0.03}, {0, "Y", 600.0, {"T1"}, 0.03}};
      ASSERT_TRUE(app_->machines().Register(m, "test", nullptr).ok());
    }
  }
  httplib::Result Post(const std::string& token, const std::string& machine,
                       const std::string& body) {
    return client_->Post("/api/v1/machines/" + machine + "/compensation/applied",
                         {{"Authorization", "Bearer " + token}}, body, "application/json");
  }
  json Compensation(const std::string& machine) {
    auto r = client_->Get("/api/v1/machines/" + machine + "/compensation",
                          {{"Authorization", "Bearer " + kAppliedReader}});
    EXPECT_EQ(r->status, 200) << r->body;
    return json::parse(r->body);
  }
  static const json& AxisOf(const json& compensation, const std::string& axis) {
    for (const json& a : compensation["axes"]) {
      if (a["axis"] == axis) return a;
    }
    static const json none;
    return none;
  }
  int64_t Rows() { return Count("SELECT COUNT(*) FROM applied_compensation"); }
  int64_t AuditLines() {
    return Count("SELECT COUNT(*) FROM audit WHERE action = 'compensation-applied'");
  }
  void Restart() {
    http_->Stop();
    http_.reset();
    app_.reset();
    auto app = OpenApp(config_, clock_);
    ASSERT_TRUE(app.ok()) << app.status().ToString();
    app_ = std::move(app).value();
    StartHttp();
    client_ = testing::TestClient(http_->port());
  }
  std::unique_ptr<httplib::Client> client_;
};

constexpr const char* kAppliedFullBody =
    R"({"axis": "Y", "sequence": 17, "offset_mm": -0.0123, "slope_um_per_m": 4.2,)"
    R"( "offset_at_probe_mm": -0.0119, "via": "opcua"})";

TEST_F(AppliedHttpTest, StoredWithTheServersClockAndShownInTheCompensation) {
  const json before = Compensation("m1");
  EXPECT_TRUE(AxisOf(before, "Y").contains("applied"));
  EXPECT_TRUE(AxisOf(before, "Y")["applied"].is_null());
  EXPECT_TRUE(AxisOf(before, "X")["applied"].is_null());

  auto r = Post(kAppliedCell1, "m1", kAppliedFullBody);
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 201) << r->body;
  const json stored = json::parse(r->body);
  EXPECT_EQ(stored["machine"], "m1");
  EXPECT_EQ(stored["axis"], "Y");
  EXPECT_EQ(stored["sequence"], 17);
  EXPECT_EQ(stored["applied_at"], FormatRfc3339(clock_.NowMs()));
  EXPECT_EQ(stored["offset_mm"], -0.0123);
  EXPECT_EQ(stored["slope_um_per_m"], 4.2);
  EXPECT_EQ(stored["offset_at_probe_mm"], -0.0119);
  EXPECT_EQ(stored["via"], "opcua");
  EXPECT_EQ(stored["actor"], "token:cell-1");
  EXPECT_EQ(AuditLines(), 1);

  const json after = Compensation("m1");
  json applied = stored;
  applied.erase("machine");
  applied.erase("axis");
  EXPECT_EQ(AxisOf(after, "Y")["applied"], applied);
  EXPECT_TRUE(AxisOf(after, "X")["applied"].is_null());
  // The served fields are all still there, and the other machine is untouched.
  EXPECT_EQ(AxisOf(after, "Y")["state"], AxisOf(before, "Y")["state"]);
  EXPECT_TRUE(AxisOf(Compensation("m2"), "Y")["applied"].is_null());
  // The controls' text formats are as they were.
  auto text = client_->Get("/api/v1/machines/m1/compensation?format=beckhoff",
                           {{"Authorization", "Bearer " + kAppliedReader}});
  EXPECT_EQ(text->body.find("applied"), std::string::npos);

  // Only the axis' sequence counts: the values may be left out, via defaults.
  clock_.Advance(60000);
  auto next = Post(kAppliedAdmin, "m1", R"({"axis": "Y", "sequence": 18})");
  ASSERT_EQ(next->status, 201) << next->body;
  const json y = AxisOf(Compensation("m1"), "Y")["applied"];
  EXPECT_EQ(y["sequence"], 18);
  EXPECT_EQ(y["applied_at"], FormatRfc3339(clock_.NowMs()));
  EXPECT_TRUE(y["offset_mm"].is_null());
  EXPECT_EQ(y["via"], "http");
  EXPECT_EQ(y["actor"], "token:admin");
}

TEST_F(AppliedHttpTest, TheNewestSequenceAgainIsARetryStoredOnce) {
  ASSERT_EQ(Post(kAppliedCell1, "m1", kAppliedFullBody)->status, 201);
  const std::string first = json::parse(Post(kAppliedCell1, "m1", kAppliedFullBody)->body).dump();
  clock_.Advance(5000);
  auto again = Post(kAppliedCell1, "m1", kAppliedFullBody);
  ASSERT_EQ(again->status, 200) << again->body;
  EXPECT_EQ(json::parse(again->body).dump(), first);  // the stored record, its time too
  EXPECT_EQ(Rows(), 1);
  EXPECT_EQ(AuditLines(), 1);
  // The same sequence with other values is no retry: 409 naming it, the
  // first report kept.
  json other = json::parse(kAppliedFullBody);
  other["offset_mm"] = 0.5;
  auto conflict = Post(kAppliedCell1, "m1", other.dump());
  ASSERT_EQ(conflict->status, 409) << conflict->body;
  EXPECT_EQ(json::parse(conflict->body)["errors"][0]["field"], "sequence");
  EXPECT_EQ(Rows(), 1);
  EXPECT_EQ(json::parse(Post(kAppliedCell1, "m1", kAppliedFullBody)->body).dump(), first);
  // A retry stating fewer values (the face restarted) is still a retry.
  auto bare = Post(kAppliedCell1, "m1", R"({"axis": "Y", "sequence": 17, "via": "opcua"})");
  ASSERT_EQ(bare->status, 200) << bare->body;
  EXPECT_EQ(json::parse(bare->body).dump(), first);
  EXPECT_EQ(Rows(), 1);
  // Another axis, or another sequence, is a new record.
  EXPECT_EQ(Post(kAppliedCell1, "m1", R"({"axis": "X", "sequence": 17})")->status, 201);
  EXPECT_EQ(Post(kAppliedCell1, "m1", R"({"axis": "Y", "sequence": 16})")->status, 201);
  EXPECT_EQ(Rows(), 3);
  EXPECT_EQ(AxisOf(Compensation("m1"), "Y")["applied"]["sequence"], 16);
}

TEST_F(AppliedHttpTest, OnlyTheMachinesOwnTokenAndAdminMayWrite) {
  auto other = Post(kAppliedCell2, "m1", kAppliedFullBody);
  EXPECT_EQ(other->status, 403) << other->body;
  EXPECT_EQ(Post(kAppliedReader, "m1", kAppliedFullBody)->status, 403);
  EXPECT_EQ(Rows(), 0);
  EXPECT_EQ(Post(kAppliedCell2, "m2", kAppliedFullBody)->status, 201);
  EXPECT_EQ(Post(kAppliedAdmin, "m1", kAppliedFullBody)->status, 201);
  EXPECT_EQ(Post(kAppliedAdmin, "nope", kAppliedFullBody)->status, 404);
  EXPECT_EQ(Rows(), 2);
}

TEST_F(AppliedHttpTest, BadBodiesAreRefusedNamingTheFieldAndStoreNothing) {
  const std::vector<std::tuple<std::string, int, std::string>> cases = {
      {R"({"sequence": 1})", 400, "axis"},
      {R"({"axis": "Z", "sequence": 1})", 422, "axis"},
      {R"({"axis": 7, "sequence": 1})", 400, "axis"},
      {R"({"axis": "Y"})", 400, "sequence"},
      {R"({"axis": "Y", "sequence": -1})", 400, "sequence"},
      {R"({"axis": "Y", "sequence": 9007199254740992})", 400, "sequence"},
      {R"({"axis": "Y", "sequence": 1.5})", 400, "sequence"},
      {R"({"axis": "Y", "sequence": "17"})", 400, "sequence"},
      {R"({"axis": "Y", "sequence": 1, "offset_mm": 1000.5})", 400, "offset_mm"},
      {R"({"axis": "Y", "sequence": 1, "slope_um_per_m": -1e300})", 400, "slope_um_per_m"},
      {R"({"axis": "Y", "sequence": 1, "offset_at_probe_mm": "0.1"})", 400, "offset_at_probe_mm"},
      {R"({"axis": "Y", "sequence": 1, "via": "OPC UA"})", 400, "via"},
      {R"({"axis": "Y", "sequence": 1, "via": ""})", 400, "via"},
      {R"({"axis": "Y", "sequence": 1, "via": "abcdefghijklmnopqrstuvwxyz0123456"})", 400, "via"},
  };
  for (const auto& [body, status, field] : cases) {
    auto r = Post(kAppliedCell1, "m1", body);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, status) << body << " -> " << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json") << body;
    const json problem = json::parse(r->body);
    ASSERT_TRUE(problem.contains("errors")) << body << " -> " << r->body;
    EXPECT_EQ(problem["errors"][0]["field"], field) << body;
  }
  EXPECT_EQ(Post(kAppliedCell1, "m1", "[1]")->status, 400);
  EXPECT_EQ(Rows(), 0);
  EXPECT_EQ(AuditLines(), 0);
  // The largest sequence and the bounds themselves are taken; null is "not stated".
  EXPECT_EQ(Post(kAppliedCell1, "m1",
                 R"({"axis": "Y", "sequence": 9007199254740991, "offset_mm": -1000,)"
                 R"( "slope_um_per_m": null, "via": "plc_2-a"})")
                ->status,
            201);
}

TEST_F(AppliedHttpTest, TheNewestRecordIsServedAgainAfterARestart) {
  ASSERT_EQ(Post(kAppliedCell1, "m1", kAppliedFullBody)->status, 201);
  const json before = AxisOf(Compensation("m1"), "Y")["applied"];
  Restart();
  EXPECT_EQ(AxisOf(Compensation("m1"), "Y")["applied"], before);
  // And the retry rule holds across it.
  EXPECT_EQ(Post(kAppliedCell1, "m1", kAppliedFullBody)->status, 200);
  EXPECT_EQ(Rows(), 1);
}

TEST_F(AppliedHttpTest, TheHistoryIsNewestFirstAndBounded) {
  for (int sequence = 1; sequence <= 5; ++sequence) {
    clock_.Advance(60000);
    ASSERT_EQ(
        Post(kAppliedCell1, "m1", R"({"axis": "Y", "sequence": )" + std::to_string(sequence) + "}")
            ->status,
        201);
  }
  const httplib::Headers reader = {{"Authorization", "Bearer " + kAppliedReader}};
  auto r = client_->Get("/api/v1/machines/m1/compensation/applied?axis=Y&limit=3", reader);
  ASSERT_EQ(r->status, 200) << r->body;
  const json h = json::parse(r->body);
  ASSERT_EQ(h["records"].size(), 3u);
  EXPECT_EQ(h["records"][0]["sequence"], 5);
  EXPECT_EQ(h["records"][2]["sequence"], 3);
  EXPECT_EQ(h["records"][0]["axis"], "Y");
  EXPECT_EQ(client_->Get("/api/v1/machines/m1/compensation/applied?axis=Y&limit=0", reader)->status,
            400);
  EXPECT_EQ(client_->Get("/api/v1/machines/m1/compensation/applied", reader)->status, 400);
  EXPECT_EQ(client_->Get("/api/v1/machines/m1/compensation/applied?axis=Q", reader)->status, 404);
}

}  // namespace
}  // namespace thermocomp
