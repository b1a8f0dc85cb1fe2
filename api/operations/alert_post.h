// The webhook's HTTP client (service/operations/alert_webhook.h): POSTs a
// JSON event to an http:// or https:// URL with bounded timeouts, so a
// receiver that hangs holds the webhook's thread for at most those.
#pragma once

#include <string>

#include "service/operations/alert_webhook.h"

namespace thermocomp::api {

// Connect and read/write timeouts of one POST.
inline constexpr int kAlertPostTimeoutS = 10;

// Status OK only for a 2xx answer; InvalidArgument for a URL that is not
// scheme://host[:port][/path]; Unavailable when the receiver is not reached
// or answers otherwise.
Status PostAlert(const std::string& url, const std::string& json);

// Whether `url` is one PostAlert can send to (empty is allowed: no webhook).
bool ValidAlertUrl(const std::string& url);

}  // namespace thermocomp::api
