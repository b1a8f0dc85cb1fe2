#include "service/config.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <string_view>
#include <utility>

#include <arpa/inet.h>
#include <netinet/in.h>

#include <toml++/toml.h>

#include "core/display_name.h"
#include "service/mtconnect/mtconnect_config.h"

namespace thermocomp {
namespace {

// A token's name is the user name of its OPC UA sessions and who acted in
// the audit and on the pages.
constexpr size_t kMaxTokenNameLength = 64;

// "config PATH: WHAT", the start of every refusal of a configuration file.
std::string ConfigError(const std::string& path, const std::string& what) {
  std::string out = "config ";
  out += path;
  out += ": ";
  out += what;
  return out;
}

// One key of the file: how to read it into the Config. A reader fails with
// the reason (the caller adds file and key).
using Reader = std::function<std::string(const toml::node&, Config&)>;

std::string Describe(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a number";
    case toml::node_type::boolean:
      return "true/false";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::table:
      return "a table";
    default:
      return "a date or time";
  }
}

std::string Range(double lo, double hi) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%g..%g", lo, hi);
  return buf;
}

template <typename T>
Reader Int(T Config::*field, int64_t lo, int64_t hi) {
  return [=](const toml::node& n, Config& c) -> std::string {
    auto v = n.value_exact<int64_t>();
    if (!v) return "must be an integer, not " + Describe(n);
    if (*v < lo || *v > hi) return "must be within " + Range(lo, hi);
    c.*field = static_cast<T>(*v);
    return "";
  };
}

// A number (an integer is a number too) within [lo, hi].
Reader Number(const std::function<double&(Config&)>& field, double lo, double hi) {
  return [=](const toml::node& n, Config& c) -> std::string {
    std::optional<double> v =
        n.is_integer() ? std::optional<double>(*n.value<int64_t>()) : n.value_exact<double>();
    if (!v) return "must be a number, not " + Describe(n);
    if (!(*v >= lo && *v <= hi)) return "must be within " + Range(lo, hi);
    field(c) = *v;
    return "";
  };
}

Reader Number(double Config::*field, double lo, double hi) {
  return Number([field](Config& c) -> double& { return c.*field; }, lo, hi);
}

Reader Text(std::string Config::*field, const std::set<std::string>& allowed = {}) {
  return [=](const toml::node& n, Config& c) -> std::string {
    auto v = n.value_exact<std::string>();
    if (!v) return "must be a string, not " + Describe(n);
    if (!allowed.empty() && !allowed.count(*v)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "\"" : ", \"") + a + "\"";
      return "must be one of " + list;
    }
    if (v->empty()) return "must not be empty";
    c.*field = *v;
    return "";
  };
}

Reader Bool(bool Config::*field) {
  return [=](const toml::node& n, Config& c) -> std::string {
    auto v = n.value_exact<bool>();
    if (!v) return "must be true or false, not " + Describe(n);
    c.*field = *v;
    return "";
  };
}

// Whether the system's zone database (tzdata) has the zone: a compiled
// zone file begins with "TZif". The browser converts the times with its own
// copy of the same IANA database; a name neither knows would leave every
// page without times, so it stops the start instead.
bool KnownZone(const std::string& name) {
  if (name == "UTC") return true;
  std::ifstream file("/usr/share/zoneinfo/" + name, std::ios::binary);
  char magic[4] = {};
  return file.read(magic, sizeof magic) && std::string_view(magic, sizeof magic) == "TZif";
}

// An IANA zone name ("Europe/Berlin", "UTC"), by its shape (no dots, so no
// path leaves the zone directory) and in the zone database.
std::string TimeZone(const toml::node& n, Config& c) {
  auto v = n.value_exact<std::string>();
  if (!v) return "must be a time zone name such as \"Europe/Berlin\", not " + Describe(n);
  static const std::regex shape("[A-Za-z][A-Za-z0-9_+-]*(/[A-Za-z0-9_+-]+){0,2}");
  if (v->size() > 64 || !std::regex_match(*v, shape)) {
    return "must be a time zone name such as \"Europe/Berlin\" or \"UTC\"";
  }
  if (!KnownZone(*v)) {
    return "\"" + *v + "\" is not a time zone of the IANA database (/usr/share/zoneinfo); " +
           "for example \"Europe/Berlin\" or \"UTC\"";
  }
  c.web_time_zone = *v;
  return "";
}

