#include "server/background_work.h"

#include <chrono>

#include "api/operations/agent_get.h"
#include "api/operations/alert_post.h"

namespace thermocomp {

Status BackgroundWork::Start() {
  const Config& config = app_.config();
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
  return Status::Ok();
}

void BackgroundWork::Stop() {
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
