// What one machine or one request may make the server hold, over real HTTP
// on a real SQLite file: events per machine and UTC day (429, nothing
// stored), the events an analysis considers, sensors per machine (400,
// nothing stored), points in one temperature history, and the overview
// read a page at a time. Bounds are asserted as counts and sizes, never as
// times or memory.
#include "tests/app_fixture.h"  // first: Eigen before httplib.h (see api/http_server.h)

#include <algorithm>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "core/time_format.h"

namespace thermocomp {
namespace {

using nlohmann::json;

constexpr int kEventsPerDay = 5;
constexpr int kAnalysisEvents = 3;
constexpr int kSensors = 8;
constexpr int kResponsePoints = 1000;
constexpr int kPageSize = 3;

class BoundsTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override {
    c.max_events_per_machine_day = kEventsPerDay;
    c.analysis_max_events = kAnalysisEvents;
    c.max_sensors_per_machine = kSensors;
    c.max_response_points = kResponsePoints;
    c.overview_page_size = kPageSize;
  }
  void SetUp() override {
    AppFixture::SetUp();
    StartHttp();
    client_ = testing::TestClient(http_->port());
  }
  httplib::Result Put(const std::string& path, const json& body) {
    return client_->Put(path, body.dump(), "application/json");
  }
  httplib::Result Post(const std::string& path, const json& body) {
    return client_->Post(path, body.dump(), "application/json");
  }
  json Get(const std::string& path, int expect = 200) {
    auto r = client_->Get(path);
    EXPECT_TRUE(r) << path;
    if (!r) return {};
    EXPECT_EQ(r->status, expect) << path << " " << r->body;
    return json::parse(r->body, nullptr, false);
  }
  // A machine with sensors T0..T{n-1} and axis Y.
  static json Machine(int sensors, int first = 0) {
    json list = json::array();
    for (int i = first; i < first + sensors; ++i) list.push_back({{"id", "T" + std::to_string(i)}});
    return {{"sensors", list}};
  }
  json Event(int64_t ts_ms, const std::string& kind = "other", const std::string& note = "") {
    return {{"ts", FormatRfc3339(ts_ms)}, {"kind", kind}, {"note", note}};
  }
  // The field the first error of a problem names.
  static std::string Field(const httplib::Result& r) {
    const json p = json::parse(r->body, nullptr, false);
    if (p.is_discarded() || !p.contains("errors") || p["errors"].empty()) return "";
    return p["errors"][0].value("field", "");
  }
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(BoundsTest, EventsBeyondTheDailyAllowanceAreRefusedWhole) {
  ASSERT_EQ(Put("/api/v1/machines/m1", Machine(2))->status, 201);
  const std::string events = "/api/v1/machines/m1/events";
  const int64_t day = testing::kT0 + 3 * 86400000LL;  // 2026-03-05T00:00:00Z
  for (int i = 0; i < kEventsPerDay; ++i) {
    auto r = Post(events, Event(day + i * 3600000LL, "other", "n" + std::to_string(i)));
    ASSERT_TRUE(r);
    ASSERT_EQ(r->status, 201) << r->body;
  }
  const int64_t audit = Count("SELECT COUNT(*) FROM audit");
  // One more that UTC day, of any kind, at its last millisecond too.
  for (const json& more : {Event(day + 86399999LL, "maintenance"), Event(day + 1, "collision")}) {
    auto r = Post(events, more);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 429) << r->body;
    EXPECT_EQ(r->get_header_value("Content-Type"), "application/problem+json");
    EXPECT_EQ(Field(r), "events") << r->body;
    EXPECT_NE(r->body.find("2026-03-05"), std::string::npos) << r->body;
  }
  EXPECT_EQ(Count("SELECT COUNT(*) FROM events"), kEventsPerDay);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM audit"), audit);  // nothing stored
  // An event sent again is a duplicate, not a new one: still answered.
  auto again = Post(events, Event(day, "other", "n0"));
  ASSERT_TRUE(again);
  EXPECT_EQ(again->status, 200) << again->body;
  // The day before and the day after have their own allowance; another
  // machine has its own.
  EXPECT_EQ(Post(events, Event(day - 1))->status, 201);
  EXPECT_EQ(Post(events, Event(day + 86400000LL))->status, 201);
  ASSERT_EQ(Put("/api/v1/machines/m2", Machine(1))->status, 201);
  EXPECT_EQ(Post("/api/v1/machines/m2/events", Event(day + 5))->status, 201);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM events"), kEventsPerDay + 3);
}

TEST_F(BoundsTest, AnAnalysisConsidersOnlyTheNewestEvents) {
  Simulate("m1", 20, 5);
  // An event on each of twelve days inside the data, each with runs on
  // either side: every one would be a candidate and a comparison.
  std::vector<int64_t> times;
  for (int d = 4; d < 16; ++d) {
    const int64_t ts = clock_.NowMs() - int64_t{20 - d} * 86400000 + 12 * 3600000LL;
    ASSERT_TRUE(app_->ingest().AddEvent("m1", {ts, "other", "test"}, "test").status.ok());
  }
  const int64_t machine_id = app_->machines().Find("m1")->id;
  {
    const std::unique_ptr<Session> session = app_->storage().Open();
    for (const EventRecord& e : session->aux().Events(machine_id)) times.push_back(e.ts_ms);
  }
  ASSERT_GT(times.size(), static_cast<size_t>(kAnalysisEvents));
  const int64_t oldest_kept = times[times.size() - kAnalysisEvents];
  auto r = Post("/api/v1/machines/m1/axes/Y/analysis", {{"policy", "off"}});
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 201) << r->body;
  const json report = json::parse(r->body);
  EXPECT_FALSE(report["event_comparisons"].empty()) << report.dump(1);
  EXPECT_LE(report["event_comparisons"].size(), static_cast<size_t>(kAnalysisEvents));
  for (const auto& c : report["event_comparisons"]) {
    const auto ts = ParseRfc3339(c["event"]["ts"].get<std::string>());
    ASSERT_TRUE(ts) << c.dump();
    EXPECT_GE(*ts, oldest_kept) << c.dump();
  }
  // The audit says how many were left out.
  EXPECT_EQ(Count("SELECT COUNT(*) FROM audit WHERE action = 'analysis' AND detail LIKE '%" +
                  std::to_string(times.size() - kAnalysisEvents) + " older event(s) left out%'"),
            1);
}

