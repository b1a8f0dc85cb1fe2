// Config: the server's settings, read from a TOML file (toml++) and
// overridden from the command line. Every field has a working default, so
// `thermocomp serve` runs without a file.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/status.h"
#include "model/acceptance.h"
#include "model/effect_search.h"
#include "model/selection.h"

namespace thermocomp {

// A bearer token and what it may do (see api/auth.h for the roles).
struct AccessToken {
  std::string name;  // who, in the audit
  std::string token;
  std::string role;     // machine | reader | maintenance | admin
  std::string machine;  // for role "machine"
};

// One [[mtconnect.sources]]: a machine read from an MTConnect agent
// (docs/mtconnect.md).
struct MtconnectSourceConfig {
  std::string machine;
  std::string url;     // http://host[:port][/prefix] of the agent
  std::string device;  // a device's name or uuid; empty: the agent's only device
  int poll_s = 10;
  int count = 1000;  // observations asked for per /sample
  // A Temperature data item's id -> the machine's sensor it feeds.
  std::map<std::string, std::string> sensors;
};

struct Config {
  // [server]
  std::string listen_host = "127.0.0.1";
  int listen_port = 8080;
  int http_threads = 64;  // workers; each open connection holds one while it is open
  size_t max_body_bytes = 16 * 1024 * 1024;
  int max_connections_per_client = 48;  // beyond: idle ones are closed, else 503
  int header_timeout_s = 10;            // a request head must arrive within this
  int body_timeout_s = 120;             // and its body within this
  int keep_alive_timeout_s = 60;        // an idle keep-alive connection is closed after this
  // A body's deadline is proportional to its size: body_grace_s plus the
  // announced (chunked: received) bytes at body_min_rate_bytes_per_s,
  // never beyond body_timeout_s.
  int body_grace_s = 5;
  int body_min_rate_bytes_per_s = 16384;
  // Requests without a valid credential may hold at most this share of the
  // workers while their bodies arrive; beyond: 503 with Retry-After.
  double anonymous_worker_share = 0.25;
  // Host header names (with or without port) accepted; empty: loopback
  // names only when no tokens are configured, any name with tokens.
  std::vector<std::string> allowed_hosts;
  // A listen address beyond loopback without [[auth.tokens]] stops the
  // start unless this is true (docs/operations.md, Exposure).
  bool allow_network_without_tokens = false;
  // Peers (IP literals) whose X-Forwarded-For names the client: the TLS
  // proxy in front of the server (deploy/nginx/). Empty: the socket's peer.
  std::vector<std::string> trusted_proxies;
  bool access_log = true;  // one log line per request
  // [database]
  // Relative to the working directory. The installed program's default
  // is absolute (/var/lib/thermocomp/thermocomp.db: server/command_util.h).
  std::string db_path = "var/thermocomp.db";
  std::string synchronous = "full";
  int busy_timeout_ms = 5000;  // a write waits this long for another writer, then 503
  // [compensation]
  int stale_after_s = 300;
  double plausible_min_c = -10.0;
  double plausible_max_c = 80.0;
  double max_step_c = 5.0;  // raw minus filtered beyond this: sensor fault
  double range_margin = 0.1;
  // When a served correction stops being valid (data stopped, the model
  // became unusable) the last valid one is held this long, then ramped to 0.
  int hold_s = 600;
  // The served correction moves at most this fast anywhere on the travel,
  // in every state: the ramp to 0, a new model, a step of the inputs.
  double max_rate_um_per_min = 2.0;
  // [ingest] samples dated further than this into the future are refused.
  int max_future_skew_s = 300;
  // [limits] what one machine or request may make the server hold.
  int max_events_per_machine_day = 500;  // more: 429 naming events
  int analysis_max_events = 200;         // the newest events an analysis considers
  int max_sensors_per_machine = 256;
  int max_response_points = 200000;  // points in one temperature history response
  int overview_page_size = 200;      // machines per overview page by default (limit<=1000)
  int probe_cache_points = 20000;    // probe points whose temperatures stay in memory
  // [auth] failed credentials per client address and per credential tried
  int auth_max_failures = 10;
  int auth_failure_window_s = 600;
  // [fit]
  int refit_interval_min = 1440;  // 0: off
  int refit_after_new_runs = 5;   // 0: off
  int holdout_runs = 2;
  double gross_error_mm = 0.1;  // |drift| at or above: chips in the hole, discarded
  SelectionOptions selection;
  AcceptanceRules acceptance;
  // [[auth.tokens]]; none: loopback clients only, without tokens
  std::vector<AccessToken> tokens;
  // [fit] daily_at "HH:MM" UTC; -1: not set
  int refit_daily_at_min = -1;
  // [analysis] after each scheduled refit: "off", "propose" (store the
  // extended model as a candidate) or "activate" (serve it when it passes)
  std::string analysis_policy = "propose";
  EffectSearchOptions analysis;
  // The runs an analysis holds out by default: the newest until they hold
  // this many points and span this many days (a fit keeps fit.holdout_runs).
  int holdout_min_points = 40;
  double holdout_min_days = 1.0;
  // [checks] column checks: a request per machine every `weekly_days`
  // (0: off), due `due_after_h` later; a machine-zero change beyond the
  // tolerance between checks is logged as an event.
  int check_every_days = 7;
  int check_due_after_h = 24;
  double zero_tolerance_um = 10.0;
  // [log]
  // The pages (docs/pages.md): times shown in the plant's zone (IANA
  // name; stored as UTC), the charting library's folder, sign-in sessions.
  std::string web_time_zone = "UTC";
  std::string web_dygraphs_dir = "/usr/share/javascript/dygraphs";
  int web_session_hours = 12;
  bool web_secure_cookie = false;      // true behind an HTTPS proxy
  int web_max_sessions = 1000;         // beyond: the least recently made is signed out
  int web_max_sessions_per_token = 5;  // beyond: that token's oldest session ends

