#include "service/operations/operator_gauges.h"

#include <cstdio>
#include <filesystem>
#include <map>
#include <system_error>

#include "core/version.h"
#include "service/operations/alerts.h"

namespace thermocomp {
namespace {

// A label value in the exposition format: backslash, quote and newline escaped.
std::string Escape(const std::string& value) {
  std::string out;
  for (const char c : value) {
    if (c == '\\' || c == '"') out += '\\';
    if (c == '\n') {
      out += "\\n";
      continue;
    }
    out += c;
  }
  return out;
}

std::string GaugeNumber(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.9g", v);
  return text;
}

// One metric family: HELP and TYPE once, then its samples.
class Family {
 public:
  Family(std::string name, const std::string& help) : name_(std::move(name)) {
    text_ = "# HELP " + name_ + " " + help + "\n# TYPE " + name_ + " gauge\n";
  }
  void Add(const std::vector<std::pair<std::string, std::string>>& labels, double value) {
    text_ += name_;
    if (!labels.empty()) {
      text_ += "{";
      for (size_t i = 0; i < labels.size(); ++i) {
        if (i > 0) text_ += ",";
        text_ += labels[i].first + "=\"" + Escape(labels[i].second) + "\"";
      }
      text_ += "}";
    }
    text_ += " " + GaugeNumber(value) + "\n";
  }
  const std::string& text() const { return text_; }

