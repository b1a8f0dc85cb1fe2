#include "server/command_util.h"

#include <sys/socket.h>
#include <sys/un.h>

#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

#include "core/log.h"
#include "core/version.h"
#include "server/open_app.h"
#include "storage/postgresql/pg_storage.h"

namespace thermocomp::cli {

StatusOr<Args> Parse(const CommandSpec& spec, const std::vector<std::string>& in) {
  Args a;
  for (size_t i = 0; i < in.size(); ++i) {
    if (in[i].rfind("--", 0) != 0) {
      if (a.positional.size() >= spec.max_positional) {
        return Status::InvalidArgument("unexpected argument '" + in[i] + "'");
      }
      a.positional.push_back(in[i]);
      continue;
    }
    std::string key = in[i].substr(2);
    std::optional<std::string> value;
    if (auto eq = key.find('='); eq != std::string::npos) {
      value = key.substr(eq + 1);
      key = key.substr(0, eq);
    }
    const OptionSpec* option = nullptr;
    for (const auto& o : spec.options) {
      if (key == o.name) option = &o;
    }
    if (!option) return Status::InvalidArgument("unknown option --" + key);
    if (option->takes_value && !value) {
      if (i + 1 >= in.size() || in[i + 1].rfind("--", 0) == 0) {
        return Status::InvalidArgument("--" + key + " needs a value");
      }
      value = in[++i];
    } else if (!option->takes_value && value) {
      return Status::InvalidArgument("--" + key + " takes no value");
    }
    if (a.opts.count(key)) return Status::InvalidArgument("--" + key + " given twice");
    a.opts[key] = value.value_or("true");
  }
  return a;
}

int Fail(const std::string& what) {
  std::fprintf(stderr, "thermocomp: %s\n", what.c_str());
  return 1;
}

bool RunningInstalled() {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return false;
  // /bin is /usr/bin on a merged-/usr system: compare the real paths.
  const fs::path installed = fs::weakly_canonical(build::kInstalledBinary, ec);
  return !ec && self == installed;
}

Config DefaultConfig() {
  Config c;
  if (RunningInstalled()) c.db_path = std::string(build::kStateDir) + "/thermocomp.db";
  return c;
}

StatusOr<Config> LoadWithOverrides(const Args& a) {
  auto c = LoadConfig(a.Get("config"), DefaultConfig());
  if (!c.ok()) return c;
  if (a.Has("db")) c->db_path = a.Get("db");
  if (a.Has("listen")) {
    if (Status s = ParseListen(a.Get("listen"), *c); !s.ok()) return s;
  }
  if (a.Has("read-only")) c->read_only = true;
  if (c->read_only && !c->centre_url.empty()) {
    return Status::InvalidArgument("--read-only: a read-only server ships nothing (centre.url)");
  }
  if (a.Has("dds-domain")) c->dds_domain = static_cast<uint32_t>(std::stoul(a.Get("dds-domain")));
  log::SetLevel(c->log_level);
  return c;
}

StatusOr<std::string> DdsConfigFile(const Args& a, const Config& config) {
  namespace fs = std::filesystem;
  const fs::path config_dir =
      a.Has("config") ? fs::absolute(a.Get("config")).parent_path() : fs::path();
  std::vector<fs::path> candidates;
  if (!config.dds_config.empty()) {
    const fs::path configured(config.dds_config);
    candidates.push_back(fs::absolute(configured));
    if (configured.is_relative() && !config_dir.empty()) {
      candidates.push_back(config_dir / configured);
    }
  } else {
    if (!config_dir.empty()) candidates.push_back(config_dir / "cyclonedds.xml");
    candidates.push_back(fs::path(build::kConfigDir) / "cyclonedds.xml");
    candidates.push_back(fs::path(build::kSourceDir) / "deploy" / "cyclonedds.xml");
  }
  std::string looked;
  for (const auto& c : candidates) {
    std::error_code ec;
    if (fs::is_regular_file(c, ec)) return c.lexically_normal().string();
    looked += (looked.empty() ? "" : ", ") + c.string();
  }
  return Status::NotFound((config.dds_config.empty()
                               ? std::string("no Cyclone DDS file")
                               : "dds.config \"" + config.dds_config + "\" not found") +
                          " (looked for " + looked + "; set dds.config or CYCLONEDDS_URI)");
}

Status NotifyServiceManager(const std::string& state) {
  const char* socket_path = std::getenv("NOTIFY_SOCKET");
  if (!socket_path || !*socket_path) return Status::Ok();
  sockaddr_un address{};
  address.sun_family = AF_UNIX;
  const size_t length = std::strlen(socket_path);
  if ((socket_path[0] != '/' && socket_path[0] != '@') || length >= sizeof address.sun_path) {
    return Status::InvalidArgument(std::string("NOTIFY_SOCKET \"") + socket_path +
                                   "\" is not a socket path or @name");
  }
  std::memcpy(address.sun_path, socket_path, length);
  // An abstract socket's name starts with a NUL byte, written '@'.
  if (address.sun_path[0] == '@') address.sun_path[0] = '\0';
  const socklen_t address_length = static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + length);
  const int fd = socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return Status::Unavailable(std::string("notify socket: ") + std::strerror(errno));
  const ssize_t sent = sendto(fd, state.data(), state.size(), MSG_NOSIGNAL,
                              reinterpret_cast<const sockaddr*>(&address), address_length);
  const int error = errno;
  close(fd);
  if (sent != static_cast<ssize_t>(state.size())) {
    return Status::Unavailable(std::string("notify ") + socket_path + ": " + std::strerror(error));
  }
  return Status::Ok();
}

Status PrepareDatabasePath(const Args& a, const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  // A PostgreSQL archive is made by its administrator (docs/operations.md).
  if (IsPostgresqlUrl(path) || fs::exists(path, ec)) return Status::Ok();
  if (!a.Has("create")) {
    return Status::NotFound("database " + path +
                            " does not exist (check the path; --create makes a new one)");
  }
  const fs::path dir = fs::path(path).parent_path();
  if (!dir.empty()) fs::create_directories(dir, ec);
  if (ec) return Status::Unavailable("cannot create " + dir.string() + ": " + ec.message());
  return Status::Ok();
}

StatusOr<std::unique_ptr<App>> OpenApp(const Args& a) {
  static const SystemClock clock;
  auto config = LoadWithOverrides(a);
  if (!config.ok()) return config.status();
  if (Status s = PrepareDatabasePath(a, config->db_path); !s.ok()) return s;
  return OpenApp(*config, clock);
}

std::string ReadFile(const std::string& path, bool& ok) {
  std::ifstream in(path, std::ios::binary);
  ok = static_cast<bool>(in);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string Describe(const IngestResult& r) {
  if (r.status.ok()) {
    return std::to_string(r.accepted) + " accepted, " + std::to_string(r.duplicates) +
           " duplicates";
  }
  std::string s = r.status.message();
  for (size_t i = 0; i < r.errors.size() && i < 5; ++i) {
    s += "\n  item " + std::to_string(r.errors[i].index) + " " + r.errors[i].field + ": " +
         r.errors[i].message;
  }
  return s;
}

std::atomic<bool> g_stop{false};
void OnSignal(int) {
  g_stop = true;
}
std::atomic<bool> g_reload{false};
void OnReload(int) {
  g_reload = true;
}

}  // namespace thermocomp::cli
