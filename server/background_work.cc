#include "server/background_work.h"

#include <chrono>

#include "api/operations/agent_get.h"
#include "api/operations/alert_post.h"
#include "core/log.h"
#include "storage/postgresql/pg_centre.h"
#include "storage/postgresql/pg_connection.h"
#include "storage/sql/shipping/outbox_store.h"
#include "storage/sqlite/sqlite_storage.h"

namespace thermocomp {

Status BackgroundWork::Start() {
  const Config& config = app_.config();
  if (config.read_only) return Status::Ok();
  if (!api::ValidAlertUrl(config.alert_webhook_url)) {
    return Status::InvalidArgument(
        "alerts.webhook_url: not an http:// or https:// URL with a host");
  }
  app_.scheduler().Start(std::chrono::seconds(60));
  scheduler_started_ = true;
  if (!config.backup_dir.empty()) {
    BackupSchedule::Options options;
    options.dir = config.backup_dir;
    options.every_h = config.backup_every_h;
    options.keep = config.backup_keep;
    backups_ = std::make_unique<BackupSchedule>(app_.storage(), app_.clock(), options);
    backups_->Start();  // checks at once, then every minute; backs up when due
  }
  if (config.retention_raw_days > 0) {
    Retention::Options options;
    options.raw_days = config.retention_raw_days;
    options.keep_around_h = config.retention_keep_around_h;
    options.every_h = config.retention_every_h;
    retention_ = std::make_unique<Retention>(app_.storage(), app_.clock(), options);
    retention_->Start();
  }
  // The conditions are evaluated for the webhook only; GET /api/v1/alerts
  // and /metrics evaluate them when asked.
  if (!config.alert_webhook_url.empty()) {
    webhook_ = std::make_unique<AlertWebhook>(config.alert_webhook_url, api::PostAlert);
    webhook_->Start();
    monitor_ = std::make_unique<AlertMonitor>(app_, webhook_.get());
    monitor_->Start(std::chrono::seconds(30));
  }
  for (const MtconnectSourceConfig& source : config.mtconnect_sources) {
    mtconnect_.push_back(std::make_unique<MtconnectSource>(
        source,
        [](const std::string& url, const std::string& path) {
          return api::GetFromAgent(url, path);
        },
        app_.ingest(), app_.storage(), app_.clock(), &app_.mtconnect_board()));
    mtconnect_.back()->Start();
  }
  return StartShipping();
}

Status BackgroundWork::StartShipping() {
  const Config& config = app_.config();
  auto* sqlite = dynamic_cast<SqliteStorage*>(&app_.storage());
  if (sqlite == nullptr) {
    if (config.centre_url.empty()) return Status::Ok();
    return Status::InvalidArgument(
        "centre.url: a line server ships from an SQLite archive; an archive in PostgreSQL"
        " reaches another site by PostgreSQL's replication (docs/operations.md)");
  }
  WithSqlConnection with = [sqlite](const std::function<void(SqlConnection&)>& fn) {
    sqlite->WithConnection([&](Database& db) { fn(db); });
  };
  ShippingSwitch outcome;
  Status status;
  with([&](SqlConnection& db) {
    status =
        config.centre_url.empty() ? DisableShipping(db, &outcome) : EnableShipping(db, &outcome);
  });
  if (!status.ok()) return status;
  if (config.centre_url.empty()) {
    if (outcome.dropped_rows > 0) {
      log::Warn("shipping off (no centre.url): rows not shipped were forgotten",
                "rows=" + std::to_string(outcome.dropped_rows));
    }
    return Status::Ok();
  }
  if (outcome.snapshot) {
    log::Info("shipping on: the archive's rows are in the outbox",
              "rows=" + std::to_string(outcome.snapshot_rows));
  }
  outbox_ = std::make_unique<SqlOutbox>(with);
  Shipper::Options options;
  options.plant = config.centre_plant;
  options.batch_rows = config.centre_batch_rows;
  options.interval_ms = config.centre_interval_ms;
  const std::string url = config.centre_url;
  shipper_ = std::make_unique<Shipper>(
      *outbox_, [url] { return OpenCentre(url); }, app_.shipping_board(), options);
  shipper_->Start();
  log::Info("shipping to the centre",
            "plant=" + config.centre_plant + " centre=\"" + WithoutPassword(url) + "\"");
  return Status::Ok();
}

void BackgroundWork::Stop() {
  if (shipper_) shipper_->Stop();
  for (auto& source : mtconnect_) source->Stop();
  mtconnect_.clear();
  if (monitor_) monitor_->Stop();
  if (webhook_) webhook_->Stop();
  if (retention_) retention_->Stop();
  if (backups_) backups_->Stop();
  if (scheduler_started_) app_.scheduler().Stop();
  scheduler_started_ = false;
}

}  // namespace thermocomp