TEST_F(BoundsTest, SensorsPerMachineAreBoundedAtRegistration) {
  auto r = Put("/api/v1/machines/m1", Machine(kSensors + 1));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400) << r->body;
  EXPECT_EQ(Field(r), "sensors") << r->body;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM machines"), 0);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM sensors"), 0);

  ASSERT_EQ(Put("/api/v1/machines/m1", Machine(kSensors - 2))->status, 201);
  // The stored sensors are kept, so they count with those a PUT adds.
  r = Put("/api/v1/machines/m1", Machine(3, kSensors - 2 + 5));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400) << r->body;
  EXPECT_EQ(Field(r), "sensors") << r->body;
  EXPECT_EQ(Count("SELECT COUNT(*) FROM sensors"), kSensors - 2);
  // Up to the limit, and listing stored ones again, is fine.
  EXPECT_EQ(Put("/api/v1/machines/m1", Machine(kSensors))->status, 200);
  EXPECT_EQ(Count("SELECT COUNT(*) FROM sensors"), kSensors);
}

TEST_F(BoundsTest, OneTemperatureHistoryCarriesAtMostTheResponsePoints) {
  ASSERT_EQ(Put("/api/v1/machines/m1", Machine(kSensors))->status, 201);
  const int per_sensor = 300;  // minute samples: raw, not the hourly envelope
  std::vector<TemperatureInput> samples;
  for (int s = 0; s < kSensors; ++s) {
    for (int i = 0; i < per_sensor; ++i) {
      samples.push_back({"T" + std::to_string(s), testing::kT0 + i * 60000LL, 20.0 + 0.01 * i});
    }
  }
  ASSERT_TRUE(app_->ingest().AddTemperatures("m1", samples, "test").status.ok());
  // A few hundred events in the range: they come along, bounded as well.
  WithConnection([&](SqlConnection& db) {
    for (int i = 0; i < 50; ++i) {
      SqlStatement q(
          db, "INSERT INTO events(machine_id, ts_ms, kind, note) VALUES (1, ?, 'other', '')");
      q.Bind(1, int64_t{testing::kT0 + i * 1000LL});
      ASSERT_TRUE(q.Run().ok());
    }
  });

  const json h =
      Get("/api/v1/machines/m1/temperatures?from=" + FormatRfc3339(testing::kT0) +
          "&to=" + FormatRfc3339(testing::kT0 + per_sensor * 60000LL) + "&max_points=20000");
  ASSERT_EQ(h["sensors"].size(), static_cast<size_t>(kSensors));
  const size_t effective = h["max_points"].get<size_t>();
  EXPECT_EQ(effective, static_cast<size_t>(kResponsePoints / kSensors));
  size_t points = 0;
  for (const auto& s : h["sensors"]) {
    EXPECT_LE(s["points"].size(), effective) << s["sensor"];
    EXPECT_EQ(s["total"].get<int>(), per_sensor);
    points += s["points"].size();
  }
  EXPECT_LE(points, static_cast<size_t>(kResponsePoints));
  EXPECT_EQ(h["events"].size(), 50u);
  // Asking for fewer per sensor than the share is kept as asked.
  EXPECT_EQ(Get("/api/v1/machines/m1/temperatures?max_points=10")["max_points"], 10);
}

