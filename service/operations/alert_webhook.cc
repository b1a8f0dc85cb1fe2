#include "service/operations/alert_webhook.h"

#include <algorithm>
#include <set>

#include <nlohmann/json.hpp>

#include "core/log.h"
#include "core/time_format.h"

namespace thermocomp {

AlertWebhook::AlertWebhook(std::string url, AlertPost post, Options options)
    : url_(std::move(url)), post_(std::move(post)), options_(options) {}

void AlertWebhook::Start() {
  if (url_.empty() || thread_.joinable()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = false;
  }
  thread_ = std::thread([this] { Run(); });
}

void AlertWebhook::Stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  if (!queue_.empty()) {
    log::Warn("alert webhook stopped with events unsent",
              "queued=" + std::to_string(queue_.size()));
  }
}

void AlertWebhook::Enqueue(std::string json) {
  if (url_.empty()) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (queue_.size() >= options_.max_queue) {
      // The receiver has been gone long enough: the newest state matters more.
      queue_.pop_front();
      ++dropped_;
    }
    queue_.push_back(std::move(json));
  }
  wake_.notify_all();
}

uint64_t AlertWebhook::sent() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sent_;
}
uint64_t AlertWebhook::failed() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return failed_;
}
uint64_t AlertWebhook::dropped() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}
size_t AlertWebhook::queued() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return queue_.size();
}

void AlertWebhook::Run() {
  std::chrono::milliseconds backoff = options_.first_backoff;
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stop_) {
    wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
    if (stop_) break;
    const std::string event = queue_.front();
    lock.unlock();
    const Status posted = post_(url_, event);  // without the lock: Enqueue never waits
    lock.lock();
    if (posted.ok()) {
      // The front is still this event unless the queue overflowed meanwhile
      // and dropped it.
      if (!queue_.empty() && queue_.front() == event) queue_.pop_front();
      ++sent_;
      backoff = options_.first_backoff;
      continue;
    }
    ++failed_;
    log::Warn("alert webhook failed, retrying",
              "error=\"" + posted.message() + "\" retry_ms=" + std::to_string(backoff.count()));
    wake_.wait_for(lock, backoff, [this] { return stop_; });
    backoff = std::min(backoff * 2, options_.max_backoff);
  }
}

std::string AlertEventJson(const std::string& event, const Alert& alert, int64_t at_ms) {
  const nlohmann::json body = {
      {"event", event},
      {"kind", alert.kind},
      {"machine", alert.machine},
      {"axis", alert.axis.empty() ? nlohmann::json(nullptr) : nlohmann::json(alert.axis)},
      {"since", FormatRfc3339(alert.since_ms)},
      {"detail", alert.detail},
      {"at", FormatRfc3339(at_ms)}};
  return body.dump();
}

int AlertMonitor::Tick() {
  std::lock_guard<std::mutex> tick(tick_mutex_);
  const int64_t now = app_.clock().NowMs();
  std::map<std::string, Alert> current;
  for (Alert& a : EvaluateAlerts(app_)) {
    std::string key = a.Key();
    current.emplace(std::move(key), std::move(a));
  }
  int changes = 0;
  for (const auto& [key, alert] : current) {
    if (active_.count(key) > 0) continue;
    ++changes;
    log::Warn("alert raised", "kind=" + alert.kind + " machine=" + alert.machine +
                                  (alert.axis.empty() ? "" : " axis=" + alert.axis));
    if (webhook_) webhook_->Enqueue(AlertEventJson("raised", alert, now));
  }
  for (const auto& [key, alert] : active_) {
    if (current.count(key) > 0) continue;
    ++changes;
    log::Info("alert cleared", "kind=" + alert.kind + " machine=" + alert.machine +
                                   (alert.axis.empty() ? "" : " axis=" + alert.axis));
    if (webhook_) webhook_->Enqueue(AlertEventJson("cleared", alert, now));
  }
  active_ = std::move(current);
  return changes;
}

void AlertMonitor::Start(std::chrono::milliseconds period) {
  task_.Start(period, [this] { Tick(); });
}

void AlertMonitor::Stop() {
  task_.Stop();
}

}  // namespace thermocomp
