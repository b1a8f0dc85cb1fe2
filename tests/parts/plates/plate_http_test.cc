// The plate routes on a real server: import, conflict, list, the report in
// three formats, the holes as CSV; and hostile files, each refused with the
// row and field named and nothing stored.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "core/time_format.h"
#include "tests/api/guard_test_util.h"
#include "tests/app_fixture.h"
#include "tests/parts/plates/plate_fixture.h"

namespace thermocomp::testing {
namespace {

using nlohmann::json;

class PlateHttpTest : public AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = TestClient(http_->port());
    PlateSimOptions o;
    o.seed = 5;
    o.start_ms = clock_.NowMs() - 2 * 86400000LL;
    plate_ = SimulatePlate(o);
    LoadPlateHistory(*app_, "m1", plate_);
  }
  httplib::Result Post(const std::string& path, const std::string& body,
                       const std::string& type = "text/csv") {
    return client_->Post(path, body, type);
  }
  void ExpectNothingStored() {
    EXPECT_EQ(Count("SELECT COUNT(*) FROM plates"), 0);
    EXPECT_EQ(Count("SELECT COUNT(*) FROM plate_holes"), 0);
    EXPECT_EQ(Count("SELECT COUNT(*) FROM plate_hole_temperatures"), 0);
  }
  // The CMM file with one cell replaced: `row` 1 = first after the header.
  std::string WithCell(size_t row, size_t column, const std::string& value) {
    std::string csv = plate_.Csv();
    size_t start = 0;
    for (size_t r = 0; r < row; ++r) start = csv.find('\n', start) + 1;
    for (size_t c = 0; c < column; ++c) start = csv.find(',', start) + 1;
    const size_t end = csv.find_first_of(",\n", start);
    return csv.replace(start, end - start, value);
  }

  SimulatedPlate plate_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(PlateHttpTest, ImportListReport) {
  auto res = Post("/api/v1/machines/m1/plates/p1", plate_.Csv());
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 201) << res->body;
  EXPECT_EQ(res->get_header_value("Location"), "/api/v1/machines/m1/plates/p1");
  const json report = json::parse(res->body);
  EXPECT_EQ(report["plate"], "p1");
  EXPECT_EQ(report["axis"], "Y");
  EXPECT_EQ(report["holes"].size(), 40u);
  EXPECT_EQ(report["levels"].size(), 4u);
  EXPECT_EQ(report["pairs"].size(), 20u);
  EXPECT_TRUE(report["whole_plate"]["on"]["s_um"].is_number());
  EXPECT_TRUE(report["holes"][0]["predicted_drift_um"].is_number());
  EXPECT_TRUE(report["holes"][0]["temperatures_c"].contains("Tcb"));
  EXPECT_EQ(Count("SELECT COUNT(*) FROM plate_holes"), 40);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM audit WHERE action = 'import-plate'"), 1);

