// Shipper: ships the line's outbox to the centre (storage/shipping.h) on
// a thread of its own. Each pass reads a batch after what the centre has
// applied, applies it there in one transaction and then forgets it on the
// line; a pass that fails (the centre down, the network gone) leaves the
// outbox as it was and is tried again, after a pause that doubles up to
// 30 s. After a restart of either side it asks the centre where it stands
// and goes on from there, so a batch shipped but not forgotten is skipped,
// not applied twice. The line's work never waits for the centre: the
// outbox is written in the line's own transactions.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "core/periodic_task.h"
#include "core/status.h"
#include "service/shipping/shipping_board.h"
#include "storage/shipping.h"

namespace thermocomp {

class Shipper {
 public:
  struct Options {
    std::string plant;
    int batch_rows = 5000;
    int interval_ms = 1000;
    // Work of one pass before Stop() is looked at again.
    std::chrono::milliseconds max_pass{2000};
  };
  using Connect = std::function<StatusOr<std::unique_ptr<Centre>>()>;

  Shipper(Outbox& outbox, Connect connect, ShippingBoard& board, Options options);
  ~Shipper() { Stop(); }
  Shipper(const Shipper&) = delete;
  Shipper& operator=(const Shipper&) = delete;

  void Start();
  void Stop() { task_.Stop(); }

  // One batch: the thread's step, for tests. *shipped: rows applied.
  Status ShipBatch(int64_t* shipped);

 private:
  void Pass();
  void ShipWhileFull(std::chrono::steady_clock::time_point until);

  Outbox& outbox_;
  Connect connect_;
  ShippingBoard& board_;
  Options options_;
  std::unique_ptr<Centre> centre_;
  bool synced_ = false;  // applied_ is the centre's
  int64_t applied_ = 0;
  std::chrono::steady_clock::time_point retry_at_{};
  std::chrono::milliseconds pause_{0};
  std::string last_logged_;
  PeriodicTask task_;
};

}  // namespace thermocomp
