#include "server/config.h"

#include <cstdio>

#include <toml++/toml.h>

namespace thermocomp {

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

StatusOr<Config> LoadConfig(const std::string& path) {
  Config c;
  if (path.empty()) return c;
  toml::table t;
  try {
    t = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    return Status::InvalidArgument("config " + path + ": " + std::string(e.description()) +
                                   " at line " + std::to_string(e.source().begin.line));
  }
  if (auto listen = t["server"]["listen"].value<std::string>()) {
    if (Status s = ParseListen(*listen, c); !s.ok()) return s;
  }
  c.http_threads = t["server"]["threads"].value_or(c.http_threads);
  c.max_body_bytes = t["server"]["max_body_bytes"].value_or<int64_t>(c.max_body_bytes);
  c.db_path = t["database"]["path"].value_or(c.db_path);
  c.synchronous = t["database"]["synchronous"].value_or(c.synchronous);
  c.stale_after_s = t["compensation"]["stale_after_s"].value_or(c.stale_after_s);
  c.plausible_min_c = t["compensation"]["plausible_min_c"].value_or(c.plausible_min_c);
  c.plausible_max_c = t["compensation"]["plausible_max_c"].value_or(c.plausible_max_c);
  c.max_step_c = t["compensation"]["max_step_c"].value_or(c.max_step_c);
  c.range_margin = t["compensation"]["range_margin"].value_or(c.range_margin);
  c.refit_interval_min = t["fit"]["interval_min"].value_or(c.refit_interval_min);
  c.refit_after_new_runs = t["fit"]["after_new_runs"].value_or(c.refit_after_new_runs);
  c.holdout_runs = t["fit"]["holdout_runs"].value_or(c.holdout_runs);
  c.gross_error_mm = t["fit"]["gross_error_mm"].value_or(c.gross_error_mm);
  c.selection.p_max = t["fit"]["p_max"].value_or(c.selection.p_max);
  c.selection.vif_max = t["fit"]["vif_max"].value_or(c.selection.vif_max);
  c.selection.outlier_threshold =
      t["fit"]["outlier_threshold"].value_or(c.selection.outlier_threshold);
  c.selection.outliers_per_step =
      t["fit"]["outliers_per_step"].value_or(c.selection.outliers_per_step);
  c.acceptance.min_r2 = t["fit"]["min_r2"].value_or(c.acceptance.min_r2);
  c.acceptance.min_adj_r2 = t["fit"]["min_adj_r2"].value_or(c.acceptance.min_adj_r2);
  c.acceptance.min_observations_per_term =
      t["fit"]["min_observations_per_term"].value_or(c.acceptance.min_observations_per_term);
  if (auto v = t["fit"]["min_validation_r2"].value<double>()) c.acceptance.min_validation_r2 = *v;
  c.log_level = t["log"]["level"].value_or(c.log_level);
  c.check_every_days = t["checks"]["every_days"].value_or(c.check_every_days);
  c.check_due_after_h = t["checks"]["due_after_h"].value_or(c.check_due_after_h);
  c.zero_tolerance_um = t["checks"]["zero_tolerance_um"].value_or(c.zero_tolerance_um);
  if (c.check_every_days < 0 || c.check_due_after_h < 1 || !(c.zero_tolerance_um > 0)) {
    return Status::InvalidArgument(
        "checks: every_days >= 0, due_after_h >= 1 and zero_tolerance_um > 0");
  }
  c.analysis_policy = t["analysis"]["policy"].value_or(c.analysis_policy);
  if (c.analysis_policy != "off" && c.analysis_policy != "propose" &&
      c.analysis_policy != "activate") {
    return Status::InvalidArgument("analysis.policy must be \"off\", \"propose\" or \"activate\"");
  }
  c.analysis.alpha = t["analysis"]["alpha"].value_or(c.analysis.alpha);
  c.analysis.min_cv_gain = t["analysis"]["min_cv_gain"].value_or(c.analysis.min_cv_gain);
  c.analysis.vif_max = t["analysis"]["vif_max"].value_or(c.analysis.vif_max);
  c.analysis.max_effects = t["analysis"]["max_effects"].value_or(c.analysis.max_effects);
  if (auto grid = t["analysis"]["tau_grid_min"].as_array()) {
    c.analysis.tau_grid_min.clear();
    for (const auto& v : *grid) {
      auto tau = v.value<double>();
      if (!tau || !(*tau > 0)) {
        return Status::InvalidArgument("analysis.tau_grid_min: time constants in minutes, > 0");
      }
      c.analysis.tau_grid_min.push_back(*tau);
    }
  }
  if (!(c.analysis.alpha > 0 && c.analysis.alpha < 1) || !(c.analysis.min_cv_gain >= 0) ||
      !(c.analysis.vif_max > 1) || c.analysis.max_effects < 0 || c.analysis.tau_grid_min.empty()) {
    return Status::InvalidArgument(
        "analysis: alpha in (0,1), min_cv_gain >= 0, vif_max > 1, max_effects >= 0 and a "
        "non-empty tau_grid_min");
  }
  if (auto daily = t["fit"]["daily_at"].value<std::string>()) {
    int h = -1, m = -1;
    if (daily->size() != 5 || std::sscanf(daily->c_str(), "%2d:%2d", &h, &m) != 2 || h < 0 ||
        h > 23 || m < 0 || m > 59) {
      return Status::InvalidArgument("fit.daily_at must be \"HH:MM\" (UTC)");
    }
    c.refit_daily_at_min = h * 60 + m;
  }
  if (auto tokens = t["auth"]["tokens"].as_array()) {
    for (const auto& node : *tokens) {
      const toml::table* tt = node.as_table();
      if (!tt) return Status::InvalidArgument("auth.tokens: each entry must be a table");
      AccessToken a;
      a.name = (*tt)["name"].value_or(std::string());
      a.token = (*tt)["token"].value_or(std::string());
      a.role = (*tt)["role"].value_or(std::string());
      a.machine = (*tt)["machine"].value_or(std::string());
      if (a.name.empty() || a.token.size() < 16) {
        return Status::InvalidArgument(
            "auth.tokens: each needs a name and a token of 16 characters or more");
      }
      if (a.role != "machine" && a.role != "reader" && a.role != "maintenance" &&
          a.role != "admin") {
        return Status::InvalidArgument("auth.tokens." + a.name +
                                       ": role must be machine, reader, maintenance or admin");
      }
      if (a.role == "machine" && a.machine.empty()) {
        return Status::InvalidArgument("auth.tokens." + a.name +
                                       ": role machine needs machine = \"...\"");
      }
      c.tokens.push_back(a);
    }
  }
  c.dds_config = t["dds"]["config"].value_or(c.dds_config);
  c.dds_enabled = t["dds"]["enabled"].value_or(c.dds_enabled);
  c.dds_domain = t["dds"]["domain"].value_or(c.dds_domain);
  if (c.dds_domain > 232) return Status::InvalidArgument("dds.domain must be 0..232");
  c.dds_batch_max = t["dds"]["batch_max"].value_or(c.dds_batch_max);
  c.dds_batch_max_delay_ms = t["dds"]["batch_max_delay_ms"].value_or(c.dds_batch_max_delay_ms);
  c.dds_publish_step_mm = t["dds"]["publish_step_mm"].value_or(c.dds_publish_step_mm);
  c.dds_publish_every_s = t["dds"]["publish_every_s"].value_or(c.dds_publish_every_s);
  if (c.dds_batch_max < 1 || c.dds_batch_max_delay_ms < 1 || c.dds_publish_every_s < 1 ||
      !(c.dds_publish_step_mm >= 0)) {
    return Status::InvalidArgument(
        "dds: batch_max, batch_max_delay_ms and publish_every_s must be positive, publish_step_mm "
        ">= 0");
  }

  if (c.http_threads < 1) return Status::InvalidArgument("server.threads must be at least 1");
  if (c.stale_after_s < 1) return Status::InvalidArgument("compensation.stale_after_s must be > 0");
  if (c.holdout_runs < 1) return Status::InvalidArgument("fit.holdout_runs must be at least 1");
  return c;
}

}  // namespace thermocomp