// "192.0.2.1" or "::1": an address, not a name or a network.
bool IpLiteral(const std::string& text) {
  unsigned char buf[sizeof(in6_addr)];
  return inet_pton(AF_INET, text.c_str(), buf) == 1 || inet_pton(AF_INET6, text.c_str(), buf) == 1;
}

Reader Texts(std::vector<std::string> Config::*field, size_t max_items) {
  return [=](const toml::node& n, Config& c) -> std::string {
    const toml::array* a = n.as_array();
    if (!a || a->size() > max_items) {
      return "must be an array of at most " + std::to_string(max_items) + " strings";
    }
    std::vector<std::string> out;
    for (const auto& item : *a) {
      auto v = item.value_exact<std::string>();
      if (!v || v->empty() || v->size() > 255) return "must hold non-empty strings (255 at most)";
      out.push_back(*v);
    }
    c.*field = out;
    return "";
  };
}

std::string ReadTokens(const toml::node& n, Config& c) {
  const toml::array* list = n.as_array();
  if (!list) return "must be [[auth.tokens]] tables";
  static const std::set<std::string> kKeys = {"name", "token", "role", "machine"};
  for (const auto& item : *list) {
    const toml::table* t = item.as_table();
    if (!t) return "each entry must be a table";
    AccessToken a;
    for (const auto& [key, value] : *t) {
      const std::string k(key.str());
      if (!kKeys.count(k)) return "unknown key '" + k + "' (name, token, role, machine)";
      auto s = value.value_exact<std::string>();
      if (!s) return k + " must be a string";
      (k == "name" ? a.name : k == "token" ? a.token : k == "role" ? a.role : a.machine) = *s;
    }
    if (a.name.empty() || a.token.size() < 16) {
      return "each needs a name and a token of 16 characters or more";
    }
    // The name is who acts in the audit, on the pages and as the OPC UA
    // user name, so it is a name people read, and it names one token.
    if (std::string problem = DisplayNameProblem(a.name, kMaxTokenNameLength); !problem.empty()) {
      return "name " + problem;
    }
    for (const AccessToken& other : c.tokens) {
      if (other.name == a.name) return a.name + ": name given to two tokens";
    }
    if (a.role != "machine" && a.role != "reader" && a.role != "maintenance" &&
        a.role != "quality" && a.role != "admin") {
      return a.name + ": role must be machine, reader, maintenance, quality or admin";
    }
    if (a.role == "machine" && a.machine.empty()) {
      return a.name + ": role machine needs machine = \"...\"";
    }
    if (a.role != "machine" && !a.machine.empty()) {
      return a.name + ": machine = \"...\" is for role machine only";
    }
    c.tokens.push_back(a);
  }
  return "";
}