  // The same name again: 409, nothing more stored.
  res = Post("/api/v1/machines/m1/plates/p1", plate_.Csv());
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 409) << res->body;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM plate_holes"), 40);

  res = client_->Get("/api/v1/machines/m1/plates");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200);
  const json list = json::parse(res->body);
  ASSERT_EQ(list["plates"].size(), 1u);
  EXPECT_EQ(list["plates"][0]["plate"], "p1");
  EXPECT_EQ(list["plates"][0]["holes"], 40);
  EXPECT_EQ(list["plates"][0]["s_improvement"], report["summary"]["s_improvement"]);

  res = client_->Get("/api/v1/machines/m1/plates/p1");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200);
  EXPECT_EQ(json::parse(res->body)["whole_plate"], report["whole_plate"]);

  res = client_->Get("/api/v1/machines/m1/plates/p1", {{"Accept", "text/markdown"}});
  ASSERT_TRUE(res);
  EXPECT_EQ(res->get_header_value("Content-Type"), "text/markdown");
  EXPECT_NE(res->body.find("Per nominal level"), std::string::npos);
  res = client_->Get("/api/v1/machines/m1/plates/p1", {{"Accept", "text/html"}});
  ASSERT_TRUE(res);
  EXPECT_EQ(res->get_header_value("Content-Type"), "text/html");
  EXPECT_NE(res->body.find("<table>"), std::string::npos);

  // ?format= says the same as Accept; an unknown format is named.
  res = client_->Get("/api/v1/machines/m1/plates/p1?format=markdown");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->get_header_value("Content-Type"), "text/markdown");
  res = client_->Get("/api/v1/machines/m1/plates/p1?format=html");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->get_header_value("Content-Type"), "text/html");
  res = client_->Get("/api/v1/machines/m1/plates/p1?format=xml");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 400);
  EXPECT_NE(res->body.find("\"format\""), std::string::npos);

  // The X deviations compared instead: another plate, its axis X; an axis
  // the file does not hold is refused, naming it.
  res = Post("/api/v1/machines/m1/plates/p1x?axis=X", plate_.Csv());
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 201) << res->body;
  const json x = json::parse(res->body);
  EXPECT_EQ(x["axis"], "X");
  EXPECT_NE(x["whole_plate"]["off"]["s_um"], report["whole_plate"]["off"]["s_um"]);
  res = Post("/api/v1/machines/m1/plates/p1z?axis=Z", plate_.Csv());
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 400);
  EXPECT_NE(res->body.find("\"axis\""), std::string::npos);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM plates"), 2);

  res = client_->Get("/api/v1/machines/m1/plates/p1/holes.csv");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200);
  EXPECT_EQ(res->body.rfind("hole,pair,nominal_x_mm", 0), 0u);
  EXPECT_EQ(std::count(res->body.begin(), res->body.end(), '\n'), 41);

  res = client_->Get("/api/v1/machines/m1/plates/nope");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 404);
  res = client_->Get("/api/v1/machines/nope/plates");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 404);
}

// The plate's import goes through the guarded server like every other
// route (docs/api.md): a gzip CMM file is inflated and imported like the
// plain one, one that does not inflate is a 400 naming Content-Encoding
// with nothing stored, and each request counts in /metrics under its
// route's template.
TEST_F(PlateHttpTest, ACompressedFileIsInflatedAndCountedUnderItsRoute) {
  const httplib::Headers gzip = {{"Content-Encoding", "gzip"}};
  auto res = client_->Post("/api/v1/machines/m1/plates/p1", gzip, plate_.Csv(), "text/csv");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 400) << res->body;
  EXPECT_NE(res->body.find("Content-Encoding"), std::string::npos) << res->body;
  ExpectNothingStored();

  res =
      client_->Post("/api/v1/machines/m1/plates/p1", gzip, Compressed(plate_.Csv(), 1), "text/csv");
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 201) << res->body;
  auto plain = Post("/api/v1/machines/m1/plates/p2", plate_.Csv());
  ASSERT_TRUE(plain);
  ASSERT_EQ(plain->status, 201) << plain->body;
  json compressed = json::parse(res->body), uncompressed = json::parse(plain->body);
  EXPECT_EQ(compressed["holes"].size(), 40u);
  for (json* report : {&compressed, &uncompressed}) {  // the same report but for its name
    report->erase("plate");
    (*report)["summary"].erase("plate");
  }
  EXPECT_TRUE(compressed == uncompressed) << "the inflated file was read differently";

  const std::string plate = "route=\"/api/v1/machines/:machine/plates/:plate\"";
  const std::string text = MetricsWith(
      *client_, {"thermocomp_http_requests_total{" + plate + ",method=\"POST\",code=\"400\"} 1\n",
                 "thermocomp_http_requests_total{" + plate + ",method=\"POST\",code=\"201\"} 2\n"});
  EXPECT_NE(text.find(plate + ",method=\"POST\",code=\"201\"} 2\n"), std::string::npos) << text;
  EXPECT_NE(text.find(plate + ",method=\"POST\",code=\"400\"} 1\n"), std::string::npos) << text;
  EXPECT_EQ(text.find("route=\"unmatched\""), std::string::npos) << text;
}

