// LiveSimulation: simulated machines as live peers of a running server.
// Each minute every machine sends what it measured (over HTTP or DDS),
// takes the Y compensation the server serves and applies it to its own
// drift, and the difference is printed: the error parts would have with
// compensation on against off.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/ingest_inputs.h"
#include "sim/virtual_machine.h"

namespace thermocomp {

// How a simulated machine talks to the server.
class MachineLink {
 public:
  virtual ~MachineLink() = default;
  virtual void Send(const std::string& machine, const std::vector<TemperatureInput>& samples,
                    const std::vector<ProbePointInput>& points) = 0;
  // Auxiliary signals (spindle speed); links without a signal channel drop them.
  virtual void SendSignals(const std::string& /*machine*/, const std::vector<SignalInput>& /*s*/) {}
  // The valid Y offset the server serves now (mm), if any.
  virtual std::optional<double> OffsetY(const std::string& machine) = 0;
  // Returns once the server has what was sent (before the process ends).
  virtual void Flush() {}
};

std::unique_ptr<MachineLink> HttpLink(const std::string& url);
std::unique_ptr<MachineLink> DdsLink(uint32_t domain = 0);

struct LiveOptions {
  std::vector<std::string> machines;
  uint64_t seed = 1;
  int history_days = 14;    // replayed silently, so the state matches `demo`
  int64_t max_minutes = 0;  // simulated minutes to run (a round each); 0: until stopped
  // Simulated minutes per wall minute. Above 1 the machines run ahead of
  // the clock (the server takes timestamps up to a day ahead), at most 23 h.
  double speed = 1.0;
  // Undeclared effects per machine, as in the history `demo` made.
  std::map<std::string, std::set<HiddenEffect>> hidden;
  // Sensor faults per machine, their onsets in Unix ms.
  std::map<std::string, std::vector<InjectedFault>> faults;
};

// Runs in real time until `stop` is set or max_minutes passed.
int RunLiveSimulation(const LiveOptions& options, MachineLink& link, const std::atomic<bool>& stop);

}  // namespace thermocomp