// Every key the file may hold, by "section.key".
const std::map<std::string, Reader>& Keys() {
  static const std::map<std::string, Reader> keys = {
      {"server.listen",
       [](const toml::node& n, Config& c) -> std::string {
         auto v = n.value_exact<std::string>();
         if (!v) return "must be a string \"host:port\"";
         Status s = ParseListen(*v, c);
         return s.ok() ? "" : s.message();
       }},
      {"server.threads", Int(&Config::http_threads, 1, 4096)},
      {"server.max_body_bytes", Int(&Config::max_body_bytes, 1024, int64_t{1} << 30)},
      {"server.max_connections_per_client", Int(&Config::max_connections_per_client, 1, 100000)},
      {"server.header_timeout_s", Int(&Config::header_timeout_s, 1, 600)},
      {"server.body_timeout_s", Int(&Config::body_timeout_s, 1, 3600)},
      {"server.keep_alive_timeout_s", Int(&Config::keep_alive_timeout_s, 1, 3600)},
      {"server.body_grace_s", Int(&Config::body_grace_s, 1, 600)},
      {"server.body_min_rate_bytes_per_s",
       Int(&Config::body_min_rate_bytes_per_s, 1, int64_t{1} << 30)},
      {"server.anonymous_worker_share", Number(&Config::anonymous_worker_share, 0.01, 1)},
      {"server.allowed_hosts", Texts(&Config::allowed_hosts, 64)},
      {"server.allow_network_without_tokens", Bool(&Config::allow_network_without_tokens)},
      {"server.trusted_proxies",
       [](const toml::node& n, Config& c) -> std::string {
         if (std::string e = Texts(&Config::trusted_proxies, 16)(n, c); !e.empty()) return e;
         for (const auto& p : c.trusted_proxies) {
           if (!IpLiteral(p)) return "\"" + p + "\" is not an IPv4 or IPv6 address";
         }
         return "";
       }},
      {"server.access_log", Bool(&Config::access_log)},
      {"backup.dir",
       [](const toml::node& n, Config& c) -> std::string {
         auto v = n.value_exact<std::string>();
         if (!v || v->empty() || (*v)[0] != '/') return "must be an absolute directory path";
         c.backup_dir = *v;
         return "";
       }},
      {"backup.every_h", Int(&Config::backup_every_h, 1, 8760)},
      {"retention.raw_days", Int(&Config::retention_raw_days, 0, 36500)},
      {"retention.keep_around_h", Int(&Config::retention_keep_around_h, 0, 8760)},
      {"retention.every_h", Int(&Config::retention_every_h, 1, 8760)},
      {"backup.keep", Int(&Config::backup_keep, 1, 1000)},
      {"alerts.webhook_url",
       [](const toml::node& n, Config& c) -> std::string {
         auto v = n.value_exact<std::string>();
         if (!v || !(v->rfind("http://", 0) == 0 || v->rfind("https://", 0) == 0) ||
             v->size() > 2048) {
           return "must be an http:// or https:// URL";
         }
         c.alert_webhook_url = *v;
         return "";
       }},
      {"alerts.data_stopped_after_s", Int(&Config::alert_data_stopped_after_s, 60, 86400 * 30)},
      {"alerts.model_error_ratio", Number(&Config::alert_model_error_ratio, 1.01, 1000)},
      {"database.path", Text(&Config::db_path)},
      {"centre.url",
       [](const toml::node& n, Config& c) -> std::string {
         auto v = n.value_exact<std::string>();
         if (!v || !(v->rfind("postgresql://", 0) == 0 || v->rfind("postgres://", 0) == 0) ||
             v->size() > 2048) {
           return "must be a postgresql:// URL";
         }
         c.centre_url = *v;
         return "";
       }},
      {"centre.plant",
       [](const toml::node& n, Config& c) -> std::string {
         auto v = n.value_exact<std::string>();
         if (!v || !ValidPlantName(*v)) return "must match [A-Za-z0-9_-]{1,16}";
         c.centre_plant = *v;
         return "";
       }},
      {"centre.batch_rows", Int(&Config::centre_batch_rows, 1, 100000)},
      {"centre.interval_ms", Int(&Config::centre_interval_ms, 10, 600000)},
      {"server.read_only", Bool(&Config::read_only)},
      {"database.synchronous", Text(&Config::synchronous, {"full", "normal"})},
      {"database.busy_timeout_ms", Int(&Config::busy_timeout_ms, 0, 600000)},
      {"compensation.stale_after_s", Int(&Config::stale_after_s, 1, 86400)},
      {"compensation.plausible_min_c", Number(&Config::plausible_min_c, -60, 200)},
      {"compensation.plausible_max_c", Number(&Config::plausible_max_c, -60, 200)},
      {"compensation.max_step_c", Number(&Config::max_step_c, 0.01, 200)},
      {"compensation.range_margin", Number(&Config::range_margin, 0, 10)},
      {"compensation.hold_s", Int(&Config::hold_s, 0, 86400)},
      {"compensation.max_rate_um_per_min", Number(&Config::max_rate_um_per_min, 0.01, 1000)},
      {"ingest.max_future_skew_s", Int(&Config::max_future_skew_s, 0, 86400)},
      {"limits.max_events_per_machine_day", Int(&Config::max_events_per_machine_day, 1, 1000000)},
      {"limits.analysis_max_events", Int(&Config::analysis_max_events, 1, 100000)},
      {"limits.max_sensors_per_machine", Int(&Config::max_sensors_per_machine, 1, 100000)},
      {"limits.max_response_points", Int(&Config::max_response_points, 100, 100000000)},
      {"limits.overview_page_size", Int(&Config::overview_page_size, 1, 1000)},
      {"limits.probe_cache_points", Int(&Config::probe_cache_points, 0, 10000000)},
      {"auth.max_failures", Int(&Config::auth_max_failures, 1, 100000)},
      {"auth.failure_window_s", Int(&Config::auth_failure_window_s, 1, 86400)},
      {"fit.interval_min", Int(&Config::refit_interval_min, 0, 525600)},
      {"fit.after_new_runs", Int(&Config::refit_after_new_runs, 0, 100000)},
      {"fit.holdout_runs", Int(&Config::holdout_runs, 1, 10000)},
      {"fit.gross_error_mm", Number(&Config::gross_error_mm, 1e-6, 10)},
      {"fit.p_max", Number([](Config& c) -> double& { return c.selection.p_max; }, 1e-12, 1)},
      {"fit.vif_max", Number([](Config& c) -> double& { return c.selection.vif_max; }, 1, 1e9)},
      {"fit.outlier_threshold",
       Number([](Config& c) -> double& { return c.selection.outlier_threshold; }, 0.5, 100)},
      {"fit.outliers_per_step",
       [](const toml::node& n, Config& c) -> std::string {
         auto v = n.value_exact<int64_t>();
         if (!v || *v < 1 || *v > 1000) return "must be an integer within 1..1000";
         c.selection.outliers_per_step = static_cast<int>(*v);
         return "";
       }},
      {"fit.min_r2", Number([](Config& c) -> double& { return c.acceptance.min_r2; }, 0, 1)},
      {"fit.min_adj_r2",
       Number([](Config& c) -> double& { return c.acceptance.min_adj_r2; }, 0, 1)},
      {"fit.min_observations_per_term",
       [](const toml::node& n, Config& c) -> std::string {
         auto v = n.value_exact<int64_t>();
         if (!v || *v < 1 || *v > 10000) return "must be an integer within 1..10000";
         c.acceptance.min_observations_per_term = static_cast<int>(*v);
         return "";
       }},
      {"fit.min_validation_r2",
       [](const toml::node& n, Config& c) -> std::string {
         std::optional<double> v =
             n.is_integer() ? std::optional<double>(*n.value<int64_t>()) : n.value_exact<double>();
         if (!v || !(*v >= -10 && *v <= 1)) return "must be a number within -10..1";
         c.acceptance.min_validation_r2 = *v;
         return "";
       }},
      {"fit.daily_at",
       [](const toml::node& n,
          Config& c) -> std::
                         string {
                           auto v = n.value_exact<std::string>();
                           int h = -1, m = -1;
                           if (!v || v->size() != 5 ||
                               std::sscanf(v->c_str(), "%2d:%2d", &h, &m) != 2 || h < 0 || h > 23 ||
                               m < 0 || m > 59 || (*v)[2] != ':') {
                             return "must be \"HH:MM\" (UTC)";
                           }
                           c.refit_daily_at_min = h * 60 + m;
                           return "";
                         }},
      {"checks.every_days", Int(&Config::check_every_days, 0, 365)},
      {"checks.due_after_h", Int(&Config::check_due_after_h, 1, 8760)},
      {"checks.zero_tolerance_um", Number(&Config::zero_tolerance_um, 0.01, 10000)},
      {"analysis.policy", Text(&Config::analysis_policy, {"off", "propose", "activate"})},
      {"analysis.alpha", Number([](Config& c) -> double& { return c.analysis.alpha; }, 1e-12, 0.5)},
      {"analysis.min_cv_gain",
       Number([](Config& c) -> double& { return c.analysis.min_gain; }, 0, 0.9)},
      {"analysis.min_t", Number([](Config& c) -> double& { return c.analysis.min_t; }, 0, 100)},
      {"analysis.cv_block",
       [](const toml::node& n, Config& c) -> std::
                                              string {
                                                auto v = n.value_exact<std::string>();
                                                if (!v ||
                                                    (*v != "day" && *v != "week" && *v != "run")) {
                                                  return "must be \"day\", \"week\" or \"run\"";
                                                }
                                                c.analysis.cv_block = *v;
                                                return "";
                                              }},
      {"analysis.min_blocks",
       [](const toml::node& n, Config& c) -> std::
                                              string {
                                                auto v = n.value_exact<int64_t>();
                                                if (!v || *v < 2 || *v > 1000)
                                                  return "must be an integer within 2..1000";
                                                c.analysis.min_blocks = static_cast<int>(*v);
                                                return "";
                                              }},
      {"analysis.forward_blocks",
       [](const toml::node& n, Config& c) -> std::
                                              string {
                                                auto v = n.value_exact<int64_t>();
                                                if (!v || *v < 0 || *v > 100)
                                                  return "must be an integer within 0..100";
                                                c.analysis.forward_blocks = static_cast<int>(*v);
                                                return "";
                                              }},
      {"analysis.equivalent_t",
       Number([](Config& c) -> double& { return c.analysis.equivalent_t; }, 0, 100)},
      {"analysis.max_coefficient_change",
       Number([](Config& c) -> double& { return c.analysis.max_coefficient_change; }, 0, 100)},
      {"analysis.noise_margin",
       Number([](Config& c) -> double& { return c.analysis.noise_margin; }, 0, 100)},
      {"analysis.holdout_min_points", Int(&Config::holdout_min_points, 1, 100000)},
      {"analysis.holdout_min_days", Number(&Config::holdout_min_days, 0, 365)},
      {"analysis.vif_max",
       Number([](Config& c) -> double& { return c.analysis.vif_max; }, 1.01, 1e9)},
      {"analysis.max_effects",
       [](const toml::node& n, Config& c) -> std::
                                              string {
                                                auto v = n.value_exact<int64_t>();
                                                if (!v || *v < 0 || *v > 20)
                                                  return "must be an integer within 0..20";
                                                c.analysis.max_effects = static_cast<int>(*v);
                                                return "";
                                              }},
      {"analysis.tau_grid_min",
       [](const toml::node& n,
          Config& c) -> std::
                         string {
                           const toml::array* a = n.as_array();
                           if (!a || a->empty() || a->size() > 32) {
                             return "must be an array of 1 to 32 time constants in minutes";
                           }
                           std::vector<double> grid;
                           for (const auto& item : *a) {
                             std::optional<double> tau =
                                 item.is_integer() ? std::optional<double>(*item.value<int64_t>())
                                                   : item.value_exact<double>();
                             if (!tau || !(*tau >= 0.5 && *tau <= 10080)) {
                               return "time constants in minutes, within 0.5..10080";
                             }
                             grid.push_back(*tau);
                           }
                           c.analysis.tau_grid_min = grid;
                           return "";
                         }},
      {"auth.tokens", ReadTokens},
      {"mtconnect.sources", ReadMtconnectSources},
      {"web.time_zone", TimeZone},
      {"web.dygraphs_dir", Text(&Config::web_dygraphs_dir)},
      {"web.session_hours", Int(&Config::web_session_hours, 1, 24 * 30)},
      {"web.secure_cookie", Bool(&Config::web_secure_cookie)},
      {"web.max_sessions", Int(&Config::web_max_sessions, 1, 100000)},
      {"web.max_sessions_per_token", Int(&Config::web_max_sessions_per_token, 1, 1000)},
      {"log.level", Text(&Config::log_level, {"debug", "info", "warn", "error"})},
      {"dds.enabled", Bool(&Config::dds_enabled)},
      {"dds.domain", Int(&Config::dds_domain, 0, 232)},
      {"dds.config", Text(&Config::dds_config)},
      {"dds.batch_max", Int(&Config::dds_batch_max, 1, 100000)},
      {"dds.batch_max_delay_ms", Int(&Config::dds_batch_max_delay_ms, 1, 10000)},
      {"dds.publish_step_mm", Number(&Config::dds_publish_step_mm, 0, 1)},
      {"dds.publish_every_s", Int(&Config::dds_publish_every_s, 1, 3600)},
  };
  return keys;
}