struct BadFile {
  const char* what;
  std::string body;
  int status;
  size_t row;
  std::string field;
};

TEST_F(PlateHttpTest, BadFilesNameRowAndFieldAndStoreNothing) {
  const std::string header =
      "hole,pair,nominal_x_mm,nominal_y_mm,dev_x_mm,dev_y_mm,compensation,bored_at\n";
  const std::string first_row = plate_.Csv()
                                    .substr(header.size())
                                    .substr(0, plate_.Csv().substr(header.size()).find('\n') + 1);
  std::string million_empty = plate_.Csv() + std::string(1000000, '\n');
  std::string duplicate = plate_.Csv() + first_row;
  // Pair 1 without its second hole (the file's second row).
  std::string lonely = plate_.Csv();
  {
    const size_t a = lonely.find('\n', header.size()) + 1;
    lonely.erase(a, lonely.find('\n', a) + 1 - a);
  }
  const std::string future = FormatRfc3339(clock_.NowMs() + 86400000LL);
  const std::vector<BadFile> cases = {
      {"empty file", "", 400, 0, "header"},
      {"missing column",
       "hole,pair,nominal_x_mm,nominal_y_mm,dev_x_mm,compensation,bored_at\n"
       "a,1,0,0,0,on,2026-03-01T00:00:00Z\n",
       400, 0, "dev_y_mm"},
      {"duplicate column",
       "hole,pair,nominal_x_mm,nominal_y_mm,dev_x_mm,dev_y_mm,dev_y_mm,compensation,bored_at\n",
       400, 0, "dev_y_mm"},
      {"nan", WithCell(3, 5, "nan"), 400, 3, "dev_y_mm"},
      {"inf", WithCell(4, 4, "inf"), 400, 4, "dev_x_mm"},
      {"1e999", WithCell(5, 3, "1e999"), 400, 5, "nominal_y_mm"},
      {"invalid UTF-8", WithCell(2, 0, "P\xff\xfe"), 400, 0, "body"},
      {"a million empty rows", million_empty, 413, 10001, "row"},
      {"duplicate hole", duplicate, 422, 41, "hole"},
      {"pair without both", lonely, 422, 1, "compensation"},
      {"unknown on/off", WithCell(6, 6, "maybe"), 400, 6, "compensation"},
      {"bore time in the future", WithCell(7, 7, future), 422, 7, "bored_at"},
      {"bore time before 2000", WithCell(8, 7, "1999-12-31T23:00:00Z"), 400, 8, "bored_at"},
      {"pair not an integer", WithCell(9, 1, "1.5"), 400, 9, "pair"},
      {"deviation in um, not mm", WithCell(10, 5, "12.5"), 422, 10, "dev_y_mm"},
      {"short row", header + "a,1,0\n", 400, 1, "row"},
  };
  for (const auto& c : cases) {
    auto res = Post("/api/v1/machines/m1/plates/bad", c.body);
    ASSERT_TRUE(res) << c.what;
    EXPECT_EQ(res->status, c.status) << c.what << ": " << res->body;
    const json problem = json::parse(res->body, nullptr, false);
    ASSERT_TRUE(problem.is_object()) << c.what;
    ASSERT_TRUE(problem.contains("errors") && !problem["errors"].empty()) << c.what << res->body;
    EXPECT_EQ(problem["errors"][0]["index"], c.row) << c.what << ": " << res->body;
    EXPECT_EQ(problem["errors"][0]["field"], c.field) << c.what << ": " << res->body;
    ExpectNothingStored();
  }
  // Not CSV; an unknown axis; an axis the file does not hold.
  auto res = Post("/api/v1/machines/m1/plates/bad", plate_.Csv(), "application/json");
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 415);
  res = Post("/api/v1/machines/nope/plates/bad", plate_.Csv());
  ASSERT_TRUE(res);
  EXPECT_EQ(res->status, 404);
  ExpectNothingStored();
}

}  // namespace
}  // namespace thermocomp::testing
