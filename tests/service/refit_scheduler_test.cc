#include "service/refit_scheduler.h"

#include <fstream>

#include "tests/app_fixture.h"
#include "tests/test_util.h"

namespace thermocomp {
namespace {

class RefitSchedulerTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override {
    c.refit_after_new_runs = 3;
    c.refit_interval_min = 24 * 60;
  }
};

TEST_F(RefitSchedulerTest, FitsWhenDueAndOnlyThen) {
  VirtualMachine vm = Simulate("m1", 10);
  RefitScheduler& s = app_->scheduler();
  // No model yet: both axes with declared inputs are fitted.
  EXPECT_EQ(s.Tick(), 2);
  // Nothing new: nothing to do, however much time passes.
  EXPECT_EQ(s.Tick(), 0);
  clock_.Advance(2 * 86400000LL);
  EXPECT_EQ(s.Tick(), 0);
  // New runs arrive (a day of production holds four): refit.
  std::vector<TemperatureInput> samples;
  std::vector<ProbePointInput> points;
  SimExtras extras;
  while (vm.now_ms() + 60000 <= clock_.NowMs()) vm.Step(samples, points, &extras);
  Flush("m1", samples, points, extras);
  EXPECT_EQ(s.Tick(), 2);
  EXPECT_NE(app_->ModelGauges().find("thermocomp_fits_total 4\n"), std::string::npos);
  auto models = app_->fits().Models("m1", "Y");
  ASSERT_TRUE(models.ok());
  EXPECT_EQ(models->size(), 2u);
}

TEST_F(RefitSchedulerTest, FailedRefitNeverReplacesTheActiveModel) {
  Simulate("m1", 10);
  FitRequest good;
  auto first = app_->fits().Fit("m1", "Y", good);
  ASSERT_TRUE(first.ok());
  ASSERT_EQ(first->status, "active");
  FitRequest bad;
  bad.inputs = std::vector<std::string>{"Tenv"};
  auto second = app_->fits().Fit("m1", "Y", bad);
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(second->status, "rejected");
  auto models = app_->fits().Models("m1", "Y");
  EXPECT_EQ((*models)[0].status, "active");
  EXPECT_EQ((*models)[1].status, "rejected");
  auto comp = app_->compensation().Get("m1");
  ASSERT_TRUE(comp.ok());
  for (const auto& a : (*comp)->axes) {
    if (a.axis == "Y") {
      EXPECT_EQ(a.model_version, 1);
    }
  }
}

class ScheduledAnalysisTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override { c.analysis_policy = policy_; }
  std::string policy_ = "propose";
};

TEST_F(ScheduledAnalysisTest, ScheduledRefitProposesTheExtendedModelAsACandidate) {
  Simulate("m1", 30, 12, {HiddenEffect::kLag});
  ASSERT_EQ(app_->scheduler().Tick(), 2);
  // One analysis per refitted axis; the Y axis gets the lag of Tco.
  EXPECT_EQ(Count("SELECT COUNT(*) FROM analyses"), 2);
  auto list = app_->analyses().List("m1", "Y");
  ASSERT_TRUE(list.ok());
  ASSERT_EQ(list->size(), 1u);
  EXPECT_GE((*list)[0].effects, 1);
  ASSERT_TRUE((*list)[0].model_version);
  auto models = app_->fits().Models("m1", "Y");
  ASSERT_TRUE(models.ok());
  ASSERT_EQ(models->size(), 2u);
  EXPECT_EQ((*models)[0].status, "active");  // the scheduled fit of the declared inputs
  EXPECT_EQ((*models)[1].status, "candidate");
  EXPECT_EQ((*models)[1].version, *(*list)[0].model_version);
  // Proposing does not change what is served.
  auto comp = app_->compensation().Get("m1");
  ASSERT_TRUE(comp.ok());
  for (const auto& a : (*comp)->axes) {
    if (a.axis == "Y") {
      EXPECT_EQ(a.model_version, 1);
    }
  }
}

class ScheduledActivationTest : public ScheduledAnalysisTest {
 protected:
  void Configure(Config& c) override { c.analysis_policy = "activate"; }
};

