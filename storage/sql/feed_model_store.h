// SqlFeedModelStore: FeedModelStore over SQL (feed_axis_configs,
// feed_models; migrations/0009_feed_axis.sql).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "storage/feed_model_store.h"
#include "storage/sql/connection.h"

namespace thermocomp {

class SqlFeedModelStore final : public FeedModelStore {
 public:
  explicit SqlFeedModelStore(SqlConnection& db) : db_(db) {}

  Status PutConfig(int64_t axis_id, const std::string& config_json, int64_t now_ms) override;
  std::optional<FeedAxisConfigRecord> Config(int64_t axis_id) override;
  std::vector<FeedAxisConfigRecord> Configs(int64_t machine_id) override;

  StatusOr<int> Insert(int64_t axis_id, const FeedModelRecord& record) override;
  std::vector<FeedModelRecord> List(int64_t axis_id) override;
  std::optional<FeedModelRecord> Get(int64_t axis_id, int version) override;
  std::optional<FeedModelRecord> Active(int64_t axis_id) override;
  Status Activate(int64_t axis_id, int version) override;
  Status SetReport(int64_t axis_id, int version, const std::string& report_json) override;

 private:
  SqlConnection& db_;
};

}  // namespace thermocomp
