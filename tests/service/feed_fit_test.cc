// Feed-axis refits through the service on a real SQLite file
// (docs/model.md §14): a simulated ball-screw axis (sim/screw_axis.h)
// arrives the way real data does (its sensors' temperatures through
// IngestService, its laser checks through CheckService), and the refit
// fits the physical, neural and regression types on the older checks,
// scores them on the newest third, and keeps a good model against bad
// checks. The neural type never serves a value outside its range unguarded.
#include <cmath>
#include <random>

#include "reports/feed_fit_report_codec.h"
#include "reports/feed_fit_report_text.h"
#include "service/feed_axis/feed_fit_service.h"
#include "service/feed_axis/feed_model.h"
#include "service/feed_axis/screw_type.h"
#include "sim/screw_axis.h"
#include "storage/feed_model_store.h"
#include "tests/app_fixture.h"

namespace thermocomp {
namespace {

// What the laser reads besides the thermal error: the screw's cold pitch
// error, the same in every check (the reference check takes it out).
double PitchErrorUm(double position_mm) {
  return 4.0 * std::sin(position_mm / 170.0);
}

class FeedFitTest : public testing::AppFixture {
 protected:
  // A machine with axis X and the sensors of `axis`, read unfiltered (the
  // samples arrive at the checks' times only).
  void Register(const ScrewAxis& axis) {
    MachineRecord m;
    m.name = "m1";
    for (const ScrewSensor& s : axis.sensors) m.sensors.push_back({0, s.name, "screw", 1.0});
    m.axes.push_back({0, "X", 0, {}, 0.1, std::nullopt, std::nullopt});
    FieldErrors errors;
    ASSERT_TRUE(app_->machines().Register(m, "test", &errors).ok());
    axis_id_ = app_->machines().Find("m1")->axes[0].id;
  }

  void ConfigureScrew(const ScrewAxis& axis, const std::string& extra = "") {
    nlohmann::json sensors = nlohmann::json::array();
    for (const ScrewSensor& s : axis.sensors) {
      sensors.push_back({{"name", s.name}, {"x_mm", s.x_mm}, {"reference_c", s.reference_c}});
    }
    nlohmann::json j = {{"arrangement", BearingArrangementName(axis.arrangement)},
                        {"bearing_distance_mm", axis.bearing_distance_mm},
                        {"zero_mm", axis.zero_mm},
                        {"direction", axis.direction},
                        {"sensors", sensors}};
    if (axis.arrangement == BearingArrangement::kPreloaded) j["stiffness_ratio"] = 0.25;
    if (!extra.empty()) j.update(nlohmann::json::parse(extra));
    const std::unique_ptr<Session> session = app_->storage().Open();
    ASSERT_TRUE(session->feeds().PutConfig(axis_id_, j.dump(), clock_.NowMs()).ok());
  }

  // One check at `ts_ms`: the sensors' temperatures a second before, then
  // the laser's runs (two each way, ±0.5 µm of reversal about the mean).
  void AddCheck(const ScrewAxis& axis, int64_t ts_ms, const std::vector<double>& temperature_c,
                const std::vector<double>& position_mm, const std::vector<double>& error_um) {
    std::vector<TemperatureInput> samples;
    for (size_t s = 0; s < axis.sensors.size(); ++s) {
      samples.push_back({axis.sensors[s].name, ts_ms - 1000, temperature_c[s]});
    }
    ASSERT_TRUE(app_->ingest().AddTemperatures("m1", samples, "test").status.ok());
    PositioningInput in;
    in.axis = "X";
    in.ts_ms = ts_ms;
    in.data.targets_mm = position_mm;
    for (int direction : {+1, -1, +1, -1}) {
      PositioningRun run;
      run.direction = direction;
      for (size_t k = 0; k < position_mm.size(); ++k) {
        run.deviations_um.push_back(error_um[k] + PitchErrorUm(position_mm[k]) + 0.5 * direction);
      }
      in.data.runs.push_back(run);
    }
    bool created = false;
    auto report = app_->checks().AddPositioningCheck("m1", in, "test", &created);
    ASSERT_TRUE(report.ok()) << report.status().message();
    ASSERT_TRUE(created);
  }

