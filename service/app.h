// App: the wiring of one thermocomp instance: the database, the services
// and the scheduler, built from a Config. Sources (HTTP, import, DDS) and
// sinks talk to the services, never to storage directly.
#pragma once

#include <memory>

#include "core/clock.h"
#include "core/plant_time.h"
#include "service/analysis_service.h"
#include "service/check_service.h"
#include "service/compensation_service.h"
#include "service/config.h"
#include "service/feed_axis/feed_axis_service.h"
#include "service/feed_axis/feed_fit_service.h"
#include "service/feed_axis/thermal_error_table.h"
#include "service/fit_service.h"
#include "service/history_service.h"
#include "service/ingest_service.h"
#include "service/latest_temperatures.h"
#include "service/machine_service.h"
#include "service/metrics.h"
#include "service/mtconnect/mtconnect_board.h"
#include "service/shipping/shipping_board.h"
#include "service/outcome/outcome_service.h"
#include "service/probe_temperature_cache.h"
#include "service/refit_scheduler.h"
#include "storage/storage.h"

namespace thermocomp {

// The parts' services (service/parts/*/), declared only: a face includes the
// one it calls, so a change to one part test rebuilds its own callers.
class PlateService;
class TurningService;
class PartModelService;
class SurfaceService;
// What the controls applied (service/applied_compensation_service.h).
class AppliedCompensationService;

class App {
 public:
  // The services over `storage` (the backend is chosen by the caller:
  // server/open_app.h).
  static StatusOr<std::unique_ptr<App>> Open(const Config& config, const Clock& clock,
                                             std::unique_ptr<Storage> storage);

  ~App();  // in app.cc, where the parts' services are complete
  App(const App&) = delete;
  App& operator=(const App&) = delete;

  const Config& config() const { return config_; }
  const Clock& clock() const { return clock_; }
  // How reports and texts for people write times (web.time_zone).
  const PlantTime& plant_time() const { return plant_time_; }
  Storage& storage() { return *storage_; }
  MachineService& machines() { return *machines_; }
  IngestService& ingest() { return *ingest_; }
  FitService& fits() { return *fits_; }
  AnalysisService& analyses() { return *analyses_; }
  CheckService& checks() { return *checks_; }
  FeedAxisService& feed_axes() { return *feed_axes_; }
  CompensationService& compensation() { return *compensation_; }
  HistoryService& history() { return *history_; }
  LatestTemperatureService& latest_temperatures() { return *latest_temperatures_; }
  OutcomeService& outcomes() { return *outcomes_; }
  RefitScheduler& scheduler() { return *scheduler_; }
  ThermalErrorTableService& thermal_errors() { return *thermal_errors_; }
  FeedFitService& feed_fit() { return *feed_fit_; }
  // Parts (docs/model.md §15).
  PlateService& plates() { return *plates_; }
  TurningService& turning() { return *turning_; }
  PartModelService& part_models() { return *part_models_; }
  SurfaceService& surfaces() { return *surfaces_; }
  AppliedCompensationService& applied() { return *applied_; }
  Metrics& metrics() { return metrics_; }
  // What the MTConnect sources last did (server/background_work.cc runs them).
  MtconnectBoard& mtconnect_board() { return mtconnect_board_; }
  // How shipping to the centre stands (server/background_work.cc runs it).
  ShippingBoard& shipping_board() { return shipping_board_; }
  // /metrics lines the services own: fits stored, model age per axis.
  std::string ModelGauges();

 private:
  App(const Config& config, const Clock& clock);
  Config config_;
  const Clock& clock_;
  std::unique_ptr<Storage> storage_;
  std::unique_ptr<MachineService> machines_;
  std::unique_ptr<IngestService> ingest_;
  std::unique_ptr<FitService> fits_;
  std::unique_ptr<AnalysisService> analyses_;
  std::unique_ptr<CheckService> checks_;
  std::unique_ptr<FeedAxisService> feed_axes_;
  std::unique_ptr<CompensationService> compensation_;
  std::unique_ptr<HistoryService> history_;
  std::unique_ptr<LatestTemperatureService> latest_temperatures_;
  PlantTime plant_time_;
  std::unique_ptr<OutcomeService> outcomes_;
  std::unique_ptr<RefitScheduler> scheduler_;
  std::unique_ptr<ThermalErrorTableService> thermal_errors_;
  std::unique_ptr<FeedFitService> feed_fit_;
  std::unique_ptr<PlateService> plates_;
  std::unique_ptr<TurningService> turning_;
  std::unique_ptr<PartModelService> part_models_;
  std::unique_ptr<SurfaceService> surfaces_;
  std::unique_ptr<AppliedCompensationService> applied_;
  Metrics metrics_;
  MtconnectBoard mtconnect_board_;
  ShippingBoard shipping_board_;
  ProbeTemperatureCache probe_temperatures_;
};

}  // namespace thermocomp