 private:
  std::string name_, text_;
};

// The archive's file and its write-ahead log, as the disk holds them.
uint64_t DatabaseBytes(const std::string& path) {
  uint64_t total = 0;
  for (const std::string& file : {path, path + "-wal"}) {
    std::error_code error;
    const uintmax_t size = std::filesystem::file_size(file, error);
    if (!error) total += size;
  }
  return total;
}

constexpr const char* kModelStatuses[] = {"active", "candidate", "rejected", "retired"};
// The newest analyses per axis counted by outcome; far beyond a decade of
// daily refits.
constexpr int kAnalysesCounted = 10000;

}  // namespace

std::string OperatorGauges(App& app) {
  const std::vector<MachineWatch> watch = ReadWatch(app);
  const int64_t now = app.clock().NowMs();
  Family offset("thermocomp_compensation_offset_millimeters",
                "Correction served now at the axis' reference position (mm, as the controls "
                "take it).");
  Family valid("thermocomp_compensation_valid",
               "1 when the served value is the model's from live, plausible inputs.");
  Family stale("thermocomp_compensation_stale",
               "1 when an input of the axis' model is older than compensation.stale_after_s.");
  Family clamped("thermocomp_compensation_clamped",
                 "1 when the clamp limits the correction somewhere on the travel.");
  Family status("thermocomp_compensation_status",
                "The status word every format carries (1 valid, 2 stale, 4 clamped, 8 holding, "
                "16 ramping).");
  Family input_age("thermocomp_compensation_input_age_seconds",
                   "Age of the oldest input of the axis' model (by sample time or arrival).");
  Family sample_age("thermocomp_last_sample_age_seconds",
                    "Seconds since the newest temperature sample of the machine.");
  Family datum_age("thermocomp_last_datum_age_seconds",
                   "Seconds since the newest datum (k = 0) probe point of the machine.");
  Family sensor_failed("thermocomp_sensor_failed",
                       "1 when compensation reports the sensor's input implausible.");
  Family recent("thermocomp_model_recent_error_micrometers",
                "RMS error of the active model at the probe points of the last 7 days since "
                "it was first served (µm).");
  Family recent_points("thermocomp_model_recent_points",
                       "Probe points the recent error is computed over.");
  Family validated("thermocomp_model_validated_error_micrometers",
                   "Held-out RMSE the active model's report states (µm).");
  for (const MachineWatch& w : watch) {
    if (w.last_sample_ms) {
      sample_age.Add({{"machine", w.name}}, static_cast<double>(now - *w.last_sample_ms) / 1000.0);
    }
    if (w.last_datum_ms) {
      datum_age.Add({{"machine", w.name}}, static_cast<double>(now - *w.last_datum_ms) / 1000.0);
    }
    std::map<std::string, bool> failed;
    for (const auto& sensor : w.sensors) failed[sensor.first] = false;
    if (w.compensation) {
      for (const AxisCompensation& a : w.compensation->axes) {
        const std::vector<std::pair<std::string, std::string>> labels = {{"machine", w.name},
                                                                         {"axis", a.axis}};
        offset.Add(labels, a.offset_mm);
        valid.Add(labels, a.valid ? 1 : 0);
        stale.Add(labels, a.stale ? 1 : 0);
        clamped.Add(labels, a.clamped ? 1 : 0);
        status.Add(labels, a.StatusWord());
        if (a.input_age_s) input_age.Add(labels, *a.input_age_s);
        const std::string sensor = ImplausibleInput(a.reason);
        if (!sensor.empty()) failed[sensor] = true;
      }
    }
    for (const auto& [sensor, bad] : failed) {
      sensor_failed.Add({{"machine", w.name}, {"sensor", sensor}}, bad ? 1 : 0);
    }
    for (const AxisOutcomeSummary& o : w.outcome) {
      const std::vector<std::pair<std::string, std::string>> labels = {{"machine", w.name},
                                                                       {"axis", o.axis}};
      const ModelHealth& h = o.health.judged;
      if (h.recent_rmse_mm) recent.Add(labels, *h.recent_rmse_mm * 1000.0);
      recent_points.Add(labels, static_cast<double>(h.recent_points));
      if (h.validated_rmse_mm) validated.Add(labels, *h.validated_rmse_mm * 1000.0);
    }
  }

  Family versions("thermocomp_model_versions",
                  "Stored model versions per status: the outcomes of the axis' fits.");
  Family analyses("thermocomp_analyses",
                  "Effect analyses per outcome: no_change (nothing proposed) or the status of "
                  "the model version it proposed.");
  {
    const std::unique_ptr<Session> session = app.storage().Open();
    for (const MachineRecord& m : session->machines().List()) {
      for (const AxisRecord& a : m.axes) {
        std::map<std::string, int> by_status;
        std::map<int, std::string> status_of;
        for (const char* s : kModelStatuses) by_status[s] = 0;
        for (const ModelRecord& r : session->models().List(a.id)) {
          ++by_status[r.status];
          status_of[r.version] = r.status;
        }
        for (const auto& [s, n] : by_status) {
          versions.Add({{"machine", m.name}, {"axis", a.name}, {"status", s}}, n);
        }
        std::map<std::string, int> by_outcome;
        by_outcome["no_change"] = 0;
        for (const char* s : kModelStatuses) by_outcome[s] = 0;
        for (const AnalysisRecord& r : session->analyses().List(a.id, kAnalysesCounted)) {
          auto it = r.model_version ? status_of.find(*r.model_version) : status_of.end();
          ++by_outcome[it == status_of.end() ? "no_change" : it->second];
        }
        for (const auto& [s, n] : by_outcome) {
          analyses.Add({{"machine", m.name}, {"axis", a.name}, {"outcome", s}}, n);
        }
      }
    }
  }

  Family active("thermocomp_alerts_active",
                "Conditions active now per kind (GET /api/v1/alerts lists them).");
  std::map<std::string, int> by_kind;
  for (const char* k :
       {kAlertModelGoneBad, kAlertDataStopped, kAlertCheckOverdue, kAlertSensorFailed,
        kAlertCompensationStale, kAlertCompensationInvalid, kAlertSensorToCheck}) {
    by_kind[k] = 0;
  }
  for (const Alert& a : EvaluateAlerts(app, watch)) ++by_kind[a.kind];
  for (const auto& [k, n] : by_kind) active.Add({{"kind", k}}, n);

  Family db("thermocomp_database_size_bytes",
            "Size of the archive on disk: the SQLite file and its write-ahead log.");
  db.Add({}, static_cast<double>(DatabaseBytes(app.storage().location())));
  Family build("thermocomp_build_info", "The running build: version, git description, schema.");
  build.Add({{"version", build::kVersion},
             {"git", build::kGitDescribe},
             {"schema", std::to_string(app.storage().schema_version())}},
            1);

  std::string out;
  for (const Family* f : {&offset, &valid, &stale, &clamped, &status, &input_age, &sample_age,
                          &datum_age, &sensor_failed, &recent, &recent_points, &validated,
                          &versions, &analyses, &active, &db, &build}) {
    out += f->text();
  }
  out += app.mtconnect_board().Gauges();  // empty without MTConnect sources
  return out;
}

}  // namespace thermocomp