// The known key nearest to a mistyped one, for the message.
std::string Nearest(const std::string& key) {
  auto distance = [](const std::string& a, const std::string& b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
      size_t diagonal = row[0];
      row[0] = i;
      for (size_t j = 1; j <= b.size(); ++j) {
        const size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
        diagonal = up;
      }
    }
    return row[b.size()];
  };
  std::string best;
  size_t best_d = 4;  // only suggest what is close
  for (const auto& [known, reader] : Keys()) {
    if (size_t d = distance(key, known); d < best_d) best = known, best_d = d;
  }
  return best;
}

}  // namespace

Status ParseListen(const std::string& listen, Config& c) {
  auto colon = listen.rfind(':');
  std::string host = colon == std::string::npos ? c.listen_host : listen.substr(0, colon);
  std::string port = colon == std::string::npos ? listen : listen.substr(colon + 1);
  try {
    size_t used = 0;
    int p = std::stoi(port, &used);
    if (used != port.size() || p < 0 || p > 65535) throw std::out_of_range("port");
    c.listen_port = p;
  } catch (const std::exception&) {
    return Status::InvalidArgument("listen: \"" + listen + "\" is not host:port");
  }
  if (!host.empty()) c.listen_host = host;
  return Status::Ok();
}

StatusOr<Config> LoadConfig(const std::string& path, Config defaults) {
  Config c = std::move(defaults);
  if (path.empty()) return c;
  toml::table t;
  try {
    t = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    return Status::InvalidArgument("config " + path + ": " + std::string(e.description()) +
                                   " at line " + std::to_string(e.source().begin.line));
  }
  // Every key is known and of its type and range, or the start stops
  // naming it: a typo must not silently leave a default in force.
  for (const auto& [section, content] : t) {
    const std::string s(section.str());
    const toml::table* table = content.as_table();
    if (!table) {
      return Status::InvalidArgument(ConfigError(path, "'" + s + "'") +
                                     " must be a [section]; keys belong in one");
    }
    for (const auto& [key, value] : *table) {
      const std::string name = s + "." + std::string(key.str());
      auto it = Keys().find(name);
      if (it == Keys().end()) {
        const std::string near = Nearest(name);
        std::string message = ConfigError(path, "unknown key " + name);
        if (!near.empty()) message += " (did you mean " + near + "?)";
        return Status::InvalidArgument(message);
      }
      if (std::string why = it->second(value, c); !why.empty()) {
        return Status::InvalidArgument(ConfigError(path, name) + " " + why);
      }
    }
  }
  if (!(c.plausible_min_c < c.plausible_max_c)) {
    return Status::InvalidArgument("config " + path +
                                   ": compensation.plausible_min_c must be below plausible_max_c");
  }
  if (!c.centre_url.empty() && c.centre_plant.empty()) {
    return Status::InvalidArgument("config " + path +
                                   ": centre.plant: a line that ships names its plant");
  }
  if (!c.centre_url.empty() && c.read_only) {
    return Status::InvalidArgument(
        "config " + path + ": centre.url: a read-only server ships nothing (server.read_only)");
  }
  return c;
}

bool ValidPlantName(const std::string& plant) {
  return !plant.empty() && plant.size() <= 16 &&
         std::all_of(plant.begin(), plant.end(), [](char ch) {
           return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_' || ch == '-';
         });
}

}  // namespace thermocomp