  // The simulated axis' checks, the first (cold) four days before now.
  int64_t FeedSimulation(const ScrewSimRecording& rec) {
    const int64_t start = clock_.NowMs() - 4 * 86400000LL;
    for (size_t i = 0; i < rec.checks.size(); ++i) {
      const int64_t ts = start + static_cast<int64_t>(rec.check_hour[i] * 3600000.0) + 60000;
      AddCheck(rec.axis, ts, rec.checks[i].temperature_c, rec.checks[i].position_mm,
               rec.checks[i].error_um);
    }
    return start;
  }

  FeedFitService& Service() { return app_->feed_fit(); }

  const FeedTypeResult* TypeOf(const FeedFitReport& r, const std::string& type) {
    for (const auto& t : r.types)
      if (t.type == type) return &t;
    return nullptr;
  }

  std::optional<FeedModelRecord> Active() {
    const std::unique_ptr<Session> session = app_->storage().Open();
    return session->feeds().Active(axis_id_);
  }
  std::vector<FeedModelRecord> Models() {
    const std::unique_ptr<Session> session = app_->storage().Open();
    return session->feeds().List(axis_id_);
  }

  int64_t axis_id_ = 0;
};

TEST_F(FeedFitTest, ThePhysicalModelIsIdentifiedAndRemovesTheHeldOutErrorOfTheSimulatedAxis) {
  ScrewSimOptions o;
  o.seed = 1;
  const ScrewSimRecording rec = SimulateScrewAxis(o);
  Register(rec.axis);
  ConfigureScrew(rec.axis);
  FeedSimulation(rec);

  auto report = Service().Fit("m1", "X", "test");
  ASSERT_TRUE(report.ok()) << report.status().message();
  // A check every 3 h for three days besides the cold one: the newest
  // third held out (the third day's).
  const size_t n = rec.checks.size() - 1, held = (n + 2) / 3;
  ASSERT_GE(n, 20u);
  EXPECT_EQ(report->training_check_ids.size(), n - held);
  EXPECT_EQ(report->held_out_check_ids.size(), held);
  EXPECT_TRUE(report->skipped.empty());
  const FeedTypeResult* screw = TypeOf(*report, "screw");
  ASSERT_NE(screw, nullptr);
  ASSERT_TRUE(screw->fitted) << screw->error;
  ASSERT_TRUE(screw->parameters.alpha_um_per_m_k);
  EXPECT_NEAR(*screw->parameters.alpha_um_per_m_k, rec.true_alpha_um_per_m_k,
              0.02 * rec.true_alpha_um_per_m_k);
  EXPECT_GT(*screw->parameters.alpha_se, 0.0);
  EXPECT_GE(screw->held_out.reduction, 0.9);
  EXPECT_GT(screw->held_out.max_before_um, 20.0);
  // Before and after on each held-out check.
  ASSERT_EQ(screw->held_out.checks.size(), held);
  for (const FeedCheckScore& s : screw->held_out.checks) {
    EXPECT_GT(s.max_before_um, s.max_after_um) << "check " << s.check_id;
    EXPECT_GT(s.rms_before_um, s.rms_after_um) << "check " << s.check_id;
    EXPECT_EQ(s.invalid_targets, 0);
  }
  // Every type was fitted and scored on the same checks.
  for (const char* type : {"neural", "regression"}) {
    const FeedTypeResult* t = TypeOf(*report, type);
    ASSERT_NE(t, nullptr);
    ASSERT_TRUE(t->fitted) << type << ": " << t->error;
    EXPECT_EQ(t->held_out.checks.size(), held);
    EXPECT_GT(t->version, 0);
  }
  std::printf("held-out max %.1f um: screw leaves %.2f, neural %.2f, regression %.2f\n",
              screw->held_out.max_before_um, screw->held_out.max_after_um,
              TypeOf(*report, "neural")->held_out.max_after_um,
              TypeOf(*report, "regression")->held_out.max_after_um);
  // The challenger is accepted and served; one model active.
  EXPECT_TRUE(report->accepted) << report->decision;
  EXPECT_FALSE(report->champion);
  auto active = Active();
  ASSERT_TRUE(active);
  EXPECT_EQ(active->version, report->active_version);
  EXPECT_EQ(active->type, report->challenger);
  EXPECT_EQ(Models().size(), 3u);
  // The interpolation bound at each held-out check (nine sensors).
  ASSERT_EQ(report->sensors.interpolation_bound.size(), held);
  for (const auto& b : report->sensors.interpolation_bound) {
    ASSERT_TRUE(b.bound_um);
    EXPECT_GE(*b.bound_um, 0.0);
  }
  // The stored report reads back as it was returned.
  auto stored = FeedFitReportFromJson(nlohmann::json::parse(active->report_json));
  ASSERT_TRUE(stored.ok()) << stored.status().message();
  EXPECT_EQ(FeedFitReportToJson(*stored), FeedFitReportToJson(*report));
  EXPECT_EQ(Count("SELECT COUNT(*) FROM audit WHERE action = 'feed-fit'"), 1);
  // And for people: every held-out check in the physical type's table.
  const std::string md = FeedFitReportMarkdown(*report);
  for (int64_t id : report->held_out_check_ids) {
    EXPECT_NE(md.find("| " + std::to_string(id) + " | "), std::string::npos) << id;
  }
  EXPECT_NE(md.find("α "), std::string::npos);
}

TEST_F(FeedFitTest, GarbageHeldOutChecksDoNotReplaceTheActiveModel) {
  ScrewSimOptions o;
  o.seed = 2;
  const ScrewSimRecording rec = SimulateScrewAxis(o);
  Register(rec.axis);
  ConfigureScrew(rec.axis);
  FeedSimulation(rec);
  auto first = Service().Fit("m1", "X", "test");
  ASSERT_TRUE(first.ok()) << first.status().message();
  ASSERT_TRUE(first->accepted);
  const int served = first->active_version;

  // Twelve newer checks that measured nothing real: the newest third of 36
  // is all of them.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> garbage(-150.0, 150.0);
  for (int i = 0; i < 12; ++i) {
    const ScrewCheck& like = rec.checks[5 + i];
    std::vector<double> error;
    for (size_t k = 0; k < like.position_mm.size(); ++k) error.push_back(garbage(rng));
    AddCheck(rec.axis, clock_.NowMs() - 3600000LL * (12 - i), like.temperature_c, like.position_mm,
             error);
  }
  auto second = Service().Fit("m1", "X", "test");
  ASSERT_TRUE(second.ok()) << second.status().message();
  EXPECT_EQ(second->held_out_check_ids.size(), 12u);
  EXPECT_FALSE(second->accepted) << second->decision;
  ASSERT_TRUE(second->champion);
  EXPECT_EQ(second->champion->version, served);
  ASSERT_TRUE(second->champion->held_out);
  EXPECT_EQ(second->active_version, served);
  auto active = Active();
  ASSERT_TRUE(active);
  EXPECT_EQ(active->version, served);
  for (const auto& t : second->types) {
    if (t.fitted) {
      EXPECT_NE(t.status, "active") << t.type;
    }
  }
}

TEST_F(FeedFitTest, ANeuralModelNeverServesAnInputOutsideItsRangeUnguarded) {
  ScrewSimOptions o;
  o.seed = 5;
  const ScrewSimRecording rec = SimulateScrewAxis(o);
  Register(rec.axis);
  ConfigureScrew(rec.axis);
  FeedSimulation(rec);
  auto report = Service().Fit("m1", "X", "test");
  ASSERT_TRUE(report.ok()) << report.status().message();
  const FeedTypeResult* neural = TypeOf(*report, "neural");
  ASSERT_TRUE(neural && neural->fitted);
  std::optional<FeedModelRecord> stored;
  for (const auto& m : Models())
    if (m.type == "neural") stored = m;
  ASSERT_TRUE(stored);
  nlohmann::json j = nlohmann::json::parse(stored->model_json);
  const FeedModelType* type = FindFeedModelType("neural");
  ASSERT_NE(type, nullptr);
  auto with_fallback = type->FromJson(rec.axis, j, nullptr);
  ASSERT_TRUE(with_fallback.ok()) << with_fallback.status().message();
  j["fallback"] = nullptr;
  auto alone = type->FromJson(rec.axis, j, nullptr);
  ASSERT_TRUE(alone.ok()) << alone.status().message();

  // The screw 25 K warmer than any check; a position beyond the travel;
  // a sensor missing.
  FeedTemperatures hot, usual;
  for (size_t s = 0; s < rec.axis.sensors.size(); ++s) {
    hot[rec.axis.sensors[s].name] = 65.0;
    usual[rec.axis.sensors[s].name] = rec.checks[4].temperature_c[s];
  }
  FeedTemperatures missing = usual;
  missing.erase(rec.axis.sensors[3].name);
  const std::vector<double> positions = {100, 500, 1000};
  // Outside the range: the physical model's value, marked, or nothing.
  struct Case {
    const FeedTemperatures* t;
    std::vector<double> x;
    std::string names;
  };
  for (const Case& c :
       {Case{&hot, positions, rec.axis.sensors[0].name}, Case{&usual, {5000.0}, "position_mm"}}) {
    for (const FeedPrediction& p : (*with_fallback)->Predict(*c.t, c.x)) {
      EXPECT_TRUE(p.valid) << p.reason;
      EXPECT_EQ(p.fallback, "screw");
      EXPECT_NE(p.reason.find(c.names), std::string::npos) << p.reason;
      EXPECT_TRUE(std::isfinite(p.error_um));
    }
    for (const FeedPrediction& p : (*alone)->Predict(*c.t, c.x)) {
      EXPECT_FALSE(p.valid);
      EXPECT_TRUE(p.fallback.empty());
      EXPECT_NE(p.reason.find(c.names), std::string::npos) << p.reason;
    }
  }
  // A screw sensor missing: the physical model cannot stand in either.
  for (const auto* model : {&*with_fallback, &*alone}) {
    for (const FeedPrediction& p : (*model)->Predict(missing, positions)) {
      EXPECT_FALSE(p.valid);
      EXPECT_NE(p.reason.find(rec.axis.sensors[3].name), std::string::npos) << p.reason;
    }
  }
  // Inside its range it serves itself.
  for (const FeedPrediction& p : (*alone)->Predict(usual, positions)) {
    EXPECT_TRUE(p.valid) << p.reason;
    EXPECT_TRUE(p.fallback.empty());
  }
}

// A preloaded screw (L = 1000 mm, a = 1/6, α = 10) measured without noise at
// ten thermal states besides the cold one: the service recovers both.
TEST_F(FeedFitTest, NoiseFreeChecksGiveAlphaAndTheStiffnessRatioExactly) {
  ScrewAxis truth;
  truth.arrangement = BearingArrangement::kPreloaded;
  truth.bearing_distance_mm = 1000;
  truth.alpha_um_per_m_k = 10;
  truth.stiffness_ratio = 1.0 / 6.0;
  for (int i = 0; i < 5; ++i) truth.sensors.push_back({"S" + std::to_string(i), 250.0 * i, 20.0});
  Register(truth);
  ConfigureScrew(truth);
  std::vector<double> targets;
  for (double x = 0; x <= 1000; x += 50) targets.push_back(x);
  const int64_t start = clock_.NowMs() - 2 * 86400000LL;
  for (int state = 0; state <= 9; ++state) {
    std::vector<double> t;
    for (const ScrewSensor& s : truth.sensors) {
      const double u = s.x_mm / truth.bearing_distance_mm;
      t.push_back(20.0 + (state == 0 ? 0.0
                                     : 0.5 + 0.15 * state + 0.6 * state * std::sin(3.14159 * u) +
                                           (state % 3) * u * 2.0));
    }
    auto rise = ScrewRise(truth, t);
    ASSERT_TRUE(rise.ok());
    std::vector<double> error;
    error.reserve(targets.size());
    for (double x : targets) error.push_back(ScrewErrorUm(truth, *rise, x));
    AddCheck(truth, start + state * 3600000LL, t, targets, error);
  }
  auto report = Service().Fit("m1", "X", "test");
  ASSERT_TRUE(report.ok()) << report.status().message();
  const FeedTypeResult* screw = TypeOf(*report, "screw");
  ASSERT_TRUE(screw && screw->fitted) << (screw ? screw->error : "");
  EXPECT_NEAR(*screw->parameters.alpha_um_per_m_k, 10.000, 0.0005);
  ASSERT_TRUE(screw->parameters.stiffness_ratio);
  EXPECT_NEAR(*screw->parameters.stiffness_ratio, 0.1667, 0.00005);
  EXPECT_LT(screw->held_out.max_after_um, 1e-6);
  EXPECT_TRUE(report->accepted);
}

TEST_F(FeedFitTest, AStuckSensorIsDroppedAndItsCostStated) {
  ScrewSimOptions o;
  o.seed = 4;
  ScrewSimRecording rec = SimulateScrewAxis(o);
  for (auto& c : rec.checks) c.temperature_c[4] = 21.3;  // the middle sensor stuck
  Register(rec.axis);
  ConfigureScrew(rec.axis);
  FeedSimulation(rec);
  auto report = Service().Fit("m1", "X", "test");
  ASSERT_TRUE(report.ok()) << report.status().message();
  ASSERT_EQ(report->sensors.dropped.size(), 1u);
  EXPECT_EQ(report->sensors.dropped[0].name, rec.axis.sensors[4].name);
  EXPECT_NE(report->sensors.dropped[0].why.find("stuck"), std::string::npos);
  ASSERT_TRUE(report->sensors.held_out_max_with_um);
  ASSERT_TRUE(report->sensors.held_out_max_without_um);
  EXPECT_NE(report->sensors.cost.find(rec.axis.sensors[4].name), std::string::npos);
  // Without the stuck sensor the physical model still removes most of it.
  EXPECT_GE(TypeOf(*report, "screw")->held_out.reduction, 0.9);
  EXPECT_LT(*report->sensors.held_out_max_without_um, *report->sensors.held_out_max_with_um);
}

TEST_F(FeedFitTest, TheSchedulerRefitsWhenANewPositioningCheckArrives) {
  ScrewSimOptions o;
  o.seed = 3;
  const ScrewSimRecording rec = SimulateScrewAxis(o);
  Register(rec.axis);
  ConfigureScrew(rec.axis, R"({"types": ["screw", "regression"]})");
  FeedSimulation(rec);
  EXPECT_EQ(app_->scheduler().Tick(), 1);
  EXPECT_EQ(Models().size(), 2u);
  EXPECT_EQ(app_->scheduler().Tick(), 0);  // nothing new
  const ScrewCheck& like = rec.checks.back();
  AddCheck(rec.axis, clock_.NowMs() - 3600000LL, like.temperature_c, like.position_mm,
           like.error_um);
  EXPECT_EQ(app_->scheduler().Tick(), 1);
  EXPECT_EQ(Models().size(), 4u);
  EXPECT_EQ(app_->scheduler().Tick(), 0);
}

TEST_F(FeedFitTest, TooFewChecksAreA422AndStoreNothing) {
  ScrewSimOptions o;
  o.hours = 6;  // the cold check and two more
  const ScrewSimRecording rec = SimulateScrewAxis(o);
  Register(rec.axis);
  ConfigureScrew(rec.axis);
  FeedSimulation(rec);
  auto report = Service().Fit("m1", "X", "test");
  EXPECT_EQ(report.status().code(), Status::Code::kUnprocessable);
  EXPECT_NE(report.status().message().find("too few positioning checks"), std::string::npos);
  EXPECT_TRUE(Models().empty());
  // An axis without a screw configuration says so.
  EXPECT_EQ(Service().Fit("m1", "Y", "test").status().code(), Status::Code::kNotFound);
}

}  // namespace
}  // namespace thermocomp
