#include "service/mtconnect/mtconnect_board.h"

#include <cstdio>
#include <functional>

namespace thermocomp {

namespace mtconnect_board {

// A number as Prometheus reads it; integers up to 2^53 exactly.
std::string Number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// One metric family over every source. Machine names are identifiers
// ([A-Za-z0-9_.-], config.cc), so a label needs no escaping.
void Family(
    std::string& out, const std::string& name, const char* type, const char* help,
    const std::vector<MtconnectSourceStatus>& sources,
    const std::function<std::vector<std::pair<std::string, double>>(const MtconnectSourceStatus&)>&
        series) {
  out += "# HELP " + name + " " + help + "\n# TYPE " + name + " " + type + "\n";
  for (const auto& s : sources) {
    for (const auto& [extra, value] : series(s)) {
      out.append(name).append("{machine=\"").append(s.machine).append("\"").append(extra);
      out.append("} ").append(Number(value)).append("\n");
    }
  }
}

}  // namespace mtconnect_board

void MtconnectBoard::Publish(const MtconnectSourceStatus& status) {
  const std::lock_guard<std::mutex> lock(mutex_);
  sources_[status.machine] = status;
}

std::vector<MtconnectSourceStatus> MtconnectBoard::Snapshot() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  std::vector<MtconnectSourceStatus> out;
  out.reserve(sources_.size());
  for (const auto& [machine, s] : sources_) out.push_back(s);
  return out;
}

std::string MtconnectBoard::Gauges() const {
  namespace mb = mtconnect_board;
  using Series = std::vector<std::pair<std::string, double>>;
  const std::vector<MtconnectSourceStatus> sources = Snapshot();
  if (sources.empty()) return "";
  std::string out;
  mb::Family(out, "thermocomp_mtconnect_connected", "gauge",
             "1 when the machine's MTConnect agent answered the last request with a document.",
             sources, [](const MtconnectSourceStatus& s) {
               return Series{{"", s.connected ? 1.0 : 0.0}};
             });
  mb::Family(out, "thermocomp_mtconnect_instance_id", "gauge",
             "The agent's instanceId (changes when the agent restarts).", sources,
             [](const MtconnectSourceStatus& s) {
               return Series{{"", static_cast<double>(s.instance_id)}};
             });
  mb::Family(out, "thermocomp_mtconnect_next_sequence", "gauge",
             "The agent's sequence number the next /sample starts from.", sources,
             [](const MtconnectSourceStatus& s) {
               return Series{{"", static_cast<double>(s.next_sequence)}};
             });
  mb::Family(out, "thermocomp_mtconnect_last_poll_timestamp_seconds", "gauge",
             "When the source last asked its agent (Unix seconds).", sources,
             [](const MtconnectSourceStatus& s) {
               return Series{{"", static_cast<double>(s.last_poll_ms) / 1000.0}};
             });
  mb::Family(out, "thermocomp_mtconnect_last_gap_timestamp_seconds", "gauge",
             "When the source last recorded a gap (Unix seconds; 0: none yet). The audit line "
             "(action mtconnect_gap) names it.",
             sources, [](const MtconnectSourceStatus& s) {
               return Series{{"", static_cast<double>(s.last_gap_ms) / 1000.0}};
             });
  mb::Family(out, "thermocomp_mtconnect_gaps_total", "counter",
             "Gaps recorded in the audit (action mtconnect_gap), by reason.", sources,
             [](const MtconnectSourceStatus& s) {
               return Series{{",reason=\"unavailable\"", static_cast<double>(s.gaps_unavailable)},
                             {",reason=\"restart\"", static_cast<double>(s.gaps_restart)},
                             {",reason=\"wrap\"", static_cast<double>(s.gaps_wrap)}};
             });
  mb::Family(out, "thermocomp_mtconnect_samples_total", "counter",
             "Grid samples handed to ingest, by outcome.", sources,
             [](const MtconnectSourceStatus& s) {
               return Series{{",outcome=\"stored\"", static_cast<double>(s.samples_stored)},
                             {",outcome=\"duplicate\"", static_cast<double>(s.samples_duplicate)},
                             {",outcome=\"refused\"", static_cast<double>(s.samples_refused)}};
             });
  mb::Family(out, "thermocomp_mtconnect_polls_failed_total", "counter",
             "Polls that got no usable document (unreachable, error answer, malformed XML).",
             sources, [](const MtconnectSourceStatus& s) {
               return Series{{"", static_cast<double>(s.polls_failed)}};
             });
  return out;
}

}  // namespace thermocomp
