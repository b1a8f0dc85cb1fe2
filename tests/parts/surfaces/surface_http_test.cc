// Surfaces over real HTTP on a real SQLite file: a simulated part measured,
// mirrored through the corrected program the API exports, re-measured
// (the file's nominal columns carrying the corrected points) and reported
// against the ORIGINAL nominal; the report's before/after agrees with the
// truth; the allowance flag; the exports parse; every bad file refused
// with the row and field named and nothing stored.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <cmath>
#include <sstream>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "api/parts/cmm_csv.h"
#include "sim/parts/surface_sim.h"

namespace thermocomp {
namespace {

using nlohmann::json;

const std::string kParts = "/api/v1/machines/m1/surfaces";
const std::string kPart = kParts + "/blade-7";
const std::string kPost = kPart + "/measurements";

// The corrected program as the API exports it (CSV), read back.
std::vector<SurfacePoint> ReadProgram(const std::string& csv) {
  std::vector<SurfacePoint> out;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "point,x_mm,y_mm,z_mm,i,j,k");
  while (std::getline(in, line)) {
    SurfacePoint p;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream cells(line);
    cells >> p.id >> p.x_mm >> p.y_mm >> p.z_mm >> p.i >> p.j >> p.k;
    out.push_back(p);
  }
  return out;
}

class SurfaceHttpTest : public testing::AppFixture {
 protected:
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = testing::TestClient(http_->port());
    MachineRecord m;
    m.name = "m1";
    m.sensors = {{0, "S1", "spindle", 0.3}};
    m.axes = {{0, "X", 0.0, {"S1"}, 0.03}};
    FieldErrors errors;
    ASSERT_TRUE(app_->machines().Register(m, "test", &errors).ok());
  }
  httplib::Result Post(const std::string& csv, const std::string& path = kPost) {
    return client_->Post(path, csv, "text/csv");
  }
  json PostOk(const std::string& csv) {
    auto r = Post(csv);
    EXPECT_TRUE(r);
    if (!r) return json();
    EXPECT_EQ(r->status, 201) << r->body.substr(0, 400);
    return json::parse(r->body, nullptr, false);
  }
  // The program to make the next part from (after the latest iteration).
  std::vector<SurfacePoint> Program() {
    auto r = client_->Get(kPart + "/corrected");
    EXPECT_TRUE(r && r->status == 200);
    return r ? ReadProgram(r->body) : std::vector<SurfacePoint>{};
  }
  // Whether the server routes this page's query parameters (iteration,
  // format); the parameter table is the server's (api/http_server.cc).
  bool QueryParametersRouted() {
    auto r = client_->Get(kPart + "?format=json");
    return r && r->body.find("unknown query parameter") == std::string::npos;
  }
  // POST `csv`, expect `status` naming `field` at `row`, and nothing stored.
  void ExpectRefused(const std::string& csv, int status, size_t row, const std::string& field) {
    SCOPED_TRACE(csv.substr(0, 100));
    const int64_t iterations = Count("SELECT COUNT(*) FROM surface_iterations");
    const int64_t parts = Count("SELECT COUNT(*) FROM surface_parts");
    const int64_t nominals = Count("SELECT COUNT(*) FROM surface_nominals");
    auto r = Post(csv);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, status) << r->body.substr(0, 400);
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
    const json p = json::parse(r->body, nullptr, false);
    ASSERT_TRUE(p.contains("errors")) << r->body.substr(0, 400);
    const json& e = p["errors"][0];
    EXPECT_EQ(e.value("field", ""), field) << r->body.substr(0, 400);
    EXPECT_EQ(e.value("index", size_t{999999}), row) << r->body.substr(0, 400);
    EXPECT_EQ(Count("SELECT COUNT(*) FROM surface_iterations"), iterations);
    EXPECT_EQ(Count("SELECT COUNT(*) FROM surface_parts"), parts);
    EXPECT_EQ(Count("SELECT COUNT(*) FROM surface_nominals"), nominals);
  }
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(SurfaceHttpTest, MirrorCutsMeanDeviationAsTheTruthAllowsAgainstTheOriginal) {
  SurfaceSimOptions o;
  SurfaceSim sim(o);
  const auto& nominal = sim.nominal();
  const SurfaceSimPart first = sim.MachineAndMeasure(nominal);
  const json j0 = PostOk(SurfaceSim::Csv(nominal, first, false, true));
  EXPECT_EQ(j0["iteration"], 0);
  EXPECT_EQ(j0["stats"]["points"], 625);
  EXPECT_EQ(j0["nominal_columns"], "original");
  EXPECT_FALSE(j0["allowance_not_uniform"].get<bool>());
  double truth_before = 0;
  for (size_t p = 0; p < nominal.size(); ++p) {
    truth_before += std::abs(first.error_mm[p] + first.noise_mm[p]);
  }
  truth_before /= static_cast<double>(nominal.size());
  EXPECT_NEAR(j0["stats"]["mean_abs_mm"].get<double>(), truth_before, 2e-6);

  // The next program, as exported, is nominal − d·n.
  const std::vector<SurfacePoint> program = Program();
  ASSERT_EQ(program.size(), nominal.size());
  EXPECT_EQ(program[0].id, nominal[0].id);
  const double d0 = first.error_mm[0] + first.noise_mm[0];
  EXPECT_NEAR(program[0].z_mm, nominal[0].z_mm - d0 * nominal[0].k, 2e-6);

  // The part made from it, measured by a CMM program whose nominal
  // columns are the corrected points: still measured against the original.
  const SurfaceSimPart second = sim.MachineAndMeasure(program);
  const json j1 = PostOk(SurfaceSim::Csv(program, second, false, true));
  EXPECT_EQ(j1["iteration"], 1);
  EXPECT_EQ(j1["nominal_columns"], "program");
  double truth_after = 0;
  for (size_t p = 0; p < nominal.size(); ++p) {
    truth_after +=
        std::abs(second.error_mm[p] + second.noise_mm[p] - (first.error_mm[p] + first.noise_mm[p]));
  }
  truth_after /= static_cast<double>(nominal.size());
  const double after = j1["stats"]["mean_abs_mm"].get<double>();
  // Exactly the truth of this draw (to the CSV's 6 decimals) ...
  EXPECT_NEAR(after, truth_after, 2e-5);
  // ... and the share the truth allows: only the noise of two measurements
  // remains (2σ/√π, ±15 %).
  EXPECT_NEAR(after, sim.ExpectedMeanAbsAfterMirror(), 0.15 * sim.ExpectedMeanAbsAfterMirror());
  EXPECT_NEAR(j1["before"]["mean_abs_mm"].get<double>(), truth_before, 2e-6);
  EXPECT_LT(j1["mean_abs_change_share"].get<double>(), -0.8);
  EXPECT_FALSE(j1["allowance_not_uniform"].get<bool>()) << j1.dump();
  EXPECT_TRUE(j1["repeat"]["repeated"].get<bool>());

  // The same re-measurement given as dev_mm along the file's (corrected)
  // nominal: the same deviations against the original.
  const json j2 = PostOk(SurfaceSim::Csv(program, second, true, false));
  EXPECT_EQ(j2["iteration"], 2);
  EXPECT_NEAR(j2["stats"]["mean_abs_mm"].get<double>(), after, 2e-5);
  EXPECT_NEAR(j2["stats"]["max_negative_mm"].get<double>(),
              j1["stats"]["max_negative_mm"].get<double>(), 2e-5);

  auto list = client_->Get(kParts);
  ASSERT_TRUE(list && list->status == 200);
  const json parts = json::parse(list->body)["parts"];
  ASSERT_EQ(parts.size(), 1u);
  EXPECT_EQ(parts[0]["iterations"], 3);
  EXPECT_NEAR(parts[0]["latest_mean_abs_mm"].get<double>(), after, 2e-5);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM audit WHERE action = 'surface-measurement'"), 3);

  // The latest program, named after the part and the program's number.
  auto csv = client_->Get(kPart + "/corrected");
  ASSERT_TRUE(csv && csv->status == 200);
  EXPECT_EQ(csv->get_header_value("Content-Type"), "text/csv");
  EXPECT_NE(csv->get_header_value("Content-Disposition").find("blade-7-program-3.csv"),
            std::string::npos);
  EXPECT_EQ(client_->Get(kParts + "/nope")->status, 404);
  EXPECT_EQ(client_->Get(kParts + "/nope/corrected")->status, 404);
  EXPECT_EQ(client_->Get("/api/v1/machines/nope/surfaces")->status, 404);
}

