#include "service/operations/backup_schedule.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <ctime>
#include <filesystem>
#include <utility>

#include "core/log.h"
#include "core/time_units.h"

namespace thermocomp {
namespace {

constexpr const char* kPrefix = "thermocomp-";
constexpr const char* kSuffix = "Z.db";

// A value for a logfmt field: quoted, its own quotes escaped.
std::string QuotedPath(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c == '\n' ? ' ' : c;
  }
  return out + "\"";
}

}  // namespace

BackupSchedule::BackupSchedule(Storage& storage, const Clock& clock, Options options)
    : storage_(storage), clock_(clock), options_(std::move(options)) {}

BackupSchedule::~BackupSchedule() {
  Stop();
}

std::string BackupSchedule::FileName(int64_t unix_ms) {
  const time_t t = static_cast<time_t>(unix_ms / 1000);
  tm utc{};
  gmtime_r(&t, &utc);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y%m%dT%H%M%S", &utc);
  return std::string(kPrefix) + buf + kSuffix;
}

std::optional<int64_t> BackupSchedule::TimeOfName(const std::string& name) {
  // thermocomp-YYYYMMDDTHHMMSSZ.db, exactly.
  const std::string prefix = kPrefix;
  const std::string suffix = kSuffix;
  if (name.size() != prefix.size() + 15 + suffix.size() || name.rfind(prefix, 0) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
    return std::nullopt;
  }
  const std::string stamp = name.substr(prefix.size(), 15);
  for (size_t i = 0; i < stamp.size(); ++i) {
    const bool ok = i == 8 ? stamp[i] == 'T' : std::isdigit(static_cast<unsigned char>(stamp[i]));
    if (!ok) return std::nullopt;
  }
  tm utc{};
  if (!strptime(stamp.c_str(), "%Y%m%dT%H%M%S", &utc)) return std::nullopt;
  // Only a name this schedule could have written (no 20261399T…).
  const int64_t seconds = timegm(&utc);
  if (FileName(seconds * 1000) != name) return std::nullopt;
  return seconds;
}

std::vector<std::string> BackupSchedule::OwnFiles() const {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(options_.dir, ec)) {
    const std::string name = entry.path().filename().string();
    // Regular files only (not following a link): a link or a directory of
    // that name is someone else's.
    if (!TimeOfName(name) || !entry.is_regular_file(ec) || entry.is_symlink(ec)) continue;
    names.push_back(name);
  }
  std::sort(names.begin(), names.end());  // the names sort as their times
  return names;
}

bool BackupSchedule::Due() const {
  const int64_t now = clock_.NowMs();
  if (last_failure_ms_ != 0 && now - last_failure_ms_ < options_.retry_after_ms) return false;
  std::optional<int64_t> last = last_backup_ms_;
  if (!last) {
    const std::vector<std::string> own = OwnFiles();
    if (!own.empty()) last = *TimeOfName(own.back()) * 1000;
  }
  return !last || now - *last >= options_.every_h * kHourMs;
}

Status BackupSchedule::Tick() {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!Due()) return Status::Ok();
  const int64_t now = clock_.NowMs();
  const std::string path = options_.dir + "/" + FileName(now);
  const int64_t started = clock_.MonotonicMs();
  Status s = storage_.Backup(path, /*replace=*/false);
  if (!s.ok()) {
    last_failure_ms_ = now;
    log::Error("backup failed",
               "file=" + QuotedPath(path) + " error=" + QuotedPath(s.message()) +
                   " retry_in_s=" + std::to_string(options_.retry_after_ms / 1000));
    return s;
  }
  last_failure_ms_ = 0;
  last_backup_ms_ = now;
  struct stat st {};
  const int64_t bytes = stat(path.c_str(), &st) == 0 ? st.st_size : -1;
  log::Info("backup written", "file=" + QuotedPath(path) + " bytes=" + std::to_string(bytes) +
                                  " ms=" + std::to_string(clock_.MonotonicMs() - started));
  return Rotate();
}

Status BackupSchedule::Rotate() {
  const std::vector<std::string> own = OwnFiles();
  const size_t keep = static_cast<size_t>(std::max(options_.keep, 1));
  Status result = Status::Ok();
  for (size_t i = 0; i + keep < own.size(); ++i) {
    const std::filesystem::path old = std::filesystem::path(options_.dir) / own[i];
    std::error_code ec;
    if (std::filesystem::remove(old, ec)) {
      log::Info("backup deleted",
                "file=" + QuotedPath(old.string()) + " keep=" + std::to_string(options_.keep));
    } else if (ec) {
      log::Error("backup not deleted",
                 "file=" + QuotedPath(old.string()) + " error=" + QuotedPath(ec.message()));
      result = Status::Unavailable("cannot delete " + old.string() + ": " + ec.message());
    }
  }
  return result;
}

void BackupSchedule::Start(std::chrono::milliseconds poll) {
  if (task_.running()) return;
  log::Info("backups scheduled", "dir=" + QuotedPath(options_.dir) +
                                     " every_h=" + std::to_string(options_.every_h) +
                                     " keep=" + std::to_string(options_.keep));
  task_.Start(poll, [this] { (void)Tick(); });  // logged there; the server goes on either way
}

void BackupSchedule::Stop() {
  task_.Stop();
}

}  // namespace thermocomp
