#include "service/operations/audit_trail.h"

#include <algorithm>

namespace thermocomp {

StatusOr<AuditPage> AuditTrail::Read(const AuditQuery& q) {
  AuditQuery one_more = q;
  one_more.limit = std::clamp(q.limit, 1, kMaxLimit);
  const auto wanted = static_cast<size_t>(one_more.limit);
  ++one_more.limit;  // one row beyond the page says whether an older page exists
  StatusOr<std::vector<AuditRow>> rows = Status::Internal("unread");
  {
    const std::unique_ptr<Session> session = storage_.Open();
    rows = session->log().AuditTrail(one_more);
  }
  if (!rows.ok()) return rows.status();
  AuditPage page;
  const size_t n = std::min(rows->size(), wanted);
  page.entries.reserve(n);
  for (size_t i = 0; i < n; ++i) page.entries.push_back((*rows)[i].entry);
  if (rows->size() > wanted) page.next_before_id = (*rows)[n - 1].id;
  return page;
}

}  // namespace thermocomp
