// A DDS peer for the tests: its own participant on the loopback
// configuration, writing the ingest topics and reading what the server
// publishes, as a machine or line software would.
#pragma once

#include <algorithm>
#include <chrono>
#include <vector>
#include <cstdlib>
#include <optional>
#include <string>
#include <thread>

#include <dds/dds.h>

#include "thermocomp.h"

namespace thermocomp::testing {

inline void UseRepoDdsConfig() {
  setenv("CYCLONEDDS_URI", ("file://" + std::string(THERMOCOMP_SOURCE_DIR) + "/deploy/cyclonedds.xml").c_str(), 1);
}

struct CompensationSeen {
  double offset_mm = 0;
  bool valid = false;
  int model_version = -1;
  std::string reason;
};

class DdsPeer {
 public:
  DdsPeer() {
    UseRepoDdsConfig();
    participant_ = dds_create_participant(DDS_DOMAIN_DEFAULT, nullptr, nullptr);
    dds_qos_t* reliable = dds_create_qos();
    dds_qset_reliability(reliable, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_history(reliable, DDS_HISTORY_KEEP_LAST, 4096);
    dds_qos_t* state = dds_create_qos();
    dds_qset_reliability(state, DDS_RELIABILITY_RELIABLE, DDS_SECS(1));
    dds_qset_durability(state, DDS_DURABILITY_TRANSIENT_LOCAL);
    dds_qset_history(state, DDS_HISTORY_KEEP_LAST, 1);
    dds_entity_t t_temp = dds_create_topic(participant_, &thermocomp_TemperatureSample_desc,
                                           "thermocomp/TemperatureSample", reliable, nullptr);
    dds_entity_t t_rej = dds_create_topic(participant_, &thermocomp_IngestRejection_desc,
                                          "thermocomp/IngestRejection", reliable, nullptr);
    t_comp_ = dds_create_topic(participant_, &thermocomp_CompensationParameters_desc,
                               "thermocomp/CompensationParameters", state, nullptr);
    temperature_writer_ = dds_create_writer(participant_, t_temp, reliable, nullptr);
    rejection_reader_ = dds_create_reader(participant_, t_rej, reliable, nullptr);
    dds_entity_t t_rec = dds_create_topic(participant_, &thermocomp_IngestReceipt_desc,
                                          "thermocomp/IngestReceipt", reliable, nullptr);
    receipt_reader_ = dds_create_reader(participant_, t_rec, reliable, nullptr);
    state_qos_ = state;
    dds_delete_qos(reliable);
  }
  ~DdsPeer() {
    dds_delete_qos(state_qos_);
    dds_delete(participant_);
  }
  bool ok() const { return participant_ > 0 && temperature_writer_ > 0 && rejection_reader_ > 0; }

  // Waits until a server's reader is matched, so nothing is published into the void.
  bool WaitForServer(int timeout_ms = 10000) {
    for (int waited = 0; waited < timeout_ms; waited += 20) {
      dds_publication_matched_status_t st;
      if (dds_get_publication_matched_status(temperature_writer_, &st) == DDS_RETCODE_OK &&
          st.current_count > 0) {
        return true;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }

  void Publish(const std::string& machine, const std::string& sensor, int64_t ts_ms, double value) {
    thermocomp_TemperatureSample s{};
    s.machine = const_cast<char*>(machine.c_str());
    s.sensor = const_cast<char*>(sensor.c_str());
    s.ts_ms = ts_ms;
    s.value = value;
    dds_write(temperature_writer_, &s);
  }

  // The first rejection for `machine` within the timeout: field and status.
  std::optional<std::pair<std::string, int>> WaitForRejection(const std::string& machine,
                                                              int timeout_ms = 10000) {
    for (int waited = 0; waited < timeout_ms; waited += 20) {
      void* buf[16] = {nullptr};
      dds_sample_info_t info[16];
      int n = dds_take(rejection_reader_, buf, info, 16, 16);
      std::optional<std::pair<std::string, int>> found;
      for (int i = 0; i < n; ++i) {
        auto* r = static_cast<thermocomp_IngestRejection*>(buf[i]);
        if (info[i].valid_data && machine == r->machine && !found) found = {{r->field, r->status}};
      }
      if (n > 0) dds_return_loan(rejection_reader_, buf, n);
      if (found) return found;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return std::nullopt;
  }

  struct Receipt {
    std::string machine, sensor;
    int64_t first_ts_ms, last_ts_ms, samples;
  };
  // Receipts that arrived since the last call.
  std::vector<Receipt> TakeReceipts() {
    std::vector<Receipt> out;
    void* buf[64] = {nullptr};
    dds_sample_info_t info[64];
    int n;
    while ((n = dds_take(receipt_reader_, buf, info, 64, 64)) > 0) {
      for (int i = 0; i < n; ++i) {
        auto* r = static_cast<thermocomp_IngestReceipt*>(buf[i]);
        if (info[i].valid_data) out.push_back({r->machine, r->sensor, r->first_ts_ms, r->last_ts_ms, r->samples});
      }
      dds_return_loan(receipt_reader_, buf, n);
      std::fill(std::begin(buf), std::end(buf), nullptr);
    }
    return out;
  }

  // Joins late: a new transient-local reader gets the current value at once.
  std::optional<CompensationSeen> ReadCompensation(const std::string& machine, const std::string& axis,
                                                   int timeout_ms = 10000) {
    dds_entity_t reader = dds_create_reader(participant_, t_comp_, state_qos_, nullptr);
    std::optional<CompensationSeen> seen;
    for (int waited = 0; waited < timeout_ms && !seen; waited += 20) {
      void* buf[16] = {nullptr};
      dds_sample_info_t info[16];
      int n = dds_take(reader, buf, info, 16, 16);
      for (int i = 0; i < n; ++i) {
        auto* c = static_cast<thermocomp_CompensationParameters*>(buf[i]);
        if (info[i].valid_data && machine == c->machine && axis == c->axis) {
          seen = CompensationSeen{c->offset_mm, c->valid, c->model_version, c->reason};
        }
      }
      if (n > 0) dds_return_loan(reader, buf, n);
      if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    dds_delete(reader);
    return seen;
  }

 private:
  dds_entity_t participant_ = 0, temperature_writer_ = 0, rejection_reader_ = 0, t_comp_ = 0;
  dds_entity_t receipt_reader_ = 0;
  dds_qos_t* state_qos_ = nullptr;
};

}  // namespace thermocomp::testing
