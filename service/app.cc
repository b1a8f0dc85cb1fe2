#include "service/app.h"

#include "core/log.h"
#include "service/applied_compensation_service.h"
#include "service/parts/plates/plate_service.h"
#include "service/parts/process/part_model_service.h"
#include "service/parts/surfaces/surface_service.h"
#include "service/parts/turning/turning_service.h"

namespace thermocomp {

App::App(const Config& config, const Clock& clock)
    : config_(config),
      clock_(clock),
      probe_temperatures_(static_cast<size_t>(config.probe_cache_points)) {}

App::~App() = default;

StatusOr<std::unique_ptr<App>> App::Open(const Config& config, const Clock& clock,
                                         std::unique_ptr<Storage> storage) {
  if (!storage) return Status::InvalidArgument("no storage");
  auto plant_time = PlantTime::Load(config.web_time_zone);
  if (!plant_time.ok()) return plant_time.status();
  std::unique_ptr<App> app(new App(config, clock));
  app->plant_time_ = *plant_time;
  app->storage_ = std::move(storage);
  Storage& d = *app->storage_;
  const Config& c = app->config_;
  ProbeTemperatureCache* cache = &app->probe_temperatures_;
  app->machines_ = std::make_unique<MachineService>(d, clock, cache);
  app->ingest_ = std::make_unique<IngestService>(d, clock, cache, &app->metrics_);
  app->machines_->SetLimits(c);
  app->ingest_->SetLimits(c);
  app->fits_ = std::make_unique<FitService>(d, clock, c, cache);
  app->analyses_ = std::make_unique<AnalysisService>(d, clock, c, cache);
  app->checks_ = std::make_unique<CheckService>(d, clock, c);
  app->feed_axes_ = std::make_unique<FeedAxisService>(d, clock, c);
  app->compensation_ = std::make_unique<CompensationService>(d, clock, c);
  app->history_ = std::make_unique<HistoryService>(d, c, cache);
  app->latest_temperatures_ = std::make_unique<LatestTemperatureService>(d, clock, c);
  app->outcomes_ = std::make_unique<OutcomeService>(d, clock, *app->history_, *app->compensation_,
                                                    app->plant_time_);
  app->scheduler_ = std::make_unique<RefitScheduler>(d, *app->fits_, clock, c, app->analyses_.get(),
                                                     app->checks_.get());
  app->thermal_errors_ = std::make_unique<ThermalErrorTableService>(d, clock, c);
  app->feed_fit_ = std::make_unique<FeedFitService>(d, clock, c);
  app->scheduler_->SetFeedFits(app->feed_fit_.get());
  app->plates_ = std::make_unique<PlateService>(d, clock, c);
  app->turning_ = std::make_unique<TurningService>(d, clock, c);
  app->part_models_ = std::make_unique<PartModelService>(d, clock, c);
  app->surfaces_ = std::make_unique<SurfaceService>(d, clock, c);
  app->applied_ = std::make_unique<AppliedCompensationService>(d, clock);
  CompensationService* compensation = app->compensation_.get();
  auto changed = [compensation](const std::string& machine) { compensation->MarkChanged(machine); };
  app->ingest_->SetListener(changed);
  app->fits_->SetListener(changed);
  app->analyses_->SetListener(changed);
  compensation->Start();
  log::Info("database open",
            "path=" + d.location() + " schema_version=" + std::to_string(d.schema_version()));
  return app;
}

std::string App::ModelGauges() {
  std::string out =
      "# HELP thermocomp_fits_total Model versions fitted and stored.\n"
      "# TYPE thermocomp_fits_total counter\n"
      "thermocomp_fits_total " +
      std::to_string(fits_->fits_stored()) + "\n";
  out +=
      "# HELP thermocomp_model_age_seconds Age of the active model per axis.\n"
      "# TYPE thermocomp_model_age_seconds gauge\n";
  const std::unique_ptr<Session> session = storage_->Open();
  ModelStore& models = session->models();
  const int64_t now = clock_.NowMs();
  std::string overdue =
      "# HELP thermocomp_column_checks_overdue Column-check requests past their due time.\n"
      "# TYPE thermocomp_column_checks_overdue gauge\n";
  for (const auto& m : session->machines().List()) {
    overdue += "thermocomp_column_checks_overdue{machine=\"" + m.name + "\"} " +
               std::to_string(CountChecks(*session, m.id, now).overdue) + "\n";
    for (const auto& a : m.axes) {
      if (auto rec = models.Active(a.id)) {
        out += "thermocomp_model_age_seconds{machine=\"" + m.name + "\",axis=\"" + a.name + "\"} " +
               std::to_string((now - rec->created_ms) / 1000) + "\n";
      }
    }
  }
  return out + overdue;
}

}  // namespace thermocomp
