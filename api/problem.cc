#include "api/problem.h"

#include <nlohmann/json.hpp>

namespace thermocomp::api {
namespace {

const char* Title(int status) {
  switch (status) {
    case 400:
      return "Bad Request";
    case 401:
      return "Unauthorized";
    case 403:
      return "Forbidden";
    case 404:
      return "Not Found";
    case 405:
      return "Method Not Allowed";
    case 409:
      return "Conflict";
    case 413:
      return "Payload Too Large";
    case 415:
      return "Unsupported Media Type";
    case 422:
      return "Unprocessable Content";
    case 503:
      return "Service Unavailable";
    default:
      return "Internal Server Error";
  }
}

}  // namespace

int HttpStatus(const Status& s) {
  switch (s.code()) {
    case Status::Code::kOk:
      return 200;
    case Status::Code::kInvalidArgument:
      return 400;
    case Status::Code::kNotFound:
      return 404;
    case Status::Code::kConflict:
      return 409;
    case Status::Code::kFailedPrecondition:
      return 409;
    case Status::Code::kUnprocessable:
      return 422;
    case Status::Code::kTooLarge:
      return 413;
    case Status::Code::kUnavailable:
      return 503;
    case Status::Code::kInternal:
      return 500;
  }
  return 500;
}

void WriteProblem(httplib::Response& res, int http_status, const std::string& detail,
                  const std::vector<FieldError>& errors) {
  nlohmann::json p = {{"type", "about:blank"},
                      {"title", Title(http_status)},
                      {"status", http_status},
                      {"detail", detail}};
  if (!errors.empty()) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& e : errors) {
      list.push_back({{"index", e.index}, {"field", e.field}, {"message", e.message}});
    }
    p["errors"] = list;
  }
  res.status = http_status;
  res.set_content(p.dump(), "application/problem+json");
}

void WriteProblem(httplib::Response& res, const Status& s, const std::vector<FieldError>& errors) {
  std::string detail = s.message();
  if (!errors.empty()) detail += ": " + errors.front().field + ": " + errors.front().message;
  WriteProblem(res, HttpStatus(s), detail, errors);
}

}  // namespace thermocomp::api
