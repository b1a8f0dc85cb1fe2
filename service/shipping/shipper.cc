#include "service/shipping/shipper.h"

#include <algorithm>
#include <cstdio>

#include "core/log.h"

namespace thermocomp {
namespace {

int64_t WallMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

void Line(std::string& out, const char* name, const char* type, const char* help,
          const std::string& value) {
  out += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " " + type + "\n" +
         name + " " + value + "\n";
}

}  // namespace

std::string ShippingBoard::Render() const {
  if (!enabled.load()) return "";
  const int64_t now_ms = WallMs();
  std::string out;
  const int64_t oldest = oldest_stored_ms.load();
  const int64_t backlog = backlog_rows.load();
  char lag[32];
  std::snprintf(lag, sizeof lag, "%.3f",
                backlog > 0 && oldest > 0 ? std::max<int64_t>(0, now_ms - oldest) / 1000.0 : 0.0);
  Line(out, "thermocomp_shipping_backlog_rows", "gauge",
       "Rows stored on this line and not yet applied at the centre.", std::to_string(backlog));
  Line(out, "thermocomp_shipping_lag_seconds", "gauge",
       "Age of the oldest row not yet applied at the centre (0: none waiting).", lag);
  Line(out, "thermocomp_shipping_centre_up", "gauge",
       "1 when the last pass reached the centre, else 0.", centre_up.load() ? "1" : "0");
  // The Shipper marks a refusal with applied_seq = -1 (no number is).
  Line(out, "thermocomp_shipping_refused", "gauge",
       "1 when the centre's numbers contradict this archive's and shipping stopped until it is"
       " switched off and on.",
       applied_seq.load() < 0 ? "1" : "0");
  Line(out, "thermocomp_shipping_applied_seq", "gauge",
       "The highest outbox sequence number the centre has applied.",
       std::to_string(std::max<int64_t>(0, applied_seq.load())));
  Line(out, "thermocomp_shipping_last_success_timestamp_seconds", "gauge",
       "When a batch was last applied at the centre (0: never since start).",
       std::to_string(last_success_ms.load() / 1000));
  Line(out, "thermocomp_shipping_rows_total", "counter", "Rows applied at the centre.",
       std::to_string(rows_total.load()));
  Line(out, "thermocomp_shipping_batches_total", "counter", "Batches applied at the centre.",
       std::to_string(batches_total.load()));
  Line(out, "thermocomp_shipping_passes_total", "counter",
       "Passes of the shipper over the outbox, counted when done (retries waiting out a pause"
       " are not passes).",
       std::to_string(passes_total.load()));
  Line(out, "thermocomp_shipping_failures_total", "counter",
       "Passes that failed (centre unreachable, a batch refused).",
       std::to_string(failures_total.load()));
  return out;
}

Shipper::Shipper(Outbox& outbox, Connect connect, ShippingBoard& board, Options options)
    : outbox_(outbox), connect_(std::move(connect)), board_(board), options_(std::move(options)) {
  board_.enabled = true;
}

void Shipper::Start() {
  task_.Start(std::chrono::milliseconds(options_.interval_ms), [this] { Pass(); });
}

Status Shipper::ShipBatch(int64_t* shipped) {
  *shipped = 0;
  OutboxBacklog backlog;
  if (Status s = outbox_.Backlog(&backlog); !s.ok()) return s;
  board_.backlog_rows = backlog.rows;
  board_.oldest_stored_ms = backlog.oldest_stored_ms;
  if (backlog.rows == 0 && synced_) return Status::Ok();
  if (!centre_) {
    auto centre = connect_();
    if (!centre.ok()) {
      board_.centre_up = false;
      return centre.status();
    }
    centre_ = std::move(centre).value();
    synced_ = false;
  }
  auto drop = [&](Status s) {
    centre_.reset();
    synced_ = false;
    board_.centre_up = false;
    return s;
  };
  if (!synced_) {
    int64_t acknowledged = 0;
    if (Status s = outbox_.Acknowledged(options_.plant, &acknowledged); !s.ok()) return s;
    if (acknowledged < 0) {
      board_.applied_seq = -1;  // the board's mark of a refusal
      return Status::FailedPrecondition(
          "centre: shipping of plant " + options_.plant +
          " was refused (see the first such line of the log); it stays so until shipping is"
          " switched off and on (docs/operations.md, A centre for several plants)");
    }
    if (Status s = centre_->Applied(options_.plant, &applied_); !s.ok()) return drop(s);
    board_.centre_up = true;
    board_.applied_seq = applied_;
    std::string refusal;
    if (applied_ < acknowledged) {
      refusal = "the centre holds rows of plant " + options_.plant + " up to " +
                std::to_string(applied_) + " but had acknowledged up to " +
                std::to_string(acknowledged) +
                ": it lost rows (a failover to a standby that was behind, a restore); switch"
                " shipping off and on to ship this archive again";
    } else if (applied_ > backlog.last_seq) {
      refusal = "the centre holds rows of plant " + options_.plant + " up to " +
                std::to_string(applied_) + " but this archive has numbered only " +
                std::to_string(backlog.last_seq) +
                ": another archive (or one restored from a backup) uses this plant's name;"
                " give it a centre.plant of its own";
    }
    if (!refusal.empty()) {
      // Kept in the archive: once this archive has numbered as many rows,
      // the numbers alone would no longer tell.
      if (Status s = outbox_.Refuse(options_.plant); !s.ok()) return s;
      board_.applied_seq = -1;
      return drop(Status::FailedPrecondition("centre: " + refusal));
    }
    // What the centre applied before the line could forget it.
    if (Status s = outbox_.Acknowledge(options_.plant, applied_); !s.ok()) return s;
    synced_ = true;
  }
  std::vector<ShippedRow> rows;
  if (Status s = outbox_.Read(applied_, options_.batch_rows, &rows); !s.ok()) return s;
  if (rows.empty()) {
    board_.backlog_rows = 0;
    board_.oldest_stored_ms = 0;
    return Status::Ok();
  }
  int64_t applied = applied_;
  if (Status s = centre_->Apply(options_.plant, rows, &applied); !s.ok()) return drop(s);
  board_.centre_up = true;
  for (const ShippedRow& row : rows) *shipped += row.seq > applied_ && row.seq <= applied ? 1 : 0;
  applied_ = applied;
  board_.applied_seq = applied_;
  if (Status s = outbox_.Acknowledge(options_.plant, applied_); !s.ok()) return s;
  board_.rows_total += static_cast<uint64_t>(*shipped);
  board_.batches_total += 1;
  board_.last_success_ms = WallMs();
  board_.backlog_rows = std::max<int64_t>(0, backlog.rows - static_cast<int64_t>(rows.size()));
  if (board_.backlog_rows == 0) board_.oldest_stored_ms = 0;
  return Status::Ok();
}

void Shipper::Pass() {
  const auto now = std::chrono::steady_clock::now();
  if (now < retry_at_) return;
  ShipWhileFull(now + options_.max_pass);
  // Counted once done: a pass counted after a row was stored has seen it.
  board_.passes_total += 1;
}

void Shipper::ShipWhileFull(std::chrono::steady_clock::time_point until) {
  while (std::chrono::steady_clock::now() < until) {
    int64_t shipped = 0;
    Status s = ShipBatch(&shipped);
    if (!s.ok()) {
      std::string message = s.message();  // libpq's messages span lines
      for (char& ch : message) ch = ch == '\n' || ch == '\t' ? ' ' : ch;
      board_.failures_total += 1;
      board_.SetError(message);
      pause_ =
          std::clamp(pause_ * 2, std::chrono::milliseconds(1000), std::chrono::milliseconds(30000));
      retry_at_ = std::chrono::steady_clock::now() + pause_;
      if (message != last_logged_) {  // once per new trouble, not every retry
        log::Warn("shipping: pass failed; the outbox keeps the rows",
                  "plant=" + options_.plant + " error=\"" + message + "\"");
        last_logged_ = message;
      }
      return;
    }
    if (!last_logged_.empty()) {
      log::Info("shipping: centre reached again", "plant=" + options_.plant);
      last_logged_.clear();
    }
    pause_ = std::chrono::milliseconds(0);
    if (shipped < options_.batch_rows) return;
  }
}

}  // namespace thermocomp
