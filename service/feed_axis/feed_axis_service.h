// FeedAxisService: an axis' ball-screw configuration and its feed-axis
// models (docs/api.md, "Feed axes"). A configuration is checked in full
// before anything is stored: its content (FeedAxisConfigFromJson), that
// every sensor it names is a sensor of the machine, and that its reference
// check is a positioning check of that axis; a wrong one stores nothing.
// Models are made by FeedFitService; here they are listed, read and
// activated by hand. Every write leaves an audit row. The thermal error
// table reads the active model each time, so an activation needs no
// notice to anyone.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/clock.h"
#include "core/records.h"
#include "service/config.h"
#include "service/feed_axis/feed_axis_config.h"
#include "storage/feed_model_store.h"
#include "storage/storage.h"

namespace thermocomp {

// The stored configuration of an axis (by its id) as FeedAxisConfig:
// NotFound when the axis has none; Internal when what is stored no longer
// reads (a bug: it was checked when stored).
StatusOr<FeedAxisConfig> LoadFeedAxisConfig(Session& session, int64_t axis_id);

class FeedAxisService {
 public:
  FeedAxisService(Storage& storage, const Clock& clock, const Config& config)
      : storage_(storage), clock_(clock), config_(config) {}

  // Stores `json` as the axis' configuration (replacing any). True when the
  // axis had none. NotFound for an unknown machine or axis; InvalidArgument
  // with `errors` naming the fields ("screw.sensors[0].x_mm").
  StatusOr<bool> PutConfig(const std::string& machine, const std::string& axis,
                           const nlohmann::json& json, const std::string& actor,
                           FieldErrors* errors);
  // NotFound for an unknown machine or axis, or an axis not configured.
  StatusOr<FeedAxisConfig> Config(const std::string& machine, const std::string& axis);

  // The axis' versions, newest first.
  StatusOr<std::vector<FeedModelRecord>> Models(const std::string& machine,
                                                const std::string& axis);
  StatusOr<FeedModelRecord> Model(const std::string& machine, const std::string& axis, int version);
  // Makes `version` the axis' active model (the active one is retired).
  StatusOr<AuditEntry> Activate(const std::string& machine, const std::string& axis, int version,
                                const std::string& actor);

 private:
  Storage& storage_;
  const Clock& clock_;
  [[maybe_unused]] const thermocomp::Config& config_;  // limits, as the other services take them
};

}  // namespace thermocomp
