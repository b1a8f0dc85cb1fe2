// DdsBridge: thermocomp's Cyclone DDS face (docs/dds.md). It subscribes to
// TemperatureSample and ProbePoint, validates and stores them in batches
// through IngestService (the same rules as HTTP), publishes an
// IngestReceipt for what a commit stored and an IngestRejection for refused
// data (a batch with refused items is stored without them), and publishes
// CompensationParameters
// (reliable, transient-local, keep-last 1 per machine and axis) when a
// served value changes by more than a step, changes validity, or a minute
// passed; at start it publishes the current values from SQLite. Each
// configured feed axis' ThermalErrorTable (same QoS) is computed once a
// second and published when a served point moves by more than the step,
// its status word or grid changes, or a minute passed.
// Participants use the file in CYCLONEDDS_URI; if unset, the configured
// loopback file (deploy/cyclonedds.xml).
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "service/app.h"

namespace thermocomp::dds {

struct BridgeOptions {
  int batch_max = 1000;           // flush a batch at this many samples...
  int batch_max_delay_ms = 20;    // ...or when its oldest sample waited this long
  double publish_step_mm = 1e-4;  // publish compensation on a change above this
  int publish_every_ms = 60000;   // and at least this often
  uint32_t domain = 0;            // DDS domain id
};

class DdsBridge {
 public:
  DdsBridge(App& app, BridgeOptions options);
  ~DdsBridge();
  Status Start();
  void Stop();

  // Samples committed so far (benchmarks wait on it).
  uint64_t samples_stored() const { return samples_stored_; }

 private:
  struct Entities;
  void Run();
  void Flush();
  void PublishCompensation(const MachineCompensation& c, bool force);
  void PublishThermalErrors(bool force);
  // Pending and overdue column-check requests; answered ones are disposed.
  void PublishCheckRequests();
  void PublishRejection(const std::string& machine, const char* topic, const std::string& item,
                        const IngestResult& r, size_t error_index);
  void StoreTemperatures(const std::string& machine, std::vector<TemperatureInput> samples);
  // One receipt per sensor and run of stored samples not interrupted by a
  // refused one, so no receipt covers a sample that was not stored.
  void PublishReceipts(const std::string& machine, const std::vector<TemperatureInput>& stored,
                       const std::vector<TemperatureInput>& refused = {});

  App& app_;
  BridgeOptions options_;
  std::unique_ptr<Entities> e_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::mutex publish_mutex_;
  struct Published {
    double offset_mm = 0;
    int status = -1;  // AxisCompensation::StatusWord(); -1: nothing published yet
    int64_t at_ms = 0;
  };
  std::map<std::string, Published> published_;  // by "machine/axis"
  struct PublishedTable {
    std::vector<double> correction_um;
    int status = -1;
    int64_t at_ms = 0;
  };
  std::map<std::string, PublishedTable> tables_published_;  // by "machine/axis"
  // Open column-check requests on the CheckRequest topic, by "machine/id":
  // the state written (pending or overdue).
  std::map<std::string, std::string> requests_published_;
  std::atomic<uint64_t> samples_stored_{0};
};

// Points CYCLONEDDS_URI at `config_file` unless the environment sets it.
void UseLoopbackConfig(const std::string& config_file);

}  // namespace thermocomp::dds
