// BackgroundWork: what the server runs beside its requests, each on a
// thread of its own: the refit scheduler, scheduled backups
// (backup.dir), the retention of raw samples (retention.raw_days), and
// the alert monitor with its webhook (alerts.webhook_url), and one poller
// per [[mtconnect.sources]] (docs/mtconnect.md), and the shipper to the
// centre ([centre] url; docs/architecture.md, "Plant to centre"). A
// read-only server (server.read_only) runs none of them. Start() starts
// them in that order; Stop() (also the destructor) stops them in reverse,
// before the App they read goes away.
#pragma once

#include <memory>
#include <vector>

#include "core/status.h"
#include "service/app.h"
#include "service/mtconnect/mtconnect_source.h"
#include "service/operations/alert_webhook.h"
#include "service/operations/backup_schedule.h"
#include "service/operations/retention.h"
#include "service/shipping/shipper.h"

namespace thermocomp {

class BackgroundWork {
 public:
  explicit BackgroundWork(App& app) : app_(app) {}
  ~BackgroundWork() { Stop(); }
  BackgroundWork(const BackgroundWork&) = delete;
  BackgroundWork& operator=(const BackgroundWork&) = delete;

  // InvalidArgument (nothing started) for a webhook URL the client cannot
  // send to.
  Status Start();
  void Stop();

 private:
  App& app_;
  bool scheduler_started_ = false;
  std::unique_ptr<BackupSchedule> backups_;
  std::unique_ptr<Retention> retention_;
  std::unique_ptr<AlertWebhook> webhook_;
  std::unique_ptr<AlertMonitor> monitor_;
  std::vector<std::unique_ptr<MtconnectSource>> mtconnect_;
  std::unique_ptr<Outbox> outbox_;
  std::unique_ptr<Shipper> shipper_;

  Status StartShipping();
};

}  // namespace thermocomp
