#include "api/problem.h"

#include <nlohmann/json.hpp>

#include "reports/json_text.h"

namespace thermocomp::api {
namespace {

// Reason phrases of RFC 9110 (and 4918 for 507) for every status we send.
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
    case 408:
      return "Request Timeout";
    case 409:
      return "Conflict";
    case 411:
      return "Length Required";
    case 413:
      return "Content Too Large";
    case 414:
      return "URI Too Long";
    case 415:
      return "Unsupported Media Type";
    case 416:
      return "Range Not Satisfiable";
    case 417:
      return "Expectation Failed";
    case 421:
      return "Misdirected Request";
    case 422:
      return "Unprocessable Content";
    case 429:
      return "Too Many Requests";
    case 431:
      return "Request Header Fields Too Large";
    case 500:
      return "Internal Server Error";
    case 501:
      return "Not Implemented";
    case 503:
      return "Service Unavailable";
    case 507:
      return "Insufficient Storage";
    default:
      return status >= 500 ? "Internal Server Error" : "Bad Request";
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
    case Status::Code::kFailedPrecondition:
      return 409;
    case Status::Code::kUnprocessable:
      return 422;
    case Status::Code::kTooLarge:
      return 413;
    case Status::Code::kUnavailable:
      return 503;
    case Status::Code::kInsufficientStorage:
      return 507;
    case Status::Code::kInternal:
      return 500;
  }
  return 500;
}

void WriteProblem(httplib::Response& res, int http_status, const std::string& detail,
                  const FieldErrors& errors) {
  nlohmann::json p = {{"type", "about:blank"},
                      {"title", Title(http_status)},
                      {"status", http_status},
                      {"detail", detail}};
  if (!errors.empty()) {
    nlohmann::json list = nlohmann::json::array();
    for (size_t i = 0; i < errors.size() && i < FieldErrors::kMaxReported; ++i) {
      const FieldError& e = errors[i];
      list.push_back({{"index", e.index}, {"field", e.field}, {"message", e.message}});
    }
    p["errors"] = list;
    if (errors.total() > errors.size()) p["errors_total"] = errors.total();
  }
  res.status = http_status;
  // A busy database or a full disk passes: clients (a PLC, line software)
  // should retry rather than give up.
  if (http_status == 503) res.set_header("Retry-After", "1");
  if (http_status == 507) res.set_header("Retry-After", "60");
  res.set_content(JsonText(p), "application/problem+json");
}

void WriteProblem(httplib::Response& res, const Status& s, const FieldErrors& errors) {
  std::string detail = s.message();
  if (!errors.empty()) detail += ": " + errors.front().field + ": " + errors.front().message;
  WriteProblem(res, HttpStatus(s), detail, errors);
}

}  // namespace thermocomp::api
