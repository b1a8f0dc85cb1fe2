// The audit trail (docs/api.md, Audit): GET /api/v1/audit, for admins
// only (the trail names every token's writes), filtered by machine, time
// and action, the last written first, a page at a time with a cursor.
#include "api/http_server.h"  // first: Eigen before httplib.h

#include <nlohmann/json.hpp>

#include "api/http_util.h"
#include "api/problem.h"
#include "core/time_format.h"
#include "service/operations/audit_trail.h"

namespace thermocomp::api {
namespace {

using nlohmann::json;

constexpr int kDefaultLimit = 100;

// The characters a stored name or action may have ([A-Za-z0-9_.-:]), 1..max.
bool PlainName(const std::string& text, size_t max) {
  if (text.empty() || text.size() > max) return false;
  for (const char c : text) {
    const bool ok = (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '.' || c == '-' || c == ':';
    if (!ok) return false;
  }
  return true;
}

// A positive decimal below 10^18, or nullopt.
std::optional<int64_t> Positive(const std::string& text) {
  if (text.empty() || text.size() > 18) return std::nullopt;
  int64_t n = 0;
  for (const char c : text) {
    if (c < '0' || c > '9') return std::nullopt;
    n = n * 10 + (c - '0');
  }
  return n > 0 ? std::optional<int64_t>(n) : std::nullopt;
}

// The query as the trail reads it; every bad parameter named in `errors`.
AuditQuery ParseQuery(const httplib::Request& req, FieldErrors& errors) {
  AuditQuery q;
  q.limit = kDefaultLimit;
  if (req.has_param("machine")) {
    q.machine = req.get_param_value("machine");
    if (!PlainName(q.machine, 64) || q.machine.find(':') != std::string::npos) {
      errors.push_back({0, "machine", "must match [A-Za-z0-9_.-]{1,64}"});
    }
  }
  if (req.has_param("action")) {
    q.action = req.get_param_value("action");
    if (!PlainName(q.action, 64)) {
      errors.push_back({0, "action", "must be an action's name ([A-Za-z0-9_.:-]{1,64})"});
    }
  }
  for (const char* name : {"from", "to"}) {
    if (!req.has_param(name)) continue;
    const auto ms = ParseRfc3339(req.get_param_value(name));
    if (!ms) {
      errors.push_back({0, name, "must be an RFC 3339 time, e.g. 2026-11-25T07:00:00Z"});
      continue;
    }
    (std::string(name) == "from" ? q.from_ms : q.to_ms) = *ms;
  }
  if (q.from_ms && q.to_ms && *q.from_ms > *q.to_ms) {
    errors.push_back({0, "from", "must not be after to"});
  }
  if (req.has_param("limit")) {
    const auto n = Positive(req.get_param_value("limit"));
    if (!n || *n > AuditTrail::kMaxLimit) {
      errors.push_back({0, "limit", "must be an integer from 1 to 1000"});
    } else {
      q.limit = static_cast<int>(*n);
    }
  }
  if (req.has_param("next")) {
    const auto cursor = Positive(req.get_param_value("next"));
    if (!cursor) {
      errors.push_back({0, "next", "must be the next cursor of an earlier page"});
    } else {
      q.before_id = *cursor;
    }
  }
  return q;
}

json EntryToJson(const AuditEntry& e) {
  return {{"ts", FormatRfc3339(e.ts_ms)},
          {"actor", e.actor},
          {"action", e.action},
          {"machine", e.machine.empty() ? json(nullptr) : json(e.machine)},
          {"count", e.count},
          {"detail", e.detail}};
}

}  // namespace

void HttpServer::AuditRoutes() {
  server_.Get("/api/v1/audit", [this](const Req& req, Res& res) {
    // The request hook let every reader through to a GET; the trail is
    // the admins'. Without tokens every (loopback) client is one.
    const auto snapshot = exposure();  // the token list this request saw
    const Authorizer& auth = snapshot->auth;
    bool admin = auth.open();
    if (!admin) {
      const std::string presented = CredentialsOf(req).authorization;
      const std::string bearer = "Bearer ";
      if (presented.rfind(bearer, 0) == 0) {
        const auto token = auth.FindToken(presented.substr(bearer.size()));
        admin = token && token->role == "admin";
      }
    }
    if (!admin) return WriteProblem(res, 403, "the audit trail is for the admin role only");
    FieldErrors errors;
    const AuditQuery q = ParseQuery(req, errors);
    if (!errors.empty()) {
      return WriteProblem(res, Status::InvalidArgument("invalid audit query"), errors);
    }
    auto page = AuditTrail(app_.storage()).Read(q);
    if (!page.ok()) return WriteProblem(res, page.status());
    json entries = json::array();
    for (const AuditEntry& e : page->entries) entries.push_back(EntryToJson(e));
    WriteJson(res, {{"entries", std::move(entries)},
                    {"next", page->next_before_id ? json(std::to_string(*page->next_before_id))
                                                  : json(nullptr)}});
  });
}

}  // namespace thermocomp::api
