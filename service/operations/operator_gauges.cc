#include "service/operations/operator_gauges.h"

namespace thermocomp {

std::string OperatorGauges(App&) { return ""; }

}  // namespace thermocomp
