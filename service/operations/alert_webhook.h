// AlertWebhook: tells a receiver (alerts.webhook_url) when a condition is
// raised or cleared, as a JSON POST, from its own thread. Events wait in a
// bounded queue (the oldest dropped beyond it, counted); a failed POST is
// retried with a doubling backoff until it succeeds or Stop(), so a
// receiver that is down receives the events once it is up again, in order.
// Enqueue never waits for the network: a dead or slow receiver costs the
// server nothing but the thread that waits on it.
//
// AlertMonitor: evaluates the conditions (alerts.h) every period and sends
// each change to the webhook: "raised" for a new key, "cleared" for one
// gone. Tick() does one pass (tests); Start/Stop run it on a thread.
//
// The HTTP client is the caller's (api/operations/alert_post.h): service/
// knows no HTTP.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "core/periodic_task.h"
#include "core/status.h"
#include "service/app.h"
#include "service/operations/alerts.h"

namespace thermocomp {

// POSTs `json` to `url`; OK only when the receiver answered 2xx. May block
// (the webhook's thread calls it), bounded by its own timeouts.
using AlertPost = std::function<Status(const std::string& url, const std::string& json)>;

class AlertWebhook {
 public:
  struct Options {
    size_t max_queue = 1000;
    std::chrono::milliseconds first_backoff{500};
    std::chrono::milliseconds max_backoff{60000};
  };
  // An empty `url` sends nothing (Enqueue drops every event).
  AlertWebhook(std::string url, AlertPost post, Options options);
  AlertWebhook(std::string url, AlertPost post)
      : AlertWebhook(std::move(url), std::move(post), Options{}) {}
  ~AlertWebhook() { Stop(); }
  AlertWebhook(const AlertWebhook&) = delete;
  AlertWebhook& operator=(const AlertWebhook&) = delete;

  void Start();
  // Ends the thread; events still queued are dropped (logged).
  void Stop();
  // Queues one event's JSON; never blocks on the receiver.
  void Enqueue(std::string json);

  uint64_t sent() const;
  uint64_t failed() const;  // POSTs that did not succeed (each retried)
  uint64_t dropped() const;
  size_t queued() const;

 private:
  void Run();

  const std::string url_;
  const AlertPost post_;
  const Options options_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::string> queue_;
  uint64_t sent_ = 0, failed_ = 0, dropped_ = 0;
  bool stop_ = false;
  std::thread thread_;
};

// The webhook's JSON for one change: {"event": "raised"|"cleared", "kind",
// "machine", "axis" (null for a machine's condition), "since", "detail",
// "at"} (times RFC 3339 UTC).
std::string AlertEventJson(const std::string& event, const Alert& alert, int64_t at_ms);

class AlertMonitor {
 public:
  // `webhook` may be null (conditions are tracked, nothing is sent).
  AlertMonitor(App& app, AlertWebhook* webhook) : app_(app), webhook_(webhook) {}
  ~AlertMonitor() { Stop(); }
  AlertMonitor(const AlertMonitor&) = delete;
  AlertMonitor& operator=(const AlertMonitor&) = delete;

  // One evaluation; returns the changes it sent (raised plus cleared).
  int Tick();
  void Start(std::chrono::milliseconds period);
  void Stop();

 private:
  App& app_;
  AlertWebhook* webhook_;
  std::mutex tick_mutex_;
  std::map<std::string, Alert> active_;  // by Alert::Key()
  PeriodicTask task_;                    // last: stopped before the members it uses go
};

}  // namespace thermocomp