  std::string log_level = "info";
  // [backup] online backups every `backup_every_h` into `backup_dir`
  // (empty: none scheduled), the newest `backup_keep` kept.
  std::string backup_dir;
  int backup_every_h = 24;
  int backup_keep = 7;
  // [retention] raw samples older than `retention_raw_days` (0: kept for
  // ever) are deleted, except those within `retention_keep_around_h`
  // before and after a probe point or a check; hourly rollups, probe
  // points, models and checks are never deleted. The database gives the
  // space back (incremental vacuum) every `retention_every_h`.
  int retention_raw_days = 400;
  int retention_keep_around_h = 48;
  int retention_every_h = 24;
  // [centre] a line server ships what it stores to a central PostgreSQL
  // (docs/architecture.md, "Plant to centre"); empty url: it does not.
  std::string centre_url;
  std::string centre_plant;       // qualifies this line's machine names at the centre
  int centre_batch_rows = 5000;   // rows in one shipped transaction, at most
  int centre_interval_ms = 1000;  // how often the outbox is looked at when it was empty
  // server.read_only: the centre's own server, showing what the plants
  // ship: no writes over any face, no background work, no compensation.
  bool read_only = false;
  // [alerts] what counts as an operator's condition (docs/operations.md,
  // Alerts), and where it is sent (empty: nowhere; JSON POST, retried).
  std::string alert_webhook_url;
  int alert_data_stopped_after_s = 900;  // no sample of a machine for this long
  double alert_model_error_ratio = 2.0;  // recent error beyond this × validated
  // [dds]
  bool dds_enabled = false;
  uint32_t dds_domain = 0;
  // The Cyclone DDS file; empty: looked up where the configuration and the
  // package keep it (server/command_util.h, DdsConfigFile).
  std::string dds_config;
  int dds_batch_max = 1000;
  int dds_batch_max_delay_ms = 20;
  double dds_publish_step_mm = 1e-4;
  int dds_publish_every_s = 60;
  // [[mtconnect.sources]]; none: no agent is read
  std::vector<MtconnectSourceConfig> mtconnect_sources;
};

// Reads `path` over `defaults`; an empty path yields the defaults.
StatusOr<Config> LoadConfig(const std::string& path, Config defaults = {});
// "host:port" or ":port" or "port".
Status ParseListen(const std::string& listen, Config& config);
// centre.plant: what qualifies a line's machine names at the centre
// ("plant.machine"), so it holds no dot.
bool ValidPlantName(const std::string& plant);

}  // namespace thermocomp
