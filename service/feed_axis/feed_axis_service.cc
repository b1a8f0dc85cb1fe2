#include "service/feed_axis/feed_axis_service.h"

#include <set>

#include "service/machine_lookup.h"

namespace thermocomp {
namespace {

// "list[i]", as the API names an element of a list.
std::string Indexed(const char* list, size_t i) {
  return std::string(list).append("[").append(std::to_string(i)).append("]");
}

std::string Quoted(const std::string& text) {
  return std::string("'").append(text).append("'");
}

// Sensors the configuration names that the machine does not have, each
// named by its place in the request.
void CheckSensorsExist(const MachineRecord& machine, const FeedAxisConfig& c, FieldErrors& errors) {
  std::set<std::string> known;
  for (const SensorRecord& s : machine.sensors) known.insert(s.name);
  const std::string unknown = " is not a sensor of " + machine.name;
  for (size_t i = 0; i < c.screw.sensors.size(); ++i) {
    const std::string& name = c.screw.sensors[i].name;
    if (!known.count(name)) {
      errors.push_back(
          {0, Indexed("screw.sensors", i).append(".name"), Quoted(name).append(unknown)});
    }
  }
  for (size_t i = 0; i < c.body_sensors.size(); ++i) {
    if (!known.count(c.body_sensors[i])) {
      errors.push_back(
          {0, Indexed("screw.body_sensors", i), Quoted(c.body_sensors[i]).append(unknown)});
    }
  }
}

}  // namespace

StatusOr<FeedAxisConfig> LoadFeedAxisConfig(Session& session, int64_t axis_id) {
  auto stored = session.feeds().Config(axis_id);
  if (!stored) return Status::NotFound("the axis has no screw configuration");
  const nlohmann::json j = nlohmann::json::parse(stored->config_json, nullptr, false);
  FieldErrors errors;
  auto config = FeedAxisConfigFromJson(j, &errors);
  if (!config.ok()) {
    return Status::Internal(
        "stored screw configuration of axis " + stored->axis + " does not read: " +
        (errors.empty() ? config.status().message()
                        : errors.front().field + ": " + errors.front().message));
  }
  return config;
}

StatusOr<bool> FeedAxisService::PutConfig(const std::string& machine_name,
                                          const std::string& axis_name, const nlohmann::json& json,
                                          const std::string& actor, FieldErrors* errors) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachineAxis(*session, machine_name, axis_name);
  if (!found.ok()) return found.status();
  FieldErrors e;
  auto config = FeedAxisConfigFromJson(json, &e);
  if (config.ok()) {
    CheckSensorsExist(found->machine, *config, e);
    if (config->reference_check_id) {
      auto check =
          session->checks().PositioningCheck(found->machine.id, *config->reference_check_id);
      if (!check || check->axis != axis_name) {
        e.push_back({0, "screw.reference_check_id",
                     "no positioning check " + std::to_string(*config->reference_check_id) +
                         " of axis " + axis_name + " on " + machine_name});
      }
    }
  }
  if (!e.empty()) {
    if (errors) *errors = e;
    return Status::InvalidArgument("invalid screw configuration");
  }
  const int64_t axis_id = found->axis().id;
  const bool created = !session->feeds().Config(axis_id).has_value();
  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  // Stored as read back, so the configuration in effect is what GET shows.
  const std::string text = FeedAxisConfigToJson(*config).dump();
  if (Status s = session->feeds().PutConfig(axis_id, text, clock_.NowMs()); !s.ok()) return s;
  if (Status s =
          session->log().Audit(clock_.NowMs(), actor, "screw-config", machine_name, 1, axis_name);
      !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  return created;
}

StatusOr<FeedAxisConfig> FeedAxisService::Config(const std::string& machine_name,
                                                 const std::string& axis_name) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachineAxis(*session, machine_name, axis_name);
  if (!found.ok()) return found.status();
  auto config = LoadFeedAxisConfig(*session, found->axis().id);
  if (config.status().code() == Status::Code::kNotFound) {
    return Status::NotFound("axis " + axis_name + " of " + machine_name +
                            " has no screw configuration");
  }
  return config;
}

StatusOr<std::vector<FeedModelRecord>> FeedAxisService::Models(const std::string& machine_name,
                                                               const std::string& axis_name) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachineAxis(*session, machine_name, axis_name);
  if (!found.ok()) return found.status();
  return session->feeds().List(found->axis().id);
}

StatusOr<FeedModelRecord> FeedAxisService::Model(const std::string& machine_name,
                                                 const std::string& axis_name, int version) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachineAxis(*session, machine_name, axis_name);
  if (!found.ok()) return found.status();
  auto model = session->feeds().Get(found->axis().id, version);
  if (!model) {
    return Status::NotFound("no feed model version " + std::to_string(version) + " for " +
                            machine_name + " axis " + axis_name);
  }
  return *model;
}

StatusOr<AuditEntry> FeedAxisService::Activate(const std::string& machine_name,
                                               const std::string& axis_name, int version,
                                               const std::string& actor) {
  const std::unique_ptr<Session> session = storage_.Open();
  auto found = FindMachineAxis(*session, machine_name, axis_name);
  if (!found.ok()) return found.status();
  const int64_t axis_id = found->axis().id;
  auto model = session->feeds().Get(axis_id, version);
  if (!model) {
    return Status::NotFound("no feed model version " + std::to_string(version) + " for " +
                            machine_name + " axis " + axis_name);
  }
  AuditEntry entry{
      clock_.NowMs(), actor, "activate-feed-model",
      machine_name,   1,     axis_name + " v" + std::to_string(version) + " (" + model->type + ")"};
  Transaction tx(*session);
  if (!tx.status().ok()) return tx.status();
  if (Status s = session->feeds().Activate(axis_id, version); !s.ok()) return s;
  if (Status s = session->log().Audit(entry.ts_ms, entry.actor, entry.action, entry.machine,
                                      entry.count, entry.detail);
      !s.ok()) {
    return s;
  }
  if (Status s = tx.Commit(); !s.ok()) return s;
  return entry;
}

}  // namespace thermocomp
