#include "storage/postgresql/pg_centre.h"

#include "storage/postgresql/pg_storage.h"
#include "storage/sql/shipping/centre_store.h"

namespace thermocomp {
namespace {

class PgCentre final : public Centre {
 public:
  explicit PgCentre(std::unique_ptr<PgStorage> storage)
      : storage_(std::move(storage)),
        centre_([this](const std::function<void(SqlConnection&)>& fn) {
          storage_->WithConnection(fn);
        }) {}
  Status Applied(const std::string& plant, int64_t* seq) override {
    return centre_.Applied(plant, seq);
  }
  Status Apply(const std::string& plant, const std::vector<ShippedRow>& rows,
               int64_t* applied) override {
    return centre_.Apply(plant, rows, applied);
  }

 private:
  std::unique_ptr<PgStorage> storage_;
  SqlCentre centre_;
};

}  // namespace

StatusOr<std::unique_ptr<Centre>> OpenCentre(const std::string& url) {
  auto storage = PgStorage::Open(url);
  if (!storage.ok()) return storage.status();
  return std::unique_ptr<Centre>(std::make_unique<PgCentre>(std::move(storage).value()));
}

}  // namespace thermocomp