TEST_F(SurfaceHttpTest, ReportFormatsAndDownloadsPerIteration) {
  if (!QueryParametersRouted()) {
    GTEST_SKIP() << "the server does not yet route ?format and ?iteration on surfaces";
  }
  SurfaceSim sim({});
  const SurfaceSimPart first = sim.MachineAndMeasure(sim.nominal());
  PostOk(SurfaceSim::Csv(sim.nominal(), first, false, false));
  const std::vector<SurfacePoint> program = Program();
  PostOk(SurfaceSim::Csv(program, sim.MachineAndMeasure(program), false, false));
  auto r = client_->Get(kPart + "?format=json");
  ASSERT_TRUE(r && r->status == 200);
  const json report = json::parse(r->body);
  ASSERT_EQ(report["iterations"].size(), 2u);
  EXPECT_EQ(report["points"].size(), 625u);
  EXPECT_EQ(report["iterations"][1]["d_mm"].size(), 625u);
  auto md = client_->Get(kPart + "?format=markdown");
  ASSERT_TRUE(md && md->status == 200);
  EXPECT_NE(md->body.find("| 1 |"), std::string::npos);
  EXPECT_NE(md->body.find("Before → after"), std::string::npos);
  auto html = client_->Get(kPart + "?format=html");
  ASSERT_TRUE(html && html->status == 200);
  EXPECT_NE(html->body.find("<table>"), std::string::npos);
  // The program after iteration 0 is the one the second part was made from.
  auto again = client_->Get(kPart + "/corrected?iteration=0&format=csv");
  ASSERT_TRUE(again && again->status == 200);
  EXPECT_NEAR(ReadProgram(again->body)[5].z_mm, program[5].z_mm, 1e-9);
  // Downloads: the program after iteration 1, as CSV and DXF.
  auto dxf = client_->Get(kPart + "/corrected?iteration=1&format=dxf");
  ASSERT_TRUE(dxf && dxf->status == 200);
  EXPECT_EQ(dxf->get_header_value("Content-Type"), "image/vnd.dxf");
  EXPECT_NE(dxf->get_header_value("Content-Disposition").find("blade-7-program-2.dxf"),
            std::string::npos);
  size_t points = 0;
  for (size_t at = 0; (at = dxf->body.find("\n0\nPOINT\n", at)) != std::string::npos; ++at) {
    ++points;
  }
  EXPECT_EQ(points, 625u);
  EXPECT_EQ(dxf->body.substr(dxf->body.size() - 6), "0\nEOF\n");
  EXPECT_EQ(client_->Get(kPart + "/corrected?iteration=2")->status, 404);
  EXPECT_EQ(client_->Get(kPart + "/corrected?iteration=x")->status, 400);
  EXPECT_EQ(client_->Get(kPart + "/corrected?format=iges")->status, 400);
  EXPECT_EQ(client_->Get(kPart + "?format=pdf")->status, 400);
}

