// RouteTable: the API's routes as templates ("/api/v1/machines/:machine/
// compensation"), so that what is counted per route (service/metrics.h)
// and logged has a bounded set of names whatever paths clients send. The
// templates are made from the patterns the routes register with
// cpp-httplib (api/guarded_server.h): a segment that is a regular
// expression becomes a parameter named after the segment before it
// (machines/:machine, axes/:axis, models/:version). A path is matched by
// its segments, without regular expressions, so the lookup costs well
// under a microsecond on every request; a path of no route's shape is
// kUnmatched. Routes are added before serving; Match is then read-only.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace thermocomp::api {

class RouteTable {
 public:
  static constexpr const char* kUnmatchedName = "unmatched";
  RouteTable();
  // The route registered as `pattern` (a cpp-httplib pattern); a pattern
  // of a template already known (another method) adds nothing.
  void Add(const std::string& pattern);
  // The template of `pattern`, as Add names it.
  static std::string TemplateOf(const std::string& pattern);
  // The id of the route `path` (no query string) has the shape of, an
  // index into templates(); kUnmatched() when none.
  size_t Match(std::string_view path) const;
  size_t kUnmatched() const { return templates_.size(); }
  const std::vector<std::string>& templates() const { return templates_; }

 private:
  struct Node {
    std::vector<std::pair<std::string, size_t>> literals;  // segment, child node
    size_t param = 0;                                      // child node; 0: none
    size_t route = static_cast<size_t>(-1);
  };
  size_t MatchFrom(size_t node, std::string_view rest) const;

  std::vector<Node> nodes_;  // nodes_[0] is the root
  std::vector<std::string> templates_;
};

}  // namespace thermocomp::api
