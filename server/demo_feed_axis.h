// DemoFeedAxis: the demo machine's X axis as a ball-screw feed axis, so the
// demo line shows the feed-axis thermal error (docs/model.md §12, §14). A
// simulated fixed–floating screw (sim/screw_axis.h, fixed seed) warms and
// cools over the last three days: its five screw sensors are added to the
// machine and their minute samples archived through the ingest service;
// eleven laser positioning checks of X (a cold reference, then ten at other
// thermal states, compensation off) go through the check service; then the
// screw configuration is put and the feed models are fitted, as a user
// would. Nothing already on the machine changes: X keeps its datum model,
// its sensors and its checks; the screw adds sensors, checks and a feed
// configuration beside them. Deterministic (fixed seeds); under two seconds
// of CPU, most of it the feed models' fit (the neural type's training).
#pragma once

#include <string>

#include "core/status.h"
#include "service/app.h"

namespace thermocomp {

// `summary` (optional) receives one line saying what was added.
Status DemoFeedAxis(App& app, const std::string& machine, std::string* summary = nullptr);

}  // namespace thermocomp