// Two corrections: the third part is made from corrected(2) = nominal −
// (d(0) + d(1))·n and still measured against the original: what is left is
// its noise minus the second part's, exactly as the truth says.
TEST_F(SurfaceHttpTest, SecondCorrectionIsMeasuredAgainstTheOriginal) {
  SurfaceSim sim({});
  const auto& nominal = sim.nominal();
  const SurfaceSimPart first = sim.MachineAndMeasure(nominal);
  PostOk(SurfaceSim::Csv(nominal, first, false, false));
  const std::vector<SurfacePoint> program1 = Program();
  const SurfaceSimPart second = sim.MachineAndMeasure(program1);
  PostOk(SurfaceSim::Csv(program1, second, false, false));
  const std::vector<SurfacePoint> program2 = Program();
  ASSERT_EQ(program2.size(), nominal.size());
  const SurfaceSimPart third = sim.MachineAndMeasure(program2);
  const json j2 = PostOk(SurfaceSim::Csv(program2, third, true, false));
  EXPECT_EQ(j2["iteration"], 2);
  EXPECT_EQ(j2["nominal_columns"], "program");
  auto r = client_->Get(kPart);
  ASSERT_TRUE(r && r->status == 200);
  const json report = json::parse(r->body);
  ASSERT_EQ(report["iterations"].size(), 3u);
  const json& d0 = report["iterations"][0]["d_mm"];
  const json& d1 = report["iterations"][1]["d_mm"];
  const json& d2 = report["iterations"][2]["d_mm"];
  double worst = 0;
  for (size_t p = 0; p < nominal.size(); ++p) {
    // corrected(2) moved each point by −(d0 + d1) along the original normal.
    const double shift = (program2[p].x_mm - nominal[p].x_mm) * nominal[p].i +
                         (program2[p].y_mm - nominal[p].y_mm) * nominal[p].j +
                         (program2[p].z_mm - nominal[p].z_mm) * nominal[p].k;
    EXPECT_NEAR(shift, -(d0[p].get<double>() + d1[p].get<double>()), 1e-5);
    // d2 = e + ε2 − d0 − d1 = ε2 − ε1 (the systematic part repeats).
    worst =
        std::max(worst, std::abs(d2[p].get<double>() - (third.noise_mm[p] - second.noise_mm[p])));
  }
  EXPECT_LT(worst, 2e-5);
  EXPECT_NEAR(j2["stats"]["mean_abs_mm"].get<double>(), sim.ExpectedMeanAbsAfterMirror(),
              0.15 * sim.ExpectedMeanAbsAfterMirror());
}

