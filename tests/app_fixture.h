// A real App on a fresh SQLite file in a temporary directory (or a fresh
// PostgreSQL database: tests/test_database.h), with a manual clock,
// optionally serving HTTP on an ephemeral loopback port.
#pragma once

#include <filesystem>
#include <memory>
#include <random>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "api/http_server.h"
#include "server/open_app.h"
#include "service/app.h"
#include "sim/virtual_machine.h"
#include "storage/postgresql/pg_storage.h"
#include "storage/sqlite/sqlite_storage.h"
#include "tests/test_database.h"

namespace thermocomp::testing {

inline std::filesystem::path TempDir() {
  std::random_device rd;
  auto dir = std::filesystem::temp_directory_path() /
             ("thermocomp-test-" + std::to_string(rd()) + std::to_string(rd()));
  std::filesystem::create_directories(dir);
  return dir;
}

// A client of a server under test. cpp-httplib's default read timeout is
// 5 s; an effect analysis of a month of data took 8.7-11.5 s under ASan
// with two tests in parallel on 2 cores. 300 s is a margin of 25x over
// that: the tests wait for the answer, they do not time the server.
inline constexpr int kClientReadTimeoutS = 300;
inline std::unique_ptr<httplib::Client> TestClient(int port) {
  auto client = std::make_unique<httplib::Client>("127.0.0.1", port);
  client->set_read_timeout(kClientReadTimeoutS, 0);
  client->set_write_timeout(kClientReadTimeoutS, 0);
  return client;
}

// 2026-03-02T00:00:00Z
constexpr int64_t kT0 = 1772409600000;

class AppFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = TempDir();
    config_.db_path = (dir_ / "thermocomp.db").string();
    if (OnPostgresql()) {
      ASSERT_NO_FATAL_FAILURE(postgres_.Create());
      config_.db_path = postgres_.url();
    }
    config_.synchronous = "normal";
    config_.http_threads = 8;
    Configure(config_);
    auto app = OpenApp(config_, clock_);
    ASSERT_TRUE(app.ok()) << app.status().ToString();
    app_ = std::move(app).value();
  }
  virtual void Configure(Config&) {}
  void TearDown() override {
    if (http_) http_->Stop();
    http_.reset();
    app_.reset();
    std::filesystem::remove_all(dir_);
  }
  void StartHttp() {
    http_ = std::make_unique<api::HttpServer>(*app_);
    ASSERT_TRUE(http_->Start("127.0.0.1", 0).ok());
  }
  // Registers a simulated machine and feeds it `days` of history ending at
  // the clock's time (temperatures, signals, events, probe points), with
  // the given undeclared effects. Returns the virtual machine for the truth.
  VirtualMachine Simulate(const std::string& name, int days, uint64_t seed = 3,
                          std::set<HiddenEffect> hidden = {}) {
    FieldErrors errors;
    EXPECT_TRUE(app_->machines().Register(VirtualMachine::Definition(name), "test", &errors).ok());
    SimOptions o;
    o.machine = name;
    o.seed = seed;
    o.start_ms = clock_.NowMs() - int64_t{days} * 86400000;
    o.hidden = std::move(hidden);
    VirtualMachine vm(o);
    std::vector<TemperatureInput> s;
    std::vector<ProbePointInput> p;
    SimExtras extras;
    while (vm.now_ms() + 60000 <= clock_.NowMs()) {
      vm.Step(s, p, &extras);
      if (s.size() >= 7 * 600) Flush(name, s, p, extras);
    }
    Flush(name, s, p, extras);
    return vm;
  }
  void Flush(const std::string& name, std::vector<TemperatureInput>& s,
             std::vector<ProbePointInput>& p, SimExtras& extras) {
    if (!s.empty()) {
      ASSERT_TRUE(app_->ingest().AddTemperatures(name, s, "test").status.ok());
    }
    if (!extras.signals.empty()) {
      ASSERT_TRUE(app_->ingest().AddSignals(name, extras.signals, "test").status.ok());
    }
    for (const auto& e : extras.events) {
      ASSERT_TRUE(app_->ingest().AddEvent(name, e, "test").status.ok());
    }
    if (!p.empty()) {
      ASSERT_TRUE(app_->ingest().AddProbePoints(name, p, "test").status.ok());
    }
    s.clear();
    p.clear();
    extras = SimExtras{};
  }
  // Serves `model_json` as version 1 of axis `axis_id` without a fit, so a
  // test knows the law exactly.
  void InsertActiveModel(int64_t axis_id, const std::string& model_json) {
    {
      const std::unique_ptr<Session> session = app_->storage().Open();
      auto version = session->models().Insert(axis_id, {0, "active", "test", 0, model_json, "{}"});
      ASSERT_TRUE(version.ok() && *version == 1);
    }
    for (const auto& m : app_->machines().List()) app_->compensation().MarkChanged(m.name);
  }
  int64_t Count(const std::string& sql) {
    int64_t count = -1;
    WithConnection([&](SqlConnection& db) {
      SqlStatement q(db, sql);
      if (q.Step()) count = q.Int(0);
    });
    return count;
  }
  // SQL no store offers, on the app's connection, whichever the backend.
  void WithConnection(const std::function<void(SqlConnection&)>& fn) {
    if (OnPostgresql()) {
      static_cast<PgStorage&>(app_->storage()).WithConnection(fn);
    } else {
      Sqlite().WithConnection([&](Database& db) { fn(db); });
    }
  }
  // The app's SQLite archive, for tests of what only SQLite has (they skip
  // themselves on PostgreSQL).
  SqliteStorage& Sqlite() { return static_cast<SqliteStorage&>(app_->storage()); }

  std::filesystem::path dir_;
  TestPostgresDatabase postgres_;  // dropped after the app has closed it
  Config config_;
  ManualClock clock_{kT0 + 14 * 86400000LL};
  std::unique_ptr<App> app_;
  std::unique_ptr<api::HttpServer> http_;
};

}  // namespace thermocomp::testing