TEST_F(ScheduledActivationTest, ActivatePolicyServesTheExtendedModel) {
  VirtualMachine vm = Simulate("m1", 30, 12, {HiddenEffect::kLag});
  ASSERT_EQ(app_->scheduler().Tick(), 2);
  auto models = app_->fits().Models("m1", "Y");
  ASSERT_TRUE(models.ok());
  ASSERT_EQ(models->size(), 2u);
  EXPECT_EQ((*models)[1].status, "active") << (*models)[1].reason;
  EXPECT_EQ((*models)[0].status, "retired");
  auto comp = app_->compensation().Get("m1");
  ASSERT_TRUE(comp.ok());
  for (const auto& a : (*comp)->axes) {
    if (a.axis != "Y") continue;
    ASSERT_TRUE(a.valid) << a.reason;
    EXPECT_EQ(a.model_version, 2);
    // Served live from the lagged archive: close to the true drift now.
    ASSERT_TRUE(vm.in_run());
    EXPECT_NEAR(a.predicted_drift_mm, vm.DriftSinceDatumY(), 0.003);
  }
  // New runs: the next scheduled refit of the declared inputs is compared
  // with the served extended model through its terms, loses, and does not
  // replace it.
  clock_.Advance(2 * 86400000LL);
  std::vector<TemperatureInput> samples;
  std::vector<ProbePointInput> points;
  SimExtras extras;
  while (vm.now_ms() + 60000 <= clock_.NowMs()) vm.Step(samples, points, &extras);
  Flush("m1", samples, points, extras);
  ASSERT_EQ(app_->scheduler().Tick(), 2);
  models = app_->fits().Models("m1", "Y");
  ASSERT_GE(models->size(), 3u);
  EXPECT_EQ((*models)[2].status, "rejected") << (*models)[2].reason;
  EXPECT_NE((*models)[2].reason.find("worse than active version 2"), std::string::npos)
      << (*models)[2].reason;
  // What stays served is an extended model: v2, or the analysis' refit of it.
  int extended_active = 0;
  for (const auto& m : *models) {
    if (m.status == "active" && m.model_json.find("\"lag\"") != std::string::npos) {
      ++extended_active;
    }
  }
  EXPECT_EQ(extended_active, 1);
}

}  // namespace
}  // namespace thermocomp