TEST_F(SurfaceHttpTest, NonUniformAllowanceIsFlagged) {
  SurfaceSimOptions o;
  o.allowance_variation = 0.6;  // stock 0.12 .. 0.48 mm, different on every part
  SurfaceSim sim(o);
  const SurfaceSimPart first = sim.MachineAndMeasure(sim.nominal());
  const json j0 = PostOk(SurfaceSim::Csv(sim.nominal(), first, false, true));
  EXPECT_TRUE(j0["allowance_not_uniform"].get<bool>());
  EXPECT_FALSE(j0["allowance"]["uniform"].get<bool>());
  const std::vector<SurfacePoint> program = Program();
  const SurfaceSimPart second = sim.MachineAndMeasure(program);
  // Without the allowance column: the repeat rule alone flags it.
  const json j1 = PostOk(SurfaceSim::Csv(program, second, false, false));
  EXPECT_TRUE(j1["allowance"].is_null());
  EXPECT_FALSE(j1["repeat"]["repeated"].get<bool>()) << j1["repeat"].dump();
  EXPECT_TRUE(j1["allowance_not_uniform"].get<bool>());
  auto list = client_->Get(kParts);
  EXPECT_TRUE(json::parse(list->body)["parts"][0]["latest_flagged"].get<bool>());
}

TEST_F(SurfaceHttpTest, BadFilesAreRefusedAndStoreNothing) {
  SurfaceSim sim({});
  const SurfaceSimPart first = sim.MachineAndMeasure(sim.nominal());
  const std::string good = SurfaceSim::Csv(sim.nominal(), first, false, false);
  const std::string header = good.substr(0, good.find('\n') + 1);
  ExpectRefused("", 400, 0, "header");
  ExpectRefused("point,x_mm,y_mm,z_mm,i,j,k\nP,1,2,3,0,0,1\n", 400, 0, "dev_mm");
  ExpectRefused(header + "P1,1,2,3,0,0,1,1,2,nan\n", 400, 1, "mz_mm");
  ExpectRefused(header + "P1,1,2,3,0,0,1,1,2,3\nP2,1,2,3,0,0,0,1,2,3\n", 400, 2, "i");
  ExpectRefused(header + "P1,1,2,3,0,0,1,1,2,3\nP1,1,2,3,0,0,1,1,2,3\n", 400, 2, "point");
  ExpectRefused(header + "P\xC3\x28,1,2,3,0,0,1,1,2,3\n", 400, 1, "row");
  ExpectRefused(header + std::string(1000000, '\n'), 413, api::kMaxCmmLines + 1, "row");
  ExpectRefused(header, 422, 1, "row");
  auto r = client_->Post(kPost, good, "application/json");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 415);
  EXPECT_EQ(Post(good, "/api/v1/machines/nope/surfaces/p/measurements")->status, 404);

  // Once the part exists, a re-measurement must be the original's points.
  PostOk(good);
  const std::string short_file = good.substr(0, good.rfind('\n', good.size() - 2) + 1);
  ExpectRefused(short_file, 422, 0, "point");
  std::string unknown = good;
  const size_t at = unknown.find("P013_");
  unknown.replace(at, 4, "Q013");
  ExpectRefused(unknown, 422, 301, "point");
  EXPECT_EQ(Count("SELECT COUNT(*) FROM surface_iterations"), 1);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM surface_nominals"), 625);
}

TEST_F(SurfaceHttpTest, TenThousandPointsFitTheBodyLimit) {
  SurfaceSimOptions o;
  o.nx = 100;
  o.ny = 100;
  SurfaceSim sim(o);
  const SurfaceSimPart first = sim.MachineAndMeasure(sim.nominal());
  const std::string csv = SurfaceSim::Csv(sim.nominal(), first, false, true);
  EXPECT_LT(csv.size(), config_.max_body_bytes / 10);
  const json j0 = PostOk(csv);
  EXPECT_EQ(j0["stats"]["points"], 10000);
}

}  // namespace
}  // namespace thermocomp