TEST_F(BoundsTest, ATemperatureHistoryCarriesTheNewestEventsOnly) {
  ASSERT_EQ(Put("/api/v1/machines/m1", Machine(1))->status, 201);
  const int events = static_cast<int>(kMaxEventMarks) + 200;
  WithConnection([&](SqlConnection& db) {
    ASSERT_TRUE(db.Begin().ok());
    for (int i = 0; i < events; ++i) {
      SqlStatement q(db,
                     "INSERT INTO events(machine_id, ts_ms, kind, note) VALUES (1, ?, 'other', ?)");
      q.Bind(1, int64_t{testing::kT0 + i * 60000LL}).Bind(2, std::string(500, 'n'));
      ASSERT_TRUE(q.Run().ok());
    }
    ASSERT_TRUE(db.Commit().ok());
  });
  const json h = Get("/api/v1/machines/m1/temperatures");
  ASSERT_EQ(h["events"].size(), kMaxEventMarks);
  EXPECT_EQ(h["events"].back()["ts"], FormatRfc3339(testing::kT0 + (events - 1) * 60000LL));
  EXPECT_EQ(h["events"].front()["ts"],
            FormatRfc3339(testing::kT0 + (events - static_cast<int>(kMaxEventMarks)) * 60000LL));
}

TEST_F(BoundsTest, TheOverviewIsReadAPageAtATimeInNameOrder) {
  const std::vector<std::string> names = {"m-e", "m-a", "m-d", "m-b", "m-g", "m-c", "m-f"};
  for (const auto& n : names) ASSERT_EQ(Put("/api/v1/machines/" + n, Machine(1))->status, 201);
  std::vector<std::string> sorted = names;
  std::sort(sorted.begin(), sorted.end());

  // Default page: overview_page_size machines, then `next` to the end.
  std::vector<std::string> seen;
  std::string url = "/api/v1/overview";
  int pages = 0;
  while (!url.empty() && pages < 10) {
    const json page = Get(url);
    ++pages;
    EXPECT_EQ(page["total"], names.size());
    EXPECT_LE(page["machines"].size(), static_cast<size_t>(kPageSize));
    for (const auto& m : page["machines"]) seen.push_back(m["machine"]);
    url = page["next"].is_null() ? "" : page["next"].get<std::string>();
  }
  EXPECT_EQ(pages, 3);
  EXPECT_EQ(seen, sorted);

  json page = Get("/api/v1/overview?limit=2&offset=1");
  ASSERT_EQ(page["machines"].size(), 2u);
  EXPECT_EQ(page["machines"][0]["machine"], "m-b");
  EXPECT_EQ(page["next"], "/api/v1/overview?limit=2&offset=3");
  page = Get("/api/v1/overview?limit=1000");
  EXPECT_EQ(page["machines"].size(), names.size());
  EXPECT_TRUE(page["next"].is_null());
  page = Get("/api/v1/overview?offset=7");
  EXPECT_TRUE(page["machines"].empty());
  EXPECT_TRUE(page["next"].is_null());
  EXPECT_EQ(page["total"], names.size());

  for (const auto& [query, field] :
       {std::pair{"limit=0", "limit"}, std::pair{"limit=1001", "limit"},
        std::pair{"limit=abc", "limit"}, std::pair{"limit=-1", "limit"},
        std::pair{"limit=1.5", "limit"}, std::pair{"limit=", "limit"},
        std::pair{"limit=99999999999999999999", "limit"}, std::pair{"offset=-1", "offset"},
        std::pair{"offset=x", "offset"}, std::pair{"offset=1e3", "offset"}}) {
    auto r = client_->Get(std::string("/api/v1/overview?") + query);
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 400) << query << " " << r->body;
    EXPECT_EQ(Field(r), field) << query << " " << r->body;
  }
}

}  // namespace
}  // namespace thermocomp