namespace thermocomp {
namespace {

class DailyRefitTest : public testing::AppFixture {
 protected:
  void Configure(Config& c) override {
    c.refit_after_new_runs = 0;
    c.refit_interval_min = 0;
    c.refit_daily_at_min = 3 * 60;  // 03:00 UTC
  }
};

TEST_F(DailyRefitTest, RefitsOnceAfterTheDailyTime) {
  // The fixture's clock stands at midnight; history ends there.
  VirtualMachine vm = Simulate("m1", 10);
  RefitScheduler& s = app_->scheduler();
  ASSERT_EQ(s.Tick(), 2);  // first models
  auto feed_until = [&](int64_t t) {
    clock_.Set(t);
    std::vector<TemperatureInput> samples;
    std::vector<ProbePointInput> points;
    SimExtras extras;
    while (vm.now_ms() + 60000 <= t) vm.Step(samples, points, &extras);
    Flush("m1", samples, points, extras);
  };
  const int64_t midnight = clock_.NowMs();
  feed_until(midnight + 150 * 60000);  // 02:30: a new run, but before the daily time
  EXPECT_EQ(s.Tick(), 0);
  feed_until(midnight + 190 * 60000);  // 03:10: due
  EXPECT_EQ(s.Tick(), 2);
  feed_until(midnight + 600 * 60000);  // 10:00: more runs, same day: not again
  EXPECT_EQ(s.Tick(), 0);
}

TEST(ConfigTest, ParsesTokensAndDailyTimeAndRejectsBadOnes) {
  auto dir = testing::TempDir();
  auto write = [&](const std::string& text) {
    std::ofstream((dir / "c.toml").string()) << text;
    return LoadConfig((dir / "c.toml").string());
  };
  auto ok = write(
      "[fit]\ndaily_at = \"02:30\"\n"
      "[[auth.tokens]]\nname = \"cell-3\"\ntoken = \"0123456789abcdef0\"\nrole = "
      "\"machine\"\nmachine = \"m3\"\n");
  ASSERT_TRUE(ok.ok()) << ok.status().ToString();
  EXPECT_EQ(ok->refit_daily_at_min, 150);
  ASSERT_EQ(ok->tokens.size(), 1u);
  EXPECT_EQ(ok->tokens[0].machine, "m3");
  EXPECT_FALSE(write("[fit]\ndaily_at = \"25:00\"\n").ok());
  EXPECT_FALSE(write("[[auth.tokens]]\nname = \"x\"\ntoken = \"short\"\nrole = \"admin\"\n").ok());
  EXPECT_FALSE(
      write("[[auth.tokens]]\nname = \"x\"\ntoken = \"0123456789abcdef0\"\nrole = \"boss\"\n")
          .ok());
  auto bad = write("[server]\nlisten = \"localhost:http\"\n");
  EXPECT_FALSE(bad.ok());
  EXPECT_NE(bad.status().message().find("listen"), std::string::npos);
  // A token's name is read by people (the audit, the pages, the OPC UA
  // user): 1 to 64 characters, no control character, one token each.
  const std::string token = "token = \"0123456789abcdef0\"\nrole = \"admin\"\n";
  const std::string two = "[[auth.tokens]]\nname = \"ops\"\n" + token +
                          "[[auth.tokens]]\nname = \"ops\"\ntoken = \"fedcba98765432100\"\n"
                          "role = \"reader\"\n";
  auto twice = write(two);
  ASSERT_FALSE(twice.ok());
  EXPECT_NE(twice.status().message().find("ops: name given to two tokens"), std::string::npos)
      << twice.status().message();
  auto control = write("[[auth.tokens]]\nname = \"a\\u0007b\"\n" + token);
  ASSERT_FALSE(control.ok());
  EXPECT_NE(control.status().message().find("control characters"), std::string::npos);
  EXPECT_FALSE(write("[[auth.tokens]]\nname = \"" + std::string(65, 'n') + "\"\n" + token).ok());
  EXPECT_FALSE(write("[[auth.tokens]]\nname = \"ad\\u00ADmin\"\n" + token).ok());
  // A space inside a name is a name.
  EXPECT_TRUE(write("[[auth.tokens]]\nname = \"line PLC\"\n" + token).ok());
  // 64 characters of two bytes each are 64 characters.
  std::string umlauts;
  for (int i = 0; i < 64; ++i) umlauts += "\u00e4";
  EXPECT_TRUE(write("[[auth.tokens]]\nname = \"" + umlauts + "\"\n" + token).ok());
  std::filesystem::remove_all(dir);
}

TEST(ConfigTest, UnknownKeysWrongTypesAndRangesStopTheStartNamingTheKey) {
  auto dir = testing::TempDir();
  auto message = [&](const std::string& text) {
    std::ofstream((dir / "c.toml").string()) << text;
    auto c = LoadConfig((dir / "c.toml").string());
    return c.ok() ? std::string("accepted") : c.status().message();
  };
  EXPECT_NE(message("[server]\nthread = 8\n")
                .find("unknown key server.thread (did you mean "
                      "server.threads?)"),
            std::string::npos);
  EXPECT_NE(message("[sevrer]\nthreads = 8\n").find("unknown key sevrer.threads"),
            std::string::npos);
  EXPECT_NE(message("[compensation]\nstale_after_s = \"5m\"\n")
                .find("compensation.stale_after_s must be an integer, not a string"),
            std::string::npos);
  EXPECT_NE(message("[fit]\nmin_r2 = \"0.9\"\n").find("fit.min_r2 must be a number"),
            std::string::npos);
  EXPECT_NE(message("[fit]\nmin_r2 = 1.5\n").find("fit.min_r2 must be within 0..1"),
            std::string::npos);
  EXPECT_NE(message("threads = 8\n").find("must be a [section]"), std::string::npos);
  EXPECT_NE(message("[dds]\nenabled = \"yes\"\n").find("dds.enabled must be true or false"),
            std::string::npos);
  EXPECT_NE(
      message("[compensation]\nplausible_min_c = 50.0\nplausible_max_c = 40.0\n").find("below"),
      std::string::npos);
  EXPECT_EQ(message("[fit]\nmin_r2 = 1\n[server]\nthreads = 8\n"), "accepted");
  // A misspelled zone stops the start (the pages would show no times).
  EXPECT_NE(message("[web]\ntime_zone = \"Europe/Berln\"\n")
                .find("web.time_zone \"Europe/Berln\" is not a time zone of the IANA database"),
            std::string::npos)
      << message("[web]\ntime_zone = \"Europe/Berln\"\n");
  EXPECT_NE(message("[web]\ntime_zone = \"../../etc/passwd\"\n").find("web.time_zone"),
            std::string::npos);
  EXPECT_EQ(message("[web]\ntime_zone = \"Europe/Berlin\"\n"), "accepted");
  EXPECT_EQ(message("[web]\ntime_zone = \"UTC\"\n"), "accepted");
  // The shipped file lists every key with its default: it loads as is.
  auto shipped = LoadConfig(testing::SourcePath("deploy/thermocomp.toml"));
  ASSERT_TRUE(shipped.ok()) << shipped.status().message();
  EXPECT_EQ(shipped->http_threads, Config{}.http_threads);
  EXPECT_EQ(shipped->busy_timeout_ms, Config{}.busy_timeout_ms);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace thermocomp
