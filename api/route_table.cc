#include "api/route_table.h"

#include <map>

namespace thermocomp::api {
namespace {

constexpr size_t kNone = static_cast<size_t>(-1);

// The pattern's segments between '/', a '/' inside a group or a bracket
// expression not splitting.
std::vector<std::string> Segments(const std::string& pattern) {
  std::vector<std::string> out;
  std::string current;
  int depth = 0;
  bool escaped = false;
  for (size_t i = pattern.empty() || pattern[0] != '/' ? 0 : 1; i < pattern.size(); ++i) {
    const char c = pattern[i];
    if (escaped) {
      escaped = false;
    } else if (c == '\\') {
      escaped = true;
    } else if (c == '(' || c == '[') {
      ++depth;
    } else if (c == ')' || c == ']') {
      --depth;
    } else if (c == '/' && depth == 0) {
      out.push_back(current);
      current.clear();
      continue;
    }
    current += c;
  }
  if (!current.empty() || (!pattern.empty() && pattern.back() == '/' && pattern.size() > 1)) {
    out.push_back(current);
  }
  return out;
}

// The segment as a literal ("holes\.csv" -> "holes.csv"), or "" when it is
// an expression (a parameter).
std::string Literal(const std::string& segment) {
  std::string out;
  for (size_t i = 0; i < segment.size(); ++i) {
    const char c = segment[i];
    if (c == '\\' && i + 1 < segment.size()) {
      out += segment[++i];
      continue;
    }
    if (std::string_view("([{*+?|^$").find(c) != std::string_view::npos) return "";
    out += c;
  }
  return out;
}

std::string ParameterAfter(const std::string& previous) {
  static const std::map<std::string, std::string> names = {
      {"machines", "machine"},    {"axes", "axis"},
      {"models", "version"},      {"feed-models", "version"},
      {"part-models", "version"}, {"analysis", "id"},
      {"column-checks", "id"},    {"positioning-checks", "id"},
      {"artifacts", "artifact"},  {"plates", "plate"},
      {"surfaces", "surface"},    {"static", "file"},
      {"dygraphs", "file"},       {"alerts", "alert"},
      {"requests", "id"},
  };
  auto it = names.find(previous);
  return it == names.end() ? "param" : it->second;
}

}  // namespace

RouteTable::RouteTable() : nodes_(1) {}

std::string RouteTable::TemplateOf(const std::string& pattern) {
  std::string out;
  std::string previous;
  for (const std::string& segment : Segments(pattern)) {
    std::string literal = Literal(segment);
    const bool is_param = literal.empty() && !segment.empty();
    out += "/" + (is_param ? ":" + ParameterAfter(previous) : literal);
    previous = is_param ? "" : literal;
  }
  return out.empty() ? "/" : out;
}

void RouteTable::Add(const std::string& pattern) {
  size_t node = 0;
  for (const std::string& segment : Segments(pattern)) {
    const std::string literal = Literal(segment);
    size_t next = 0;
    if (literal.empty() && !segment.empty()) {
      next = nodes_[node].param;
      if (next == 0) {
        next = nodes_.size();
        nodes_.emplace_back();
        nodes_[node].param = next;
      }
    } else {
      for (const auto& [text, child] : nodes_[node].literals) {
        if (text == literal) next = child;
      }
      if (next == 0) {
        next = nodes_.size();
        nodes_.emplace_back();
        nodes_[node].literals.emplace_back(literal, next);
      }
    }
    node = next;
  }
  if (nodes_[node].route != kNone) return;
  nodes_[node].route = templates_.size();
  templates_.push_back(TemplateOf(pattern));
}

size_t RouteTable::MatchFrom(size_t node, std::string_view rest) const {
  if (rest.empty()) return nodes_[node].route == kNone ? kUnmatched() : nodes_[node].route;
  // rest starts with '/'.
  rest.remove_prefix(1);
  const size_t slash = rest.find('/');
  const std::string_view segment = rest.substr(0, slash);
  const std::string_view after =
      slash == std::string_view::npos ? std::string_view() : rest.substr(slash);
  // A literal segment wins over a parameter (.../column-checks/requests).
  for (const auto& [text, child] : nodes_[node].literals) {
    if (text != segment) continue;
    if (size_t id = MatchFrom(child, after); id != kUnmatched()) return id;
  }
  if (nodes_[node].param != 0 && !segment.empty()) {
    return MatchFrom(nodes_[node].param, after);
  }
  return kUnmatched();
}

size_t RouteTable::Match(std::string_view path) const {
  if (path.empty() || path[0] != '/') return kUnmatched();
  if (path == "/") return nodes_[0].route == kNone ? kUnmatched() : nodes_[0].route;
  return MatchFrom(0, path);
}

}  // namespace thermocomp::api
