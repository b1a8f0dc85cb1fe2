// OperatorGauges: what an operator alerts on, as Prometheus gauges computed
// when /metrics is scraped (docs/operations.md, Observability).
#pragma once

#include <string>

#include "service/app.h"

namespace thermocomp {

// The gauges' text in the Prometheus exposition format, appended to the
// counters of Metrics::Render.
std::string OperatorGauges(App& app);

}  // namespace thermocomp
